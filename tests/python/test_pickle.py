"""Pickling a Backend (docs/python.md, Pickling): the unpickled backend has
the same state bit for bit and goes on exactly as the original would."""

import copy
import pickle

import numpy as np
import pytest

import symba


def feed(backend, keyframes):
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()


def assert_same_state(a, b):
    ka, kb = a.keyframes(), b.keyframes()
    np.testing.assert_array_equal(ka.ids, kb.ids)
    np.testing.assert_array_equal(ka.poses, kb.poses)
    assert [o.id for o in a.objects()] == [o.id for o in b.objects()]
    for oa, ob in zip(a.objects(), b.objects()):
        assert (oa.class_name, oa.symmetry, oa.observations) == (
            ob.class_name, ob.symmetry, ob.observations)
        np.testing.assert_array_equal(oa.poses, ob.poses)
        np.testing.assert_array_equal(oa.angle_evidence, ob.angle_evidence)
    assert [(x.keyframe, x.detection, x.object) for x in a.assignments()] == [
        (x.keyframe, x.detection, x.object) for x in b.assignments()]
    sa, sb = a.statistics(), b.statistics()
    assert (sa.keyframes, sa.objects, sa.solves, sa.object_upgrades) == (
        sb.keyframes, sb.objects, sb.solves, sb.object_upgrades)


def test_a_pickled_backend_goes_on_as_the_original(simulated_log):
    header, keyframes = symba.read_log(str(simulated_log))
    options = symba.BackendOptions(window_size=4, gate_sigmas=4.5,
                                   keep_history=True)
    original = symba.Backend(options, header.camera, header.classes)
    feed(original, keyframes[:13])
    original.optimize_batch()

    copied = pickle.loads(pickle.dumps(original))
    assert_same_state(original, copied)
    assert copied.options.window_size == 4
    assert copied.options.gate_sigmas == 4.5
    deep = copy.deepcopy(original)
    assert_same_state(original, deep)

    feed(original, keyframes[13:])
    feed(copied, keyframes[13:])
    assert_same_state(original, copied)
    # ... and a pickle of the copy is a pickle of the original.
    assert pickle.dumps(copied) == pickle.dumps(original)


def test_a_backend_without_a_journal_refuses_to_be_pickled(simulated_log):
    header, keyframes = symba.read_log(str(simulated_log))
    backend = symba.Backend(intrinsics=header.camera, keep_journal=False)
    feed(backend, keyframes[:2])
    with pytest.raises(symba.Error, match="keep_journal=False"):
        pickle.dumps(backend)


def test_inputs_covariances_and_maps_in_any_order_survive(simulated_log):
    """What a text log would change is kept exactly: quaternions that are
    unit only to float32 precision, detections without ids, a class prior
    of unknown order. Calls that set the solver up (covariances, saving a
    map) and a map loaded after giving up are made again in their
    order."""
    header, keyframes = symba.read_log(str(simulated_log))
    for keyframe in keyframes:
        pose = keyframe.T_wc
        if pose is not None:
            keyframe.T_wc = pose.astype(np.float32).astype(np.float64)
        for detection in keyframe.detections:
            detection.id = ""
    priors = dict(header.classes)
    priors["unknown"] = symba.ClassPrior("discrete")  # order 0: unknown
    map_text = symba.Backend(intrinsics=header.camera).save_map()
    original = symba.Backend(intrinsics=header.camera, class_priors=priors)
    original.give_up_relocalization()  # nothing to give up yet
    original.load_map(text=map_text, relocalize=True)
    for i, keyframe in enumerate(keyframes[:12]):
        original.add_keyframe(keyframe)
        if i >= 5:
            original.object_covariances()
            original.save_map()
        original.optimize_window()
    copied = pickle.loads(pickle.dumps(original))
    assert_same_state(original, copied)
    assert copied.relocalization().state == original.relocalization().state
    for keyframe in keyframes[12:]:
        for backend in (original, copied):
            backend.add_keyframe(keyframe)
            backend.object_covariances()
            backend.optimize_window()
    assert_same_state(original, copied)
    assert pickle.dumps(copied) == pickle.dumps(original)


def test_a_foreign_state_is_refused():
    state = symba.Backend().__getstate__()
    restored = symba.Backend.__new__(symba.Backend)
    assert state[0] == 2  # the layout since keyframes carry loop closures
    for bad in [(1,) + state[1:], (3,) + state[1:], state[:4],
                ("2",) + state[1:], (2, "x") + state[2:],
                (2, [("window_size", "ten")]) + state[2:]]:
        with pytest.raises(symba.Error, match="cannot unpickle the Backend"):
            restored.__setstate__(bad)
    with pytest.raises(symba.Error, match="unknown option no_such_option"):
        restored.__setstate__((2, [("no_such_option", 1)]) + state[2:])
    with pytest.raises(symba.Error, match="truncated inputs"):
        restored.__setstate__(state[:4] + (b"kw",))
    with pytest.raises(symba.Error, match="too few maps"):
        restored.__setstate__(state[:4] + (b"m",))
    with pytest.raises(symba.Error, match="truncated inputs"):
        restored.__setstate__(
            (2, [], state[2][:-3]) + state[3:])
