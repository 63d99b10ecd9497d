"""Loop closures from the host (docs/loop-closure.md) through Python: a
keyframe's loop_closures and Backend.add_loop_closure correct a drifting
odometry over the whole past, are reported, survive pickling, and bad ones
raise symba.Error."""

import math
import pickle

import numpy as np
import pytest

import symba


def pose(yaw, x, y):
    """4 x 4: a camera at (x, y, 1) turned by yaw about the world z."""
    c, s = math.cos(yaw), math.sin(yaw)
    T = np.eye(4)
    T[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    T[:3, 3] = [x, y, 1.0]
    return T


def orbit(n=40, radius=2.0):
    """The true poses of one lap and back to the start (n + 1 of them)."""
    poses = []
    for k in range(n + 1):
        phi = 2.0 * math.pi * k / n
        poses.append(pose(phi, radius * math.cos(phi), radius * math.sin(phi)))
    return poses


def drifting_keyframes(truth, bias=math.radians(1.5)):
    """Odometry with a yaw bias on the second half of the lap."""
    keyframes = [symba.Keyframe(0, 0.0, T_wc=truth[0])]
    for k in range(1, len(truth)):
        step = np.linalg.inv(truth[k - 1]) @ truth[k]
        if k > len(truth) // 2:
            step = step @ pose(bias, 0.0, 0.0) @ np.linalg.inv(pose(0, 0, 0))
        keyframes.append(symba.Keyframe(
            k, 0.1 * k, odometry=symba.Odometry(step, 0.01, 0.02)))
    return keyframes


def closure_to_start(truth, k):
    return symba.LoopClosure(0, np.linalg.inv(truth[0]) @ truth[k], 0.01,
                             0.005)


def position_rmse(backend, truth):
    estimated = backend.keyframes().poses[:, :3]
    expected = np.array([T[:3, 3] for T in truth])
    return float(np.sqrt(np.mean(np.sum((estimated - expected) ** 2, 1))))


def replay(keyframes):
    backend = symba.Backend(symba.BackendOptions(window_size=5))
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()
    return backend


def test_a_keyframes_loop_closure_corrects_the_whole_past():
    truth = orbit()
    keyframes = drifting_keyframes(truth)
    open_loop = replay(keyframes)
    keyframes[-1].loop_closures = [closure_to_start(truth, len(truth) - 1)]
    assert keyframes[-1].loop_closures[0].keyframe == 0
    closed = replay(keyframes)
    assert position_rmse(open_loop, truth) > 0.3
    assert position_rmse(closed, truth) < 0.25 * position_rmse(open_loop,
                                                               truth)
    (report,) = closed.loop_closures()
    assert (report.keyframe, report.other, report.moved_past) == (40, 0, True)
    assert report.correction_m > 0.3
    assert report.final_cost < report.initial_cost
    # The host's closure, not one found from the objects (there are none).
    assert not report.from_objects and report.objects == []
    statistics = closed.statistics()
    assert statistics.loop_closures == 1
    assert statistics.loop_closures_moved_past == 1
    assert statistics.object_loop_closures == 0
    assert statistics.objects_merged == 0


def test_add_loop_closure_is_reported_and_pickled():
    truth = orbit()
    backend = replay(drifting_keyframes(truth))
    report = backend.add_loop_closure(40, closure_to_start(truth, 40))
    assert report.moved_past and report.keyframes_moved > 30
    copied = pickle.loads(pickle.dumps(backend))
    np.testing.assert_array_equal(copied.keyframes().poses,
                                  backend.keyframes().poses)
    assert len(copied.loop_closures()) == 1
    backend.optimize_window()
    copied.optimize_window()
    np.testing.assert_array_equal(copied.keyframes().poses,
                                  backend.keyframes().poses)


def test_a_closure_waiting_for_a_solve_is_reported_as_waiting():
    truth = orbit()
    keyframes = drifting_keyframes(truth)
    backend = replay(keyframes[:-1])
    backend.add_keyframe(keyframes[-1])
    report = backend.add_loop_closure(40, closure_to_start(truth, 40))
    assert report.waiting and not report.moved_past
    assert report.message == "waits for the next solve"
    (listed,) = backend.loop_closures()
    assert (listed.keyframe, listed.other, listed.waiting) == (40, 0, True)
    backend.optimize_window()
    (listed,) = backend.loop_closures()
    assert listed.moved_past and not listed.waiting and listed.message == ""


def test_bad_loop_closures_raise():
    truth = orbit(n=8)
    backend = replay(drifting_keyframes(truth))
    with pytest.raises(symba.Error, match="unknown keyframe 99"):
        backend.add_loop_closure(8, symba.LoopClosure(99, np.eye(4)))
    with pytest.raises(symba.Error, match="itself"):
        backend.add_loop_closure(8, symba.LoopClosure(8, np.eye(4)))
    with pytest.raises(symba.Error, match="sigma_t"):
        backend.add_loop_closure(8, symba.LoopClosure(0, np.eye(4), 0.0))
    assert backend.loop_closures() == []


def test_keyframe_covariances_grow_with_the_odometry_and_shrink_with_a_loop():
    """A keyframe's world covariance (docs/backend.md "Covariances"): the
    first keyframe's is zero, the drifting odometry's accumulates along the
    lap, and the host's loop closure back to the start takes most of it."""
    truth = orbit()
    keyframes = drifting_keyframes(truth)
    ids = [0, 10, len(truth) - 1]
    open_loop = replay(keyframes)
    before = open_loop.keyframe_covariances(ids)
    assert [c["id"] for c in before] == ids
    assert all(c["covariance"].shape == (6, 6) for c in before)
    assert not before[0]["covariance"].any()
    np.testing.assert_allclose(before[2]["covariance"],
                               before[2]["covariance"].T)
    position = [np.trace(c["covariance"][:3, :3]) for c in before]
    assert 0.0 < position[1] < position[2]
    keyframes[-1].loop_closures = [closure_to_start(truth, len(truth) - 1)]
    closed = replay(keyframes).keyframe_covariances(ids)
    assert np.trace(closed[2]["covariance"][:3, :3]) < 0.5 * position[2]
    with pytest.raises(symba.Error, match="keyframe 999 is unknown"):
        open_loop.keyframe_covariances([999])
