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
reads (bit for bit the same input), and times the C++ side in one process
(--serve) that runs one repetition when asked: every run of the script's
rounds x runs times each C++ variant once, then each Python variant once,
so that C++ and Python alternate run by run. The variants:
  add_keyframe(keyframe)        add_keyframe on Keyframes read from the
                                log (the call alone);
  add_keyframe_arrays(...)      Backend.add_keyframe_arrays on the
                                keyframe's NumPy arrays (hypotheses
                                stacked (H, 7), counts, class names, ids,
                                points): what a Python front end does,
                                one call per keyframe;
  Keyframe.from_arrays(...)     the same arrays through
                                Keyframe.from_arrays, then add_keyframe
                                (two calls);
  a Detection per array         one Detection per (30, 7) array, then a
                                Keyframe, then add_keyframe (the path
                                before from_arrays: seven calls).
The timed statement is the user's call itself, on local variables, with
keyword arguments spelled out (no wrapper function, no **kwargs).
The second C++ row times a copy of each KeyframeInput plus AddKeyframe on
the copy: the least a C++ front end that builds its keyframes pays, for
reference; the ratios are against the first, AddKeyframe alone. The rows
"the clock reads alone" time nothing (the add follows, untimed): the floor
each side's timer puts under its rows.
Each side is warmed up first (one untimed run of each variant). Times are
the thread's CPU time (less sensitive to other load on the machine; Ceres
runs in the calling thread with num_threads = 1) and wall time; medians
over the runs, and "paired": the median over the runs of each run's CPU
time over the C++ AddKeyframe run just before it (insensitive to load that
drifts over the script's minutes).
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


class Cpp:
    """symba-python-overhead-bench --serve: one C++ process for the whole
    run, asked for one repetition at a time, so that C++ and Python
    alternate run by run. Kinds: "add" (AddKeyframe), "copy" (a copy of
    the keyframe and AddKeyframe on it, the copy timed too), "empty"
    (nothing timed; AddKeyframe after the clock reads)."""

    def __init__(self, binary, log):
        self.process = subprocess.Popen([binary, "--serve", log],
                                        stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, text=True)

    def time(self, kind):
        """(cpu, wall) seconds of one repetition of `kind`."""
        self.process.stdin.write(kind + "\n")
        self.process.stdin.flush()
        fields = self.process.stdout.readline().split()
        if not fields:
            sys.exit("symba-python-overhead-bench --serve failed")
        return float(fields[3]), float(fields[1])

    def close(self):
        self.process.stdin.close()
        if self.process.wait() != 0:
            sys.exit("symba-python-overhead-bench --serve failed")


def as_arrays(keyframe):
    """What a Python front end would hold for one keyframe: one (30, 7)
    array per detection."""
    return (keyframe.id, keyframe.timestamp, keyframe.T_wc,
            [(d.class_name, d.hypotheses, d.id) for d in keyframe.detections],
            keyframe.point_ids, keyframe.point_uv, keyframe.point_depth)


def as_stacked(keyframe):
    """The same with the hypotheses stacked: add_keyframe_arrays's
    arguments, in the order of the timed calls below."""
    detections = keyframe.detections
    return (keyframe.id, keyframe.timestamp, keyframe.T_wc,
            np.concatenate([d.hypotheses for d in detections]),
            np.array([len(d.weights) for d in detections], dtype=np.int64),
            [d.class_name for d in detections], [d.id for d in detections],
            keyframe.point_ids, keyframe.point_uv, keyframe.point_depth)


# One function per variant, each the whole loop over the keyframes: the
# timed statement is exactly the user's call, on local variables, between
# two reads of the thread's CPU clock (bound locally, as `clock`); each add
# is followed by an untimed optimize_window. They return one (cpu, wall)
# pair per keyframe.

def run_empty(backend, items, clock, wall):
    """Nothing between the clock reads (then the add, untimed): the floor
    the timer itself puts under every row."""
    times = []
    for kid, t, T_wc, h, counts, names, ids, pids, uv, depth in items:
        wall_start = wall()
        cpu_start = clock()
        cpu_end = clock()
        wall_end = wall()
        backend.add_keyframe_arrays(
            kid, t, T_wc=T_wc, hypotheses=h, counts=counts,
            class_names=names, detection_ids=ids, point_ids=pids,
            point_uv=uv, point_depth=depth)
        backend.optimize_window()
        times.append((cpu_end - cpu_start, wall_end - wall_start))
    return times


def run_objects(backend, keyframes, clock, wall):
    times = []
    for keyframe in keyframes:
        wall_start = wall()
        cpu_start = clock()
        backend.add_keyframe(keyframe)
        cpu_end = clock()
        wall_end = wall()
        backend.optimize_window()
        times.append((cpu_end - cpu_start, wall_end - wall_start))
    return times


def run_arrays(backend, items, clock, wall):
    times = []
    for kid, t, T_wc, h, counts, names, ids, pids, uv, depth in items:
        wall_start = wall()
        cpu_start = clock()
        backend.add_keyframe_arrays(
            kid, t, T_wc=T_wc, hypotheses=h, counts=counts,
            class_names=names, detection_ids=ids, point_ids=pids,
            point_uv=uv, point_depth=depth)
        cpu_end = clock()
        wall_end = wall()
        backend.optimize_window()
        times.append((cpu_end - cpu_start, wall_end - wall_start))
    return times


def run_from_arrays(backend, items, clock, wall):
    from_arrays = symba.Keyframe.from_arrays
    times = []
    for kid, t, T_wc, h, counts, names, ids, pids, uv, depth in items:
        wall_start = wall()
        cpu_start = clock()
        backend.add_keyframe(from_arrays(
            kid, t, T_wc=T_wc, hypotheses=h, counts=counts,
            class_names=names, detection_ids=ids, point_ids=pids,
            point_uv=uv, point_depth=depth))
        cpu_end = clock()
        wall_end = wall()
        backend.optimize_window()
        times.append((cpu_end - cpu_start, wall_end - wall_start))
    return times


def run_detections(backend, items, clock, wall):
    Detection, Keyframe = symba.Detection, symba.Keyframe
    times = []
    for kid, t, T_wc, detections, pids, uv, depth in items:
        wall_start = wall()
        cpu_start = clock()
        backend.add_keyframe(Keyframe(
            kid, t, T_wc=T_wc,
            detections=[Detection(c, h, id=i) for c, h, i in detections],
            point_ids=pids, point_uv=uv, point_depth=depth))
        cpu_end = clock()
        wall_end = wall()
        backend.optimize_window()
        times.append((cpu_end - cpu_start, wall_end - wall_start))
    return times


def python_times(header, items, warmup, run):
    """The CPU and wall seconds over the keyframes after `warmup`, and the
    trajectory."""
    backend = symba.Backend(intrinsics=header.camera)
    times = run(backend, items, time.thread_time, time.perf_counter)[warmup:]
    return ((sum(c for c, _ in times), sum(w for _, w in times)),
            backend.keyframes().poses)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--rounds", type=int, default=5,
                        help="rounds of --runs runs")
    parser.add_argument("--runs", type=int, default=5,
                        help="runs per round; each run times every variant "
                        "once, C++ and Python alternating")
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
            "python: add_keyframe(keyframe), keyframes already built":
                (keyframes, run_objects),
            "python: add_keyframe_arrays(...), one call":
                (stacked, run_arrays),
            "python: add_keyframe(Keyframe.from_arrays(...)), two calls":
                (stacked, run_from_arrays),
            "python: a Detection per (30, 7) array, a Keyframe, "
            "add_keyframe (seven calls)": (arrays, run_detections),
            "python: the clock reads alone": (stacked, run_empty),
        }
        cpp = {"c++: AddKeyframe": "add",
               "c++: copy the KeyframeInput, then AddKeyframe": "copy",
               "c++: the clock reads alone": "empty"}
        results = {name: [] for name in list(cpp) + list(variants)}
        poses = []
        server = Cpp(binary, log)
        for kind in cpp.values():  # warm-up
            server.time(kind)
        for items, run in variants.values():
            python_times(header, items, warmup, run)
        for _ in range(args.rounds * args.runs):
            for name, kind in cpp.items():
                results[name].append(server.time(kind))
            for name, (items, run) in variants.items():
                t, p = python_times(header, items, warmup, run)
                results[name].append(t)
                poses.append(p)
        server.close()
        for p in poses[1:]:
            if not np.array_equal(p, poses[0]):
                sys.exit("the Python variants disagree on the trajectory")

    base = results["c++: AddKeyframe"]
    base_cpu = statistics.median(c for c, _ in base)
    base_wall = statistics.median(w for _, w in base)
    print(f"{timed} timed keyframes; {args.rounds * args.runs} runs of "
          f"each variant, C++ and Python alternating run by run; medians "
          f"over the runs; ms per keyframe; load average {load_start:.1f} "
          f"at the start, {os.getloadavg()[0]:.1f} at the end")
    print("| variant | CPU ms | CPU vs C++ | CPU vs C++, paired | wall ms "
          "| wall vs C++ |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, values in results.items():
        cpu = statistics.median(c for c, _ in values)
        wall = statistics.median(w for _, w in values)
        paired = statistics.median(
            c / b for (c, _), (b, _) in zip(values, base))
        print(f"| {name} | {1e3 * cpu / timed:.4f} | "
              f"{100 * (cpu / base_cpu - 1):+.1f} % | "
              f"{100 * (paired - 1):+.1f} % | "
              f"{1e3 * wall / timed:.4f} | "
              f"{100 * (wall / base_wall - 1):+.1f} % |")


if __name__ == "__main__":
    main()
