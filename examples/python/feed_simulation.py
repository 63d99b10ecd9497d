#!/usr/bin/env python3
"""Feeds a simulated sequence to symba keyframe by keyframe, as a SLAM
front end would, and plots the trajectory and the map objects from above.

    PYTHONPATH=build/python python3 examples/python/feed_simulation.py \
        [--scene disc] [--seed 1] [--keyframes 72] [--out trajectory.png]

The picture needs matplotlib (Debian: python3-matplotlib); without it the
example prints its summary and skips the picture.
"""

import argparse

import numpy as np

import symba


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="disc", choices=symba.scene_names())
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--keyframes", type=int, default=72)
    parser.add_argument("--out", default="trajectory.png",
                        help="where to save the picture (PNG)")
    args = parser.parse_args()

    # The simulator stands in for a front end and a detector: per keyframe,
    # the front end's pose estimate T_wc, multi-hypothesis detections and
    # point observations. Its ground truth is kept for the comparison.
    simulation = symba.simulate(args.scene, seed=args.seed,
                                num_keyframes=args.keyframes)
    header = simulation.header

    backend = symba.Backend(symba.BackendOptions(window_size=10),
                            intrinsics=header.camera,
                            class_priors=header.classes)
    front_end = []
    for keyframe in simulation.keyframes:
        # A front end would build the keyframe from its own arrays, e.g.
        # symba.Keyframe(id, t, T_wc=pose7, detections=[symba.Detection(
        #     "table", hypotheses_n_by_7)], point_ids=ids, point_uv=uv,
        #     point_depth=depth).
        assignments = backend.add_keyframe(keyframe)
        report = backend.optimize_window()
        front_end.append(keyframe.T_wc)
        if keyframe.id % 12 == 0:
            kinds = ", ".join(f"{a.detection}->{a.object} ({a.symmetry})"
                              for a in assignments)
            print(f"keyframe {keyframe.id}: {report.iterations} iterations; "
                  f"{kinds}")

    trajectory = backend.keyframes()
    objects = backend.objects()
    truth = simulation.true_poses
    rmse = np.sqrt(np.mean(np.sum(
        (trajectory.poses[:, :3] - truth[:, :3]) ** 2, axis=1)))
    front_end = np.array(front_end)
    front_end_rmse = np.sqrt(np.mean(np.sum(
        (front_end[:, :3] - truth[:, :3]) ** 2, axis=1)))
    print(f"{len(trajectory)} keyframes, {len(objects)} map objects "
          f"({len(simulation.objects)} in the scene); keyframe position "
          f"RMSE {rmse:.3f} m (front end {front_end_rmse:.3f} m)")
    for o in objects:
        print(f"  object {o.id}: {o.class_name}, {o.symmetry}, "
              f"t_wo {np.round(o.t_wo, 3)}, {o.observations} observations")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no picture")
        return

    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(truth[:, 0], truth[:, 1], "k-", lw=1, label="ground truth")
    ax.plot(front_end[:, 0], front_end[:, 1], "C1--", lw=1, label="front end")
    ax.plot(trajectory.poses[:, 0], trajectory.poses[:, 1], "C0-", lw=1.5,
            label="symba")
    true_t = np.array([o.T_wo[:3] for o in simulation.objects])
    ax.scatter(true_t[:, 0], true_t[:, 1], marker="x", c="k",
               label="true objects")
    if objects:
        t = np.array([o.t_wo for o in objects])
        ax.scatter(t[:, 0], t[:, 1], facecolors="none", edgecolors="C0",
                   s=80, label="map objects")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{args.scene}, seed {args.seed}")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3,
              fontsize="small")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
