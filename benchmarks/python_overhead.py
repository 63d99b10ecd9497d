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
alternate C++ and the Python variants, each run several times a round:
  python (Keyframe objects)      add_keyframe on Keyframes read from the
                                 log (the call alone);
  python (add_keyframe_arrays)   Backend.add_keyframe_arrays on the
                                 keyframe's NumPy arrays (hypotheses
                                 stacked (H, 7), counts, class names, ids,
                                 points): what a Python front end does,
                                 one call per keyframe;
  python (Keyframe.from_arrays)  the same arrays through
                                 Keyframe.from_arrays, then add_keyframe
                                 (two calls);
  python (Detection objects)     one Detection per (30, 7) array, then a
                                 Keyframe, then add_keyframe (the path
                                 before from_arrays: seven calls).
The second C++ row times a copy of each KeyframeInput plus AddKeyframe on
the copy: the least a C++ front end that builds its keyframes pays, for
reference; the ratios are against the first, AddKeyframe alone.
Each side is warmed up first (C++: an untimed first run in each process;
Python: one untimed run of each variant at the start). Times are the
thread's CPU time (insensitive to other load on the machine; Ceres runs in
the calling thread with num_threads = 1) and wall time; medians over the
repetitions.
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import symba


def cpp_times(binary, log, runs, copy=False):
    """`runs` runs in one process after one warm-up run (page faults, the
    allocator's arenas), as Python's runs follow its warm-up; with `copy`,
    AddKeyframe on a copy of the keyframe, the copy timed too."""
    out = subprocess.run([binary, "--time", log, "--repetitions",
                          str(runs + 1)] + (["--copy"] if copy else []),
                         check=True, capture_output=True, text=True).stdout
    times = []
    for line in out.splitlines()[1:]:
        fields = line.split()
        times.append((float(fields[3]), float(fields[1])))  # cpu, wall
    return times


def as_arrays(keyframe):
    """What a Python front end would hold for one keyframe: one (30, 7)
    array per detection."""
    return (keyframe.id, keyframe.timestamp, keyframe.T_wc,
            [(d.class_name, d.hypotheses, d.id) for d in keyframe.detections],
            keyframe.point_ids, keyframe.point_uv, keyframe.point_depth)


def as_stacked(keyframe):
    """The same with the hypotheses stacked: add_keyframe_arrays's
    arguments."""
    detections = keyframe.detections
    return (keyframe.id, keyframe.timestamp, dict(
        T_wc=keyframe.T_wc,
        hypotheses=np.concatenate([d.hypotheses for d in detections]),
        counts=np.array([len(d.weights) for d in detections],
                        dtype=np.int64),
        class_names=[d.class_name for d in detections],
        detection_ids=[d.id for d in detections],
        point_ids=keyframe.point_ids, point_uv=keyframe.point_uv,
        point_depth=keyframe.point_depth))


def build(arrays):
    kid, t, T_wc, detections, ids, uv, depth = arrays
    return symba.Keyframe(
        kid, t, T_wc=T_wc,
        detections=[symba.Detection(c, h, id=i) for c, h, i in detections],
        point_ids=ids, point_uv=uv, point_depth=depth)


def add_objects(backend, keyframe):
    backend.add_keyframe(keyframe)


def add_detections(backend, arrays):
    backend.add_keyframe(build(arrays))


def add_arrays(backend, stacked):
    kid, t, kwargs = stacked
    backend.add_keyframe_arrays(kid, t, **kwargs)


def add_from_arrays(backend, stacked):
    kid, t, kwargs = stacked
    backend.add_keyframe(symba.Keyframe.from_arrays(kid, t, **kwargs))


def python_times(header, items, warmup, add):
    backend = symba.Backend(intrinsics=header.camera)
    cpu = wall = 0.0
    for k, item in enumerate(items):
        wall_start = time.perf_counter()
        cpu_start = time.thread_time()
        add(backend, item)
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

    load_start = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        log = str(pathlib.Path(tmp) / "backend_bench.jsonl")
        subprocess.run([binary, "--write-log", log], check=True)
        header, keyframes = symba.read_log(log)
        arrays = [as_arrays(k) for k in keyframes]
        stacked = [as_stacked(k) for k in keyframes]
        warmup = 10
        timed = len(keyframes) - warmup

        variants = {
            "python (Keyframe objects)": (keyframes, add_objects),
            "python (add_keyframe_arrays)": (stacked, add_arrays),
            "python (Keyframe.from_arrays)": (stacked, add_from_arrays),
            "python (Detection objects)": (arrays, add_detections),
        }
        results = {"c++": [], "c++ (copy the keyframe, then add it)": []}
        results.update((name, []) for name in variants)
        poses = []
        for items, add in variants.values():  # warm-up
            python_times(header, items, warmup, add)
        for _ in range(args.rounds):
            results["c++"] += cpp_times(binary, log, args.runs)
            results["c++ (copy the keyframe, then add it)"] += cpp_times(
                binary, log, args.runs, copy=True)
            for _ in range(args.runs):
                for name, (items, add) in variants.items():
                    t, p = python_times(header, items, warmup, add)
                    results[name].append(t)
                    poses.append(p)
        for p in poses[1:]:
            if not np.array_equal(p, poses[0]):
                sys.exit("the Python variants disagree on the trajectory")

    base_cpu = statistics.median(c for c, _ in results["c++"])
    base_wall = statistics.median(w for _, w in results["c++"])
    print(f"{timed} timed keyframes; {args.rounds} rounds of {args.runs} "
          f"runs per variant; medians over the runs; ms per keyframe; "
          f"load average {load_start:.1f} at the start, "
          f"{os.getloadavg()[0]:.1f} at the end")
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
