#!/usr/bin/env python3
"""What loop closures cost and give on the long simulated scene
(docs/loop-closure.md, "Measured"): `symba simulate --scene long`, replayed
keyframe by keyframe with a window solve after each, three times: without
loop closures (`detect_loops` off), with the loops symba finds from the
objects (the default), and with a host that recognises places perfectly
(objects' loops off): at keyframe k it closes a loop to the earliest (or,
with --to latest, the latest) keyframe j < k - gap whose true camera
position is within `radius` of k's, with the true relative pose (sigma 2 cm
/ 0.01 rad), at most one closure every `every` keyframes. Prints the
keyframe position RMSE, the map objects, and the loop closures' times. Not
a test.

    PYTHONPATH=build/python python3 benchmarks/loop_closure_cost.py \
        [--build build] [--keyframes 3000] [--seed 7]
"""

import argparse
import pathlib
import subprocess
import tempfile
import time

import numpy as np


def quaternion_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_tum(path):
    poses = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(x) for x in line.split()]
        T = np.eye(4)
        T[:3, :3] = quaternion_matrix(v[4:8])
        T[:3, 3] = v[1:4]
        poses.append(T)
    return poses


def host_closures(truth, gap, radius, every, latest):
    positions = np.array([T[:3, 3] for T in truth])
    closures = {}
    last = -every
    for k in range(len(truth)):
        if k - last < every or k < gap:
            continue
        near = np.nonzero(np.linalg.norm(positions[:k - gap] - positions[k],
                                         axis=1) < radius)[0]
        if len(near) == 0:
            continue
        j = int(near[-1] if latest else near[0])
        closures[k] = (j, np.linalg.inv(truth[j]) @ truth[k])
        last = k
    return closures


def replay(symba, header, keyframes, truth, closures, detect_loops):
    backend = symba.Backend(symba.BackendOptions(detect_loops=detect_loops),
                            intrinsics=header.camera,
                            class_priors=header.classes)
    times = []
    for k, keyframe in enumerate(keyframes):
        if k in closures:
            j, T = closures[k]
            keyframe.loop_closures = [symba.LoopClosure(
                keyframes[j].id, T, 0.02, 0.01)]
        start = time.perf_counter()
        backend.add_keyframe(keyframe)
        backend.optimize_window()
        times.append(time.perf_counter() - start)
    estimated = backend.keyframes().poses[:, :3]
    expected = np.array([T[:3, 3] for T in truth])
    rmse = float(np.sqrt(np.mean(np.sum((estimated - expected) ** 2, 1))))
    return backend, rmse, np.array(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--keyframes", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--gap", type=int, default=300)
    parser.add_argument("--radius", type=float, default=0.5)
    parser.add_argument("--every", type=int, default=100)
    parser.add_argument("--runs", default="none,objects,host",
                        help="which of the three runs, comma-separated")
    parser.add_argument("--to", choices=["earliest", "latest"],
                        default="earliest",
                        help="close to the earliest or the latest earlier "
                        "visit")
    args = parser.parse_args()
    import symba
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "long"
        subprocess.run([str(pathlib.Path(args.build) / "bin" / "symba"),
                        "simulate", "--scene", "long", "--keyframes",
                        str(args.keyframes), "--seed", str(args.seed),
                        "--out", str(out)], check=True)
        header, keyframes = symba.read_log(str(out / "log.jsonl"))
        truth = read_tum(out / "gt_trajectory.tum")
    closures = host_closures(truth, args.gap, args.radius, args.every,
                             args.to == "latest")
    runs = {"none": ("no loop closures", {}, False),
            "objects": ("loops from the objects", {}, True),
            "host": ("host loop closures", closures, False)}
    for run in args.runs.split(","):
        name, given, detect = runs[run]
        backend, rmse, times = replay(symba, header, keyframes, truth, given,
                                      detect)
        reports = [r for r in backend.loop_closures() if not r.waiting]
        seconds = np.array([r.seconds for r in reports]) if reports else None
        closing = set(given) | {
            k for k, keyframe in enumerate(keyframes)
            if any(r.keyframe == keyframe.id for r in reports)}
        ordinary = np.array([t for k, t in enumerate(times)
                             if k not in closing])
        line = (f"{name}: keyframe RMSE {rmse:.3f} m, "
                f"{len(backend.objects())} map objects, "
                f"ms per keyframe {1e3 * ordinary.mean():.2f} "
                f"(last 1000 {1e3 * ordinary[-1000:].mean():.2f})")
        if seconds is not None:
            merged = sum(p.merged for r in reports for p in r.objects)
            line += (f", {len(reports)} loop closures "
                     f"({sum(r.from_objects for r in reports)} from objects, "
                     f"{merged} objects merged): median "
                     f"{np.median(seconds):.3f} s, max {seconds.max():.3f} s, "
                     f"keyframe moved median "
                     f"{np.median([r.correction_m for r in reports]):.3f} m")
        print(line, flush=True)


if __name__ == "__main__":
    main()
