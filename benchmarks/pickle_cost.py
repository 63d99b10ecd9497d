#!/usr/bin/env python3
"""What pickling a Backend costs (docs/python.md, Pickling): a simulated
long run fed keyframe by keyframe with a window solve after each, once with
the journal and once without (each in a process of its own, so that the
peak memory is the run's), then the pickle's size per keyframe and the
time of pickle.dumps and pickle.loads against the run's. Not a test: it
prints numbers for docs/python.md.

    PYTHONPATH=build/python python3 benchmarks/pickle_cost.py \
        [--build build] [--keyframes 2000] [--seed 7]
"""

import argparse
import pathlib
import pickle
import resource
import subprocess
import sys
import tempfile
import time


def run(log, keep_journal):
    import symba
    header, keyframes = symba.read_log(log)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    backend = symba.Backend(intrinsics=header.camera,
                            class_priors=header.classes,
                            keep_journal=keep_journal)
    start = time.perf_counter()
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()
    seconds = time.perf_counter() - start
    growth = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    print(f"keep_journal={keep_journal}: run {seconds:.1f} s, "
          f"peak memory growth {growth / 1024:.1f} MiB")
    if keep_journal:
        start = time.perf_counter()
        data = pickle.dumps(backend)
        dumps = time.perf_counter() - start
        start = time.perf_counter()
        pickle.loads(data)
        loads = time.perf_counter() - start
        print(f"pickle {len(data) / len(keyframes) / 1000:.1f} KB per "
              f"keyframe, dumps {dumps:.2f} s, loads {loads:.1f} s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--keyframes", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        run(args.child[0], args.child[1] == "1")
        return
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([str(pathlib.Path(args.build) / "bin" / "symba"),
                        "simulate", "--scene", "long", "--keyframes",
                        str(args.keyframes), "--seed", str(args.seed),
                        "--out", out, "--quiet"], check=True)
        log = str(pathlib.Path(out) / "log.jsonl")
        for keep in ("0", "1"):
            subprocess.run([sys.executable, __file__, "--child", log, keep],
                           check=True)


if __name__ == "__main__":
    main()
