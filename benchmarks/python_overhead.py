#!/usr/bin/env python3
"""The overhead of Backend.add_keyframe through Python against AddKeyframe
in C++, on the backend benchmark's keyframes (benchmarks/backend_bench.cc):
40 keyframes, each with 5 detections of 30 hypotheses and 100 points; the
first 10 fill the window untimed, AddKeyframe is timed on the other 30
(every keyframe is followed by an untimed optimize_window, as in the
benchmark). Not a test: it prints numbers for docs/performance.md.

    PYTHONPATH=build/python python3 benchmarks/python_overhead.py \
        [--build build] [--rounds 5] [--runs 5]

symba-python-overhead-bench writes the keyframes as a log, which Python
reads (bit for bit the same input), and times the C++ side. Rounds
alternate C++ and the two Python variants, each run several times a round:
  python (Keyframe objects)   add_keyframe on Keyframes read from the log;
  python (from NumPy arrays)  building each Keyframe from NumPy arrays
                              (what a Python front end does) plus
                              add_keyframe.
Each side is warmed up first (C++: an untimed first run in each process;
Python: one untimed run at the start). Times are the thread's CPU time (insensitive to other load on the machine;
Ceres runs in the calling thread with num_threads = 1) and wall time;
medians over the repetitions.
"""

import argparse
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import symba


def cpp_times(binary, log, runs):
    """`runs` runs in one process after one warm-up run (page faults, the
    allocator's arenas), as Python's runs follow its warm-up."""
    out = subprocess.run([binary, "--time", log, "--repetitions",
                          str(runs + 1)],
                         check=True, capture_output=True, text=True).stdout
    times = []
    for line in out.splitlines()[1:]:
        fields = line.split()
        times.append((float(fields[3]), float(fields[1])))  # cpu, wall
    return times


def as_arrays(keyframe):
    """What a Python front end would hold for one keyframe."""
    return (keyframe.id, keyframe.timestamp, keyframe.T_wc,
            [(d.class_name, d.hypotheses, d.id) for d in keyframe.detections],
            keyframe.point_ids, keyframe.point_uv, keyframe.point_depth)


def build(arrays):
    kid, t, T_wc, detections, ids, uv, depth = arrays
    return symba.Keyframe(
        kid, t, T_wc=T_wc,
        detections=[symba.Detection(c, h, id=i) for c, h, i in detections],
        point_ids=ids, point_uv=uv, point_depth=depth)


def python_times(header, keyframes, warmup, from_arrays):
    backend = symba.Backend(intrinsics=header.camera)
    cpu = wall = 0.0
    for k, item in enumerate(keyframes):
        wall_start = time.perf_counter()
        cpu_start = time.thread_time()
        backend.add_keyframe(build(item) if from_arrays else item)
        cpu_end = time.thread_time()
        wall_end = time.perf_counter()
        backend.optimize_window()
        if k >= warmup:
            cpu += cpu_end - cpu_start
            wall += wall_end - wall_start
    return (cpu, wall), backend.keyframes().poses


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--rounds", type=int, default=5,
                        help="rounds alternating C++ and Python")
    parser.add_argument("--runs", type=int, default=5,
                        help="runs of each variant per round")
    args = parser.parse_args()
    binary = str(pathlib.Path(args.build) / "bin" /
                 "symba-python-overhead-bench")

    with tempfile.TemporaryDirectory() as tmp:
        log = str(pathlib.Path(tmp) / "backend_bench.jsonl")
        subprocess.run([binary, "--write-log", log], check=True)
        header, keyframes = symba.read_log(log)
        arrays = [as_arrays(k) for k in keyframes]
        warmup = 10
        timed = len(keyframes) - warmup

        results = {"c++": [], "python (Keyframe objects)": [],
                   "python (from NumPy arrays)": []}
        poses = []
        python_times(header, keyframes, warmup, False)  # warm-up
        for _ in range(args.rounds):
            results["c++"] += cpp_times(binary, log, args.runs)
            for _ in range(args.runs):
                t, p = python_times(header, keyframes, warmup, False)
                results["python (Keyframe objects)"].append(t)
                poses.append(p)
                t, p = python_times(header, arrays, warmup, True)
                results["python (from NumPy arrays)"].append(t)
                poses.append(p)
        for p in poses[1:]:
            if not np.array_equal(p, poses[0]):
                sys.exit("the Python variants disagree on the trajectory")

    base_cpu = statistics.median(c for c, _ in results["c++"])
    base_wall = statistics.median(w for _, w in results["c++"])
    print(f"{timed} timed keyframes; {args.rounds} rounds of {args.runs} "
          f"runs per variant; medians over the runs; ms per keyframe")
    print(f"| variant | CPU ms | CPU vs C++ | wall ms | wall vs C++ |")
    print(f"|---|---:|---:|---:|---:|")
    for name, values in results.items():
        cpu = statistics.median(c for c, _ in values)
        wall = statistics.median(w for _, w in values)
        print(f"| {name} | {1e3 * cpu / timed:.3f} | "
              f"{100 * (cpu / base_cpu - 1):+.1f} % | "
              f"{1e3 * wall / timed:.3f} | "
              f"{100 * (wall / base_wall - 1):+.1f} % |")


if __name__ == "__main__":
    main()
