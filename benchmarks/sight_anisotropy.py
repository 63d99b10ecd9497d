#!/usr/bin/env python3
"""How much wider DOPE's position errors are along its lines of sight than
across them, as symba's kappa measures it (docs/backend.md "Real
detectors", mechanism 8): for each object of each YCB-Video sequence in
data/real/ycbv, its detections at the keyframes (every 5th frame) placed
with the front end's chain, each against the running mean of those before
it, split into the part along the detection's line of sight and the rest;
kappa = (median |along| / 0.674) / (median |across| / 1.177). An
approximation of the backend's samples (which start at confirmation and
keep the last noise_window); no symba code runs here.

    python3 benchmarks/sight_anisotropy.py [--data data/real/ycbv]
"""

import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from front_end_drift_fit import KEYFRAME_STRIDE, MIN_DETECTION_DISTANCE_M, read_poses  # noqa: E402

CHI1_MEDIAN = 0.6744898
CHI2_MEDIAN = 1.1774100


def object_kappa(cameras, detections, times):
    total = np.zeros(3)
    count = 0
    along, across = [], []
    for (R, t), time in zip(cameras, times):
        if time not in detections:
            continue
        t_co = detections[time][1]
        if np.linalg.norm(t_co) <= MIN_DETECTION_DISTANCE_M:
            continue
        p = R @ t_co + t
        if count > 0:
            e = p - total / count
            u = R @ t_co / np.linalg.norm(t_co)
            a = e @ u
            along.append(abs(a))
            across.append(np.linalg.norm(e - a * u))
        total += p
        count += 1
    return (np.median(along) / CHI1_MEDIAN) / (np.median(across) / CHI2_MEDIAN)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default="data/real/ycbv")
    args = parser.parse_args()
    kappas = []
    for folder in sorted(pathlib.Path(args.data).iterdir()):
        if not (folder / "orbslam3_T_wc.txt").exists():
            continue
        front_end = read_poses(folder / "orbslam3_T_wc.txt")
        times = sorted(front_end)[::KEYFRAME_STRIDE]
        cameras = [front_end[t] for t in times]
        for path in sorted(folder.glob("dope_*_T_co.txt")):
            kappa = object_kappa(cameras, read_poses(path), times)
            kappas.append(kappa)
            print(f"{folder.name} {path.name[5:-9]:22s} kappa {kappa:.2f}")
    print(f"range {min(kappas):.2f} - {max(kappas):.2f} over {len(kappas)} objects")


if __name__ == "__main__":
    main()
