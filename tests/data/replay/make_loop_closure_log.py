"""Writes loop_closure.jsonl (beside this file): one lap of 40 keyframes
on a circle of radius 2 m and back to the start, odometry only, with a
1.5 deg yaw bias per keyframe on the second half, and the host's loop
closure from the last keyframe to the first (the truth, 1 cm / 0.005 rad).
Run with the symba module on PYTHONPATH; the file is committed."""

import math
import pathlib

import numpy as np

import symba


def pose(yaw, x, y):
    c, s = math.cos(yaw), math.sin(yaw)
    T = np.eye(4)
    T[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    T[:3, 3] = [x, y, 1.0]
    return T


n = 40
truth = [pose(2 * math.pi * k / n, 2 * math.cos(2 * math.pi * k / n),
              2 * math.sin(2 * math.pi * k / n)) for k in range(n + 1)]
path = pathlib.Path(__file__).with_name("loop_closure.jsonl")
writer = symba.LogWriter(str(path), symba.LogHeader())
writer.write(symba.Keyframe(0, 0.0, T_wc=truth[0]))
for k in range(1, n + 1):
    step = np.linalg.inv(truth[k - 1]) @ truth[k]
    if k > n // 2:
        step = step @ pose(math.radians(1.5), 0.0, 0.0) @ np.linalg.inv(
            pose(0.0, 0.0, 0.0))
    closures = []
    if k == n:
        closures = [symba.LoopClosure(0, np.linalg.inv(truth[0]) @ truth[k],
                                      0.01, 0.005)]
    writer.write(symba.Keyframe(k, 0.1 * k,
                                odometry=symba.Odometry(step, 0.01, 0.02),
                                loop_closures=closures))
writer.close()
