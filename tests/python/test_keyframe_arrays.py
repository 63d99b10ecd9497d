"""A whole keyframe from NumPy arrays in one call (Keyframe.from_arrays,
Backend.add_keyframe_arrays) gives what the Detection/Keyframe path gives on
the same data, and refuses bad arrays with ValueErrors naming the argument
and what was expected."""

import numpy as np
import pytest

import symba

IDENTITY = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])


def arrays_of(keyframe):
    """Keyframe.from_arrays's keyword arguments for `keyframe`: its
    detections' hypotheses stacked into one (H, 7) array."""
    detections = keyframe.detections
    kwargs = dict(T_wc=keyframe.T_wc, point_ids=keyframe.point_ids,
                  point_uv=keyframe.point_uv,
                  point_depth=keyframe.point_depth)
    if keyframe.odometry is not None:
        kwargs.update(odometry=keyframe.odometry.T_prev_cur,
                      odometry_sigma_t=keyframe.odometry.sigma_t,
                      odometry_sigma_r=keyframe.odometry.sigma_r)
    if detections:
        kwargs.update(
            hypotheses=np.concatenate([d.hypotheses for d in detections]),
            counts=np.array([len(d.weights) for d in detections],
                            dtype=np.int64),
            weights=np.concatenate([d.weights for d in detections]),
            class_names=[d.class_name for d in detections],
            detection_ids=[d.id for d in detections],
            scores=np.array([d.score for d in detections]),
            detection_sigma_t=np.array([d.sigma_t or 0.0
                                        for d in detections]),
            detection_sigma_r=np.array([d.sigma_r or 0.0
                                        for d in detections]))
    return kwargs


def assert_same_keyframe(got, want):
    assert got.id == want.id
    assert got.timestamp == want.timestamp
    if want.T_wc is None:
        assert got.T_wc is None
    else:
        np.testing.assert_allclose(got.T_wc, want.T_wc, rtol=0, atol=1e-12)
    if want.odometry is None:
        assert got.odometry is None
    else:
        np.testing.assert_allclose(got.odometry.T_prev_cur,
                                   want.odometry.T_prev_cur, rtol=0,
                                   atol=1e-12)
        assert got.odometry.sigma_t == want.odometry.sigma_t
        assert got.odometry.sigma_r == want.odometry.sigma_r
    assert len(got.detections) == len(want.detections)
    for g, w in zip(got.detections, want.detections):
        assert (g.id, g.class_name, g.score, g.sigma_t, g.sigma_r) == (
            w.id, w.class_name, w.score, w.sigma_t, w.sigma_r)
        np.testing.assert_allclose(g.hypotheses, w.hypotheses, rtol=0,
                                   atol=1e-12)
        np.testing.assert_allclose(g.weights, w.weights, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(got.point_ids, want.point_ids)
    np.testing.assert_allclose(got.point_uv, want.point_uv, rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(got.point_depth, want.point_depth, rtol=0,
                               atol=1e-12)


def test_from_arrays_equals_the_keyframe_it_was_taken_from(simulated_log):
    _, keyframes = symba.read_log(str(simulated_log))
    assert any(k.odometry is not None for k in keyframes)
    assert any(len(k.point_ids) > 0 for k in keyframes)
    for keyframe in keyframes:
        built = symba.Keyframe.from_arrays(keyframe.id, keyframe.timestamp,
                                           **arrays_of(keyframe))
        assert_same_keyframe(built, keyframe)


def test_add_keyframe_arrays_equals_add_keyframe(simulated_log):
    header, keyframes = symba.read_log(str(simulated_log))
    backends = [symba.Backend(intrinsics=header.camera,
                              class_priors=header.classes)
                for _ in range(2)]
    for keyframe in keyframes:
        want = backends[0].add_keyframe(keyframe)
        got = backends[1].add_keyframe_arrays(keyframe.id, keyframe.timestamp,
                                              **arrays_of(keyframe))
        assert [repr(a) for a in got] == [repr(a) for a in want]
        for backend in backends:
            backend.optimize_window()
    np.testing.assert_allclose(backends[1].keyframes().poses,
                               backends[0].keyframes().poses, rtol=0,
                               atol=1e-12)
    assert [repr(o) for o in backends[1].objects()] == [
        repr(o) for o in backends[0].objects()]


def test_add_keyframe_arrays_forgets_the_previous_keyframe(simulated_log):
    """A keyframe without weights, detection ids, scores or sigmas after
    one with them gets the defaults in add_keyframe_arrays, as in a
    Keyframe.from_arrays built anew (FillKeyframe overwrites every field,
    should a buffer ever be refilled)."""
    header, keyframes = symba.read_log(str(simulated_log))
    assert any(d.id for k in keyframes for d in k.detections)
    optional = {"weights", "detection_ids", "scores", "detection_sigma_t",
                "detection_sigma_r"}
    backends = [symba.Backend(intrinsics=header.camera,
                              class_priors=header.classes)
                for _ in range(2)]
    for k, keyframe in enumerate(keyframes):
        kwargs = arrays_of(keyframe)
        if k % 2:
            kwargs = {n: v for n, v in kwargs.items() if n not in optional}
        want = backends[0].add_keyframe(symba.Keyframe.from_arrays(
            keyframe.id, keyframe.timestamp, **kwargs))
        got = backends[1].add_keyframe_arrays(keyframe.id, keyframe.timestamp,
                                              **kwargs)
        assert [repr(a) for a in got] == [repr(a) for a in want]
        for backend in backends:
            backend.optimize_window()
    np.testing.assert_array_equal(backends[1].keyframes().poses,
                                  backends[0].keyframes().poses)


def test_from_arrays_equals_detections_built_one_by_one():
    rng = np.random.default_rng(7)
    q = rng.normal(size=(5, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    hypotheses = np.hstack([rng.normal(size=(5, 3)), q])
    weights = rng.uniform(0.5, 2.0, size=5)
    odometry = symba.Odometry(IDENTITY, sigma_t=0.02, sigma_r=0.03)
    want = symba.Keyframe(
        4, 0.5, odometry=odometry,
        detections=[
            symba.Detection("mug", hypotheses[:2], weights[:2], id="4/0",
                            sigma_t=0.1, score=0.5),
            symba.Detection("table", hypotheses[2:], weights[2:], id="4/1",
                            sigma_r=0.2)],
        point_ids=np.array([3, 9], dtype=np.int64),
        point_uv=np.array([[1.0, 2.0], [3.0, 4.0]]),
        point_depth=np.array([0.0, 2.5]))
    got = symba.Keyframe.from_arrays(
        4, 0.5, odometry=odometry,
        hypotheses=hypotheses,
        counts=[2, 3], weights=weights, class_names=("mug", "table"),
        detection_ids=["4/0", "4/1"], scores=[0.5, 1.0],
        detection_sigma_t=[0.1, 0.0], detection_sigma_r=[0.0, 0.2],
        point_ids=[3, 9], point_uv=[[1.0, 2.0], [3.0, 4.0]],
        point_depth=[0.0, 2.5])
    assert_same_keyframe(got, want)
    assert got.detections[1].weights.tolist() == weights[2:].tolist()
    # 4 x 4 hypotheses give the same rotations (the quaternion's sign may
    # differ) and translations.
    matrices = symba.Keyframe.from_arrays(
        4, 0.5, odometry=odometry, hypotheses=symba.pose_matrices(hypotheses),
        counts=[2, 3], class_names=["mug", "table"])
    for g, w in zip(matrices.detections, want.detections):
        np.testing.assert_allclose(symba.pose_matrices(g.hypotheses),
                                   symba.pose_matrices(w.hypotheses), rtol=0,
                                   atol=1e-12)
    # Defaults: weights 1, ids "", score 1, no sigmas, no points.
    bare = symba.Keyframe.from_arrays(0, 0.0, T_wc=IDENTITY,
                                      hypotheses=hypotheses, counts=[5],
                                      class_names=["mug"])
    assert bare.detections[0].weights.tolist() == [1.0] * 5
    assert (bare.detections[0].id, bare.detections[0].score,
            bare.detections[0].sigma_t) == ("", 1.0, None)
    assert len(bare.point_ids) == 0
    empty = symba.Keyframe.from_arrays(1, 0.1, odometry=IDENTITY)
    assert empty.detections == [] and empty.T_wc is None
    assert (empty.odometry.sigma_t, empty.odometry.sigma_r) == (0.01, 0.005)


def from_arrays_error(**overrides):
    kwargs = dict(T_wc=IDENTITY, hypotheses=np.tile(IDENTITY, (3, 1)),
                  counts=np.array([1, 2], dtype=np.int64),
                  class_names=["a", "b"])
    kwargs.update(overrides)
    with pytest.raises(ValueError) as error:
        symba.Keyframe.from_arrays(0, 0.0, **kwargs)
    backend = symba.Backend()
    with pytest.raises(ValueError) as backend_error:
        backend.add_keyframe_arrays(0, 0.0, **kwargs)
    assert str(backend_error.value) == str(error.value)
    assert backend.statistics().keyframes == 0
    return str(error.value)


def test_bad_arrays_raise_value_errors_naming_the_argument():
    three = np.tile(IDENTITY, (3, 1))
    assert from_arrays_error(hypotheses=three[:, :6]) == (
        "hypotheses: expected poses of shape (N, 7) [tx, ty, tz, qx, qy, qz, "
        "qw] or (N, 4, 4), got shape (3, 6)")
    assert from_arrays_error(hypotheses=three.astype(np.float32)) == (
        "hypotheses: expected a float64 array, got dtype float32 (convert it "
        "with .astype(numpy.float64))")
    bad = three.copy()
    bad[2, 6] = np.nan
    assert from_arrays_error(hypotheses=bad) == (
        "hypotheses[2, 6]: expected a finite number, got nan")
    assert from_arrays_error(counts=None) == (
        "hypotheses, counts: give both (with class_names) or neither")
    assert from_arrays_error(counts=np.array([1.0, 2.0])) == (
        "counts: expected a int64 array, got dtype float64 (convert it with "
        ".astype(numpy.int64))")
    assert from_arrays_error(counts=np.array([[1, 2]])) == (
        "counts: expected shape (D,), one hypothesis count per detection, "
        "got shape (1, 2)")
    assert from_arrays_error(counts=[1, 1]) == (
        "counts: the counts add up to 2, but hypotheses has 3 rows")
    assert from_arrays_error(counts=[4, -1]) == (
        "counts[1]: expected a count >= 0, got -1")
    assert from_arrays_error(weights=np.ones(2)) == (
        "weights: expected shape (3,), one weight per hypothesis, got shape "
        "(2,)")
    assert from_arrays_error(weights=[1.0, np.inf, 1.0]) == (
        "weights[1]: expected a finite number, got inf")
    assert from_arrays_error(class_names=None) == (
        "class_names: expected a list of 2 str, one per detection, got None")
    assert from_arrays_error(class_names="ab") == (
        "class_names: expected a list of 2 str, one per detection, got a "
        "single str")
    assert from_arrays_error(class_names=["a"]) == (
        "class_names: expected 2 str, one per detection, got 1")
    assert from_arrays_error(class_names=["a", 2]) == (
        "class_names[1]: expected a str, got int")
    assert from_arrays_error(detection_ids=5) == (
        "detection_ids: expected a list of 2 str, one per detection, got int")
    assert from_arrays_error(scores=[1.0]) == (
        "scores: expected shape (2,), one score per detection, got shape (1,)")
    assert from_arrays_error(detection_sigma_t=[0.1, np.nan]) == (
        "detection_sigma_t[1]: expected a finite number, got nan")
    assert from_arrays_error(detection_sigma_r=np.zeros((2, 1))) == (
        "detection_sigma_r: expected shape (2,), one sigma (0: none) per "
        "detection, got shape (2, 1)")
    assert from_arrays_error(T_wc=IDENTITY[:6]) == (
        "T_wc: expected a pose of shape (7,) [tx, ty, tz, qx, qy, qz, qw] or "
        "(4, 4), got shape (6,)")
    assert from_arrays_error(odometry=np.zeros(3)) == (
        "odometry: expected a pose of shape (7,) [tx, ty, tz, qx, qy, qz, "
        "qw] or (4, 4), got shape (3,)")
    assert from_arrays_error(odometry=IDENTITY,
                             odometry_sigma_t=float("inf")) == (
        "odometry_sigma_t: expected a finite number, got inf")
    assert from_arrays_error(odometry_sigma_r=0.1) == (
        "odometry_sigma_t, odometry_sigma_r: given without odometry")
    assert from_arrays_error(odometry=symba.Odometry(IDENTITY),
                             odometry_sigma_t=0.1) == (
        "odometry_sigma_t, odometry_sigma_r: give them only with an "
        "odometry array (an Odometry has its own sigmas)")
    assert from_arrays_error(point_ids=[1, 2], point_uv=np.zeros((3, 2))) == (
        "point_uv: expected shape (2, 2), one [u, v] per point id, got shape "
        "(3, 2)")


def test_add_keyframe_arrays_raises_the_backends_message():
    backend = symba.Backend()
    with pytest.raises(symba.Error) as error:
        backend.add_keyframe_arrays(0, 0.0, T_wc=IDENTITY,
                                    hypotheses=np.tile(IDENTITY, (2, 1)),
                                    counts=[2, 0], class_names=["a", "b"],
                                    detection_ids=["0/0", "0/1"])
    assert str(error.value) == "keyframe 0: detection 0/1: has no hypotheses"
    assert backend.statistics().keyframes == 0
    with pytest.raises(TypeError):
        backend.add_keyframe_arrays(0, 0.0, IDENTITY)  # keywords only
