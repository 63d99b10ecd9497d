"""Bad input raises: library errors as symba.Error with the C++ message,
arrays of the wrong shape, dtype or with NaN/Inf as ValueError naming the
argument and what was expected."""

import math

import numpy as np
import pytest

import symba

IDENTITY = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]


def test_error_is_a_runtime_error():
    assert issubclass(symba.Error, RuntimeError)


def test_malformed_logs_raise_the_readers_messages(source_dir):
    malformed = source_dir / "tests" / "data" / "malformed"
    path = malformed / "quaternion_not_unit.jsonl"
    with pytest.raises(symba.Error) as error:
        symba.read_log(str(path))
    assert str(error.value) == (
        f"{path}:2: detections[0].hypotheses[2].q: quaternion norm 1.2 is "
        "not within 1e-3 of 1")
    path = malformed / "keyframe_id_not_increasing.jsonl"
    reader = symba.LogReader(str(path))
    assert next(reader).id == 3
    with pytest.raises(symba.Error) as error:
        next(reader)
    assert str(error.value) == (
        f"{path}:3: keyframe: id 3 is not greater than the previous "
        "keyframe's id 3 (line 2)")
    with pytest.raises(symba.Error) as error:
        symba.LogReader(str(malformed / "no_such.jsonl"))
    assert str(error.value) == f"{malformed / 'no_such.jsonl'}: cannot open"


def test_replay_raises_with_file_and_line(source_dir):
    path = source_dir / "tests" / "data" / "replay" / "truncated.jsonl"
    with pytest.raises(symba.Error, match=f"^{path}:3: invalid JSON"):
        symba.replay(str(path))
    with pytest.raises(ValueError, match='^mode: unknown value "fast"'):
        symba.replay(str(path), mode="fast")


def test_invalid_options_raise_the_validation_message():
    with pytest.raises(symba.Error) as error:
        symba.Backend(symba.BackendOptions(window_size=0))
    assert str(error.value) == "window_size must be >= 1"
    with pytest.raises(symba.Error) as error:
        symba.BackendOptions(window_size=0).validate()
    assert str(error.value) == "window_size must be >= 1"
    with pytest.raises(ValueError) as error:
        symba.BackendOptions(method="orb")
    assert str(error.value) == (
        'method: unknown value "orb" (expected "symba", "mh" or "sh")')
    with pytest.raises(TypeError, match="unknown option 'windowsize'"):
        symba.BackendOptions(windowsize=3)
    with pytest.raises(TypeError):
        symba.BackendOptions(window_size="ten")


def test_backend_refuses_a_bad_keyframe_and_adds_nothing():
    backend = symba.Backend()
    with pytest.raises(symba.Error) as error:
        backend.add_keyframe(symba.Keyframe(0, 0.0))
    assert str(error.value) == "keyframe 0: the first keyframe needs T_wc"
    backend.add_keyframe(symba.Keyframe(5, 1.0, T_wc=IDENTITY))
    with pytest.raises(symba.Error) as error:
        backend.add_keyframe(symba.Keyframe(5, 2.0, T_wc=IDENTITY))
    assert str(error.value) == (
        "keyframe 5: id must be greater than the previous (5)")
    not_unit = [0, 0, 2, 0, 0, 0, 2.0]
    with pytest.raises(symba.Error, match=r"^keyframe 6: .*quaternion is not unit"):
        backend.add_keyframe(symba.Keyframe(
            6, 2.0, T_wc=IDENTITY,
            detections=[symba.Detection("mug", [not_unit])]))
    assert len(backend.keyframes()) == 1
    assert backend.statistics().keyframes == 1


def test_categorize_raises_the_librarys_message():
    with pytest.raises(symba.Error) as error:
        symba.categorize(np.array([IDENTITY, IDENTITY]), weights=[1.0, -1.0])
    assert "hypothesis 1" in str(error.value)
    assert "weight" in str(error.value)


def test_log_writer_refuses_with_the_writers_message(tmp_path):
    path = str(tmp_path / "log.jsonl")
    with symba.LogWriter(path, symba.LogHeader()) as writer:
        writer.write(symba.Keyframe(2, 0.0, T_wc=IDENTITY))
        with pytest.raises(symba.Error, match=f"^{path}: keyframe 1: "):
            writer.write(symba.Keyframe(1, 0.0, T_wc=IDENTITY))
    with pytest.raises(symba.Error, match="already closed"):
        writer.write(symba.Keyframe(3, 0.0, T_wc=IDENTITY))
    assert [k.id for k in symba.read_log(path)[1]] == [2]


def test_import_raises_on_a_missing_file(tmp_path):
    missing = str(tmp_path / "none.txt")
    with pytest.raises(symba.Error, match=f"^{missing}"):
        symba.import_tum(missing, [])


@pytest.mark.parametrize("hypotheses, message", [
    (np.zeros((3, 6)),
     "hypotheses: expected poses of shape (N, 7) [tx, ty, tz, qx, qy, qz, "
     "qw] or (N, 4, 4), got shape (3, 6)"),
    (np.zeros(7),
     "hypotheses: expected poses of shape (N, 7) [tx, ty, tz, qx, qy, qz, "
     "qw] or (N, 4, 4), got shape (7,)"),
    (np.zeros((2, 7), dtype=np.float32),
     "hypotheses: expected a float64 array, got dtype float32 (convert it "
     "with .astype(numpy.float64))"),
    (np.zeros((2, 7), dtype=np.int64),
     "hypotheses: expected a float64 array, got dtype int64 (convert it "
     "with .astype(numpy.float64))"),
])
def test_wrong_hypothesis_arrays_are_rejected(hypotheses, message):
    with pytest.raises(ValueError) as error:
        symba.Detection("mug", hypotheses)
    assert str(error.value) == message


def test_non_finite_numbers_are_rejected():
    hyps = np.tile(IDENTITY, (3, 1))
    hyps[1, 2] = np.nan
    with pytest.raises(ValueError) as error:
        symba.Detection("mug", hyps)
    assert str(error.value) == "hypotheses[1, 2]: expected a finite number, got nan"
    pose = np.array(IDENTITY)
    pose[6] = np.inf
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=pose)
    assert str(error.value) == "T_wc[6]: expected a finite number, got inf"
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, math.nan, T_wc=IDENTITY)
    assert str(error.value) == "timestamp: expected a finite number, got nan"
    with pytest.raises(ValueError) as error:
        symba.categorize(np.tile(IDENTITY, (2, 1)), weights=[1.0, np.inf])
    assert str(error.value) == "weights[1]: expected a finite number, got inf"


def test_wrong_pose_and_point_arrays_are_rejected():
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=np.eye(3))
    assert str(error.value) == (
        "T_wc: expected a pose of shape (7,) [tx, ty, tz, qx, qy, qz, qw] "
        "or (4, 4), got shape (3, 3)")
    not_rotation = np.eye(4)
    not_rotation[0, 0] = 1.1
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=not_rotation)
    assert str(error.value) == (
        "T_wc: not a rotation: R^T R differs from the identity by "
        f"{1.1 * 1.1 - 1} (more than 1e-3)")
    reflection = np.diag([1.0, 1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match=r"^T_wc: not a rotation: det\(R\) = -1.0"):
        symba.Keyframe(0, 0.0, T_wc=reflection)
    bad_row = np.eye(4)
    bad_row[3, 0] = 1.0
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=bad_row)
    assert str(error.value) == (
        "T_wc: the last row of a 4 x 4 pose must be [0, 0, 0, 1]")
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=IDENTITY, point_ids=[1, 2],
                       point_uv=np.zeros((3, 2)))
    assert str(error.value) == (
        "point_uv: expected shape (2, 2), one [u, v] per point id, got "
        "shape (3, 2)")
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=IDENTITY, point_ids=np.array([1.0, 2.0]),
                       point_uv=np.zeros((2, 2)))
    assert str(error.value) == (
        "point_ids: expected a int64 array, got dtype float64 (convert it "
        "with .astype(numpy.int64))")
    with pytest.raises(ValueError) as error:
        symba.Keyframe(0, 0.0, T_wc=IDENTITY, point_ids=[1, 2],
                       point_uv=np.zeros((2, 2)), point_depth=[1.0])
    assert str(error.value) == (
        "point_depth: expected shape (2,), one depth per point id, got "
        "shape (1,)")
    with pytest.raises(ValueError) as error:
        symba.Detection("mug", [IDENTITY, IDENTITY], weights=[1.0])
    assert str(error.value) == (
        "weights: expected shape (2,), one weight per hypothesis, got shape "
        "(1,)")
    with pytest.raises(ValueError, match="^hypotheses: expected float64 numbers"):
        symba.Detection("mug", [["a"] * 7])
    with pytest.raises(ValueError) as error:
        symba.ClassPrior("round")
    assert str(error.value) == (
        'symmetry: unknown symmetry "round" (expected "asymmetric", '
        '"discrete" or "continuous")')


def test_import_bop_raises_the_importers_messages(source_dir, tmp_path):
    data = source_dir / "tests" / "data" / "bop"
    bad = tmp_path / "results.csv"
    bad.write_text("7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000\n")
    with pytest.raises(symba.Error, match=(
            f"^{bad}:1: expected 7 comma-separated fields "
            r"\(scene_id,im_id,obj_id,score,R,t,time\), got 6$")):
        symba.import_bop(str(bad), str(data / "scene_camera.json"))
    log = tmp_path / "out.jsonl"
    with pytest.raises(symba.Error, match="^options: a trajectory needs"):
        symba.import_bop_to_log(str(log), str(data / "results.csv"),
                                str(data / "scene_camera.json"),
                                trajectory=str(tmp_path / "t.tum"))
    assert not log.exists()
