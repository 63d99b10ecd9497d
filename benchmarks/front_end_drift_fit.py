#!/usr/bin/env python3
"""Can the objects tell a drifting front end from an accurate one over a
whole run? (docs/backend.md, "A drift model of the front end"). For each
YCB-Video sequence in data/real/ycbv, as it is and with the drifting front
end of symba-real-bench (benchmarks/front_end_drift.h: each keyframe step
scaled by 1.10 and turned about the camera's y axis by 20 degrees per metre),
a model of systematic drift is fitted to DOPE's detections: every keyframe
step (R, t) of the front end is corrected to

    (Exp(w |t|) R, Exp(w |t|) s t)

(w: rotation per metre travelled, rad/m, about the camera's y axis or all
three axes; s: a scale, optional), the keyframes are chained again from the
ground truth's first pose, and w, s are those that make each object's
detections, put in the world with that chain, lie closest to their
component-wise median (Huber loss, 0.1 m; Gauss-Newton with the medians
re-taken at every step). Prints, per sequence and regime, the fitted drift,
how much of the detections' spread it explains (the cost's drop from w = 0,
s = 1), and the keyframe position RMSE of the corrected chain over the front
end's. With --causal, the same fit every 50 keyframes over the detections so
far: how early a run could tell. Not a test; no symba code runs here, only
the data.

    python3 benchmarks/front_end_drift_fit.py [--axes y|xyz] [--scale] [--causal]
"""

import argparse
import pathlib

import numpy as np

KEYFRAME_STRIDE = 5  # symba-real-bench's import stride
DRIFT_YAW_PER_METRE = np.radians(20.0)
DRIFT_SCALE = 1.10
HUBER_M = 0.1
MIN_DETECTION_DISTANCE_M = 0.05  # DOPE's "lost" reports sit at the camera


def quaternion_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_poses(path):
    """time -> (R, t) from a file of 'time tx ty tz qx qy qz qw' lines."""
    poses = {}
    for line in open(path):
        v = line.split()
        if len(v) < 8:
            continue
        q = np.array([float(a) for a in v[4:8]])
        if not np.all(np.isfinite(q)) or np.linalg.norm(q) == 0.0:
            continue
        poses[round(float(v[0]), 3)] = (quaternion_matrix(q),
                                        np.array([float(a) for a in v[1:4]]))
    return poses


def rotation_vector_matrix(w):
    angle = np.linalg.norm(w)
    if angle < 1e-12:
        return np.eye(3)
    k = w / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def steps_of(poses):
    return [(Ra.T @ Rb, Ra.T @ (tb - ta))
            for (Ra, ta), (Rb, tb) in zip(poses[:-1], poses[1:])]


def chain(steps, first):
    poses = [first]
    for R, t in steps:
        Rp, tp = poses[-1]
        poses.append((Rp @ R, Rp @ t + tp))
    return poses


def drifted(steps):
    """symba-real-bench's drifting front end (front_end_drift.h)."""
    out = []
    for R, t in steps:
        E = rotation_vector_matrix(
            np.array([0.0, DRIFT_YAW_PER_METRE * np.linalg.norm(t), 0.0]))
        out.append((E @ R, E @ (DRIFT_SCALE * t)))
    return out


def corrected(steps, drift):
    """drift = (w_x, w_y, w_z [rad/m], log s)."""
    out = []
    for R, t in steps:
        E = rotation_vector_matrix(drift[:3] * np.linalg.norm(t))
        out.append((E @ R, E @ (np.exp(drift[3]) * t)))
    return out


def huber_cost(residuals):
    n = np.linalg.norm(residuals, axis=1)
    return np.sum(np.where(n < HUBER_M, n * n, 2 * HUBER_M * n - HUBER_M**2))


class Sequence:

    def __init__(self, folder):
        front_end = read_poses(folder / "orbslam3_T_wc.txt")
        truth = read_poses(folder / "gt_T_wc.txt")
        self.times = sorted(front_end)[::KEYFRAME_STRIDE]
        self.truth = [truth[t] for t in self.times]
        self.steps = steps_of([front_end[t] for t in self.times])
        self.detections = []  # (keyframe, object, t_co)
        for obj, path in enumerate(sorted(folder.glob("dope_*_T_co.txt"))):
            poses = read_poses(path)
            for k, t in enumerate(self.times):
                if t in poses and np.linalg.norm(
                        poses[t][1]) > MIN_DETECTION_DISTANCE_M:
                    self.detections.append((k, obj, poses[t][1]))

    def position_rmse(self, steps):
        poses = chain(steps, self.truth[0])
        return np.sqrt(
            np.mean([
                np.sum((p[1] - g[1])**2) for p, g in zip(poses, self.truth)
            ]))

    def residuals(self, steps, drift, keyframes):
        poses = chain(corrected(steps[:keyframes], drift), self.truth[0])
        used = [d for d in self.detections if d[0] <= keyframes]
        world = np.array([poses[k][0] @ p + poses[k][1] for k, _, p in used])
        objects = np.array([o for _, o, _ in used])
        out = np.empty_like(world)
        for o in set(objects):
            out[objects == o] = world[objects == o] - np.median(
                world[objects == o], axis=0)
        return out

    def fit(self, steps, free, keyframes, start):
        """Gauss-Newton on the free drift parameters (iteratively reweighted
        for the Huber loss); returns the drift and the cost's drop."""
        drift = start.copy()
        if sum(1 for d in self.detections if d[0] <= keyframes) < 20:
            return drift, 0.0
        for _ in range(10):
            r0 = self.residuals(steps, drift, keyframes)
            cost0 = huber_cost(r0)
            norms = np.linalg.norm(r0, axis=1)
            weights = np.repeat(
                np.sqrt(np.where(norms < HUBER_M, 1.0,
                                 HUBER_M / np.maximum(norms, 1e-9))), 3)
            columns = []
            for j in free:
                moved = drift.copy()
                moved[j] += 1e-5
                columns.append(
                    ((self.residuals(steps, moved, keyframes) - r0) /
                     1e-5).reshape(-1))
            J = np.array(columns).T * weights[:, None]
            step = -np.linalg.lstsq(J, r0.reshape(-1) * weights,
                                    rcond=None)[0]
            candidate = drift.copy()
            candidate[free] += step
            if huber_cost(self.residuals(steps, candidate,
                                         keyframes)) >= cost0:
                break
            drift = candidate
        none = huber_cost(self.residuals(steps, np.zeros(4), keyframes))
        fitted = huber_cost(self.residuals(steps, drift, keyframes))
        return drift, (1.0 - fitted / none) if none > 0 else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default="data/real/ycbv")
    parser.add_argument("--axes", choices=["y", "xyz"], default="y")
    parser.add_argument("--scale", action="store_true",
                        help="fit the scale too")
    parser.add_argument("--causal", action="store_true",
                        help="also fit every 50 keyframes, causally")
    args = parser.parse_args()
    free = ([1] if args.axes == "y" else [0, 1, 2]) + ([3] if args.scale
                                                        else [])
    print("sequence regime | w [deg/m] scale | spread explained | "
          "corrected / front-end position RMSE")
    for folder in sorted(pathlib.Path(args.data).iterdir()):
        if not (folder / "orbslam3_T_wc.txt").exists():
            continue
        seq = Sequence(folder)
        for regime, steps in (("as is", seq.steps),
                              ("drifting", drifted(seq.steps))):
            drift, drop = seq.fit(steps, free, len(steps), np.zeros(4))
            ratio = (seq.position_rmse(corrected(steps, drift)) /
                     seq.position_rmse(steps))
            w = np.degrees(drift[:3])
            print(f"{folder.name} {regime:8s} | "
                  f"{w[0]:6.1f} {w[1]:6.1f} {w[2]:6.1f} "
                  f"{np.exp(drift[3]):5.3f} | {100 * drop:5.1f} % | "
                  f"{ratio:6.3f}")
            if args.causal:
                travelled = np.cumsum([np.linalg.norm(t) for _, t in steps])
                drift = np.zeros(4)
                cells = []
                for k in range(25, len(steps), 50):
                    drift, drop = seq.fit(steps, free, k, drift)
                    cells.append(f"{travelled[k - 1]:.1f} m: "
                                 f"{np.degrees(drift[1]):.0f} deg/m "
                                 f"{100 * drop:.0f} %")
                print("    causal (y rate, spread explained): " +
                      ", ".join(cells))


if __name__ == "__main__":
    main()
