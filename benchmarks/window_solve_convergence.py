#!/usr/bin/env python3
"""How the window's solves converge over a long run (docs/performance.md,
"Loop closures on the long scene"): replays a log keyframe by keyframe
with a window solve after each (default options) and prints, per block of
keyframes that closed no loop, the mean time of add_keyframe plus
optimize_window, the mean Levenberg-Marquardt iterations and the share of
solves Ceres ended converged. Not a test.

    build/bin/symba simulate --scene long --seed 1 --out /tmp/long
    PYTHONPATH=build/python python3 benchmarks/window_solve_convergence.py \
        /tmp/long/log.jsonl [--block 1000] [--no-loops]

--no-loops replays with `detect_loops` off (nothing moves the past).
"""

import argparse
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", help="a symba log (log.jsonl)")
    parser.add_argument("--block", type=int, default=1000,
                        help="keyframes per printed row")
    parser.add_argument("--no-loops", action="store_true",
                        help="detect_loops off: no loop closures")
    args = parser.parse_args()
    import symba

    header, keyframes = symba.read_log(args.log)
    options = symba.BackendOptions(detect_loops=not args.no_loops)
    backend = symba.Backend(options, intrinsics=header.camera,
                            class_priors=header.classes)
    rows = {}
    closures = 0
    for k, keyframe in enumerate(keyframes):
        start = time.perf_counter()
        backend.add_keyframe(keyframe)
        report = backend.optimize_window()
        seconds = time.perf_counter() - start
        count = sum(1 for c in backend.loop_closures() if not c.waiting)
        closed, closures = count != closures, count
        if closed:
            continue  # its time is the loop closure's
        row = rows.setdefault(k // args.block, [0, 0.0, 0, 0])
        row[0] += 1
        row[1] += seconds
        row[2] += report.iterations
        row[3] += int(report.converged)
    print("keyframes | ms per keyframe | iterations | converged")
    for block, (n, seconds, iterations, converged) in sorted(rows.items()):
        first = block * args.block
        print(f"{first}-{first + args.block - 1} | {1e3 * seconds / n:.2f} | "
              f"{iterations / n:.2f} | {100.0 * converged / n:.0f} %")


if __name__ == "__main__":
    main()
