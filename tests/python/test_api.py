"""The module's API on small inputs with exact expected values: the log
reader and writer, Keyframe/Detection construction, categorize, poses."""

import math

import numpy as np
import pytest

import symba

IDENTITY = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]


def yaw_pose(yaw, t):
    """[tx, ty, tz, qx, qy, qz, qw] of a rotation by `yaw` about z."""
    return [*t, 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)]


def test_reads_the_documented_example(source_dir):
    header, keyframes = symba.read_log(
        str(source_dir / "tests" / "data" / "example.jsonl"))
    assert header.version == 1
    assert (header.camera.fx, header.camera.fy, header.camera.cx,
            header.camera.cy) == (525.0, 525.0, 319.5, 239.5)
    assert sorted(header.classes) == ["bowl", "mug", "table"]
    table = header.classes["table"]
    assert (table.symmetry, table.order) == ("discrete", 2)
    np.testing.assert_array_equal(table.axis_o, [0.0, 0.0, 1.0])

    assert [k.id for k in keyframes] == [0, 1, 5]
    assert [k.timestamp for k in keyframes] == [0.0, 0.1, 0.5]
    first = keyframes[0]
    np.testing.assert_array_equal(first.T_wc, [0, 0, 1.2, 0, 0, 0, 1])
    assert first.odometry is None
    (table_detection,) = first.detections
    assert table_detection.id == "0/0"  # the default id
    assert table_detection.class_name == "table"
    assert table_detection.score == 0.92
    assert table_detection.sigma_t is None
    np.testing.assert_array_equal(table_detection.hypotheses,
                                  [[0.2, 0.1, 2.5, 0, 0, 0, 1],
                                   [0.2, 0.1, 2.5, 0, 0, 1, 0]])
    np.testing.assert_array_equal(table_detection.weights, [0.6, 0.4])
    np.testing.assert_array_equal(first.point_ids, [4031, 4032])
    assert first.point_ids.dtype == np.int64
    np.testing.assert_array_equal(first.point_uv,
                                  [[312.4, 208.9], [100.0, 50.5]])
    np.testing.assert_array_equal(first.point_depth, [2.31, 0.0])  # 0: none

    second = keyframes[1]
    assert second.T_wc is None
    assert (second.odometry.sigma_t, second.odometry.sigma_r) == (0.01, 0.005)
    bowl = second.detections[0]
    assert (bowl.id, bowl.sigma_t, bowl.sigma_r) == ("bowl-a", 0.05, 0.08)
    np.testing.assert_array_equal(bowl.hypotheses, [[-0.3, 0, 1.8, 0, 0, 0, 1]])

    # R form: a 90 degree turn about z, read back as a quaternion.
    s = math.sqrt(0.5)
    np.testing.assert_allclose(keyframes[2].T_wc, [0.1, 0, 1.2, 0, 0, s, s],
                               rtol=0, atol=1e-15)


def test_log_reader_iterates_and_reports_lines(source_dir):
    reader = symba.LogReader(
        str(source_dir / "tests" / "data" / "example.jsonl"))
    assert reader.header.camera.fx == 525.0
    ids_and_lines = [(k.id, reader.line) for k in reader]
    assert ids_and_lines == [(0, 2), (1, 4), (5, 5)]  # line 3 is blank
    assert list(reader) == []


def test_write_and_read_back_bit_for_bit(tmp_path):
    header = symba.LogHeader(
        camera=symba.PinholeIntrinsics(500.0, 501.0, 320.0, 240.0),
        classes={"table": symba.ClassPrior("discrete", 2, [0, 0, 1])})
    hyps = np.array([yaw_pose(0.1 * j, [0.3, -0.2, 2.0 + j / 3]) for j in range(4)])
    keyframes = [
        symba.Keyframe(0, 0.0, T_wc=yaw_pose(0.3, [1.0, 2.0, 0.5]),
                       detections=[symba.Detection("table", hyps,
                                                   weights=[1, 2, 3, 0.25],
                                                   sigma_t=0.04, score=0.5)],
                       point_ids=[7, 9], point_uv=[[1.5, 2.5], [3.0, 4.0]],
                       point_depth=[0.0, 2.75]),
        symba.Keyframe(3, 0.25,
                       odometry=symba.Odometry(yaw_pose(-0.2, [0.1, 0, 0]),
                                               sigma_t=0.02, sigma_r=0.03)),
    ]
    path = str(tmp_path / "log.jsonl")
    with symba.LogWriter(path, header) as writer:
        for keyframe in keyframes:
            writer.write(keyframe)
    read_header, read = symba.read_log(path)
    assert read_header.camera.fy == 501.0
    assert read_header.classes["table"].order == 2
    np.testing.assert_array_equal(read[0].T_wc, keyframes[0].T_wc)
    np.testing.assert_array_equal(read[0].detections[0].hypotheses, hyps)
    np.testing.assert_array_equal(read[0].detections[0].weights,
                                  [1, 2, 3, 0.25])
    assert read[0].detections[0].id == "0/0"  # the reader's default id
    assert read[0].detections[0].sigma_t == 0.04
    assert read[0].detections[0].sigma_r is None
    assert read[0].detections[0].score == 0.5
    np.testing.assert_array_equal(read[0].point_depth, [0.0, 2.75])
    np.testing.assert_array_equal(read[1].odometry.T_prev_cur,
                                  keyframes[1].odometry.T_prev_cur)
    assert read[1].T_wc is None

    # write_log gives the same bytes.
    symba.write_log(str(tmp_path / "again.jsonl"), header, keyframes)
    assert ((tmp_path / "again.jsonl").read_bytes() ==
            (tmp_path / "log.jsonl").read_bytes())


def test_matrices_and_vectors_give_the_same_poses():
    poses = np.array([yaw_pose(a, [a, 2 * a, -a]) for a in (0.0, 0.5, 3.0)])
    matrices = symba.pose_matrices(poses)
    assert matrices.shape == (3, 4, 4)
    np.testing.assert_allclose(matrices[1, :3, :3],
                               [[math.cos(0.5), -math.sin(0.5), 0],
                                [math.sin(0.5), math.cos(0.5), 0],
                                [0, 0, 1]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(symba.pose_vectors(matrices), poses,
                               rtol=0, atol=1e-15)
    from_matrices = symba.Detection("mug", matrices)
    np.testing.assert_allclose(from_matrices.hypotheses, poses, rtol=0,
                               atol=1e-15)
    keyframe = symba.Keyframe(0, 0.0, T_wc=matrices[2])
    np.testing.assert_allclose(keyframe.T_wc, poses[2], rtol=0, atol=1e-15)


def test_lists_and_strided_views_are_accepted():
    poses = np.array([yaw_pose(0.1 * j, [0, 0, 2]) for j in range(6)])
    as_list = symba.Detection("mug", poses.tolist())
    every_other = symba.Detection("mug", poses[::2])  # a view, not copied
    np.testing.assert_array_equal(as_list.hypotheses, poses)
    np.testing.assert_array_equal(every_other.hypotheses, poses[::2])
    columns = np.asfortranarray(poses)
    np.testing.assert_array_equal(symba.Detection("mug", columns).hypotheses,
                                  poses)


def test_output_arrays_own_their_buffer_without_a_copy():
    backend = symba.Backend()
    backend.add_keyframe(symba.Keyframe(0, 0.0, T_wc=IDENTITY))
    trajectory = backend.keyframes()
    # The arrays wrap the C++ vectors they were built in (base: a capsule).
    assert not trajectory.poses.flags.owndata
    assert type(trajectory.poses.base).__name__ == "PyCapsule"
    assert trajectory.poses.shape == (1, 7)
    assert trajectory.ids.dtype == np.int64


def test_categorize_a_two_fold_table():
    # The embedding example's table (docs/backend.md): two modes half a
    # turn apart, six hypotheses each.
    hyps = [yaw_pose((j % 2) * math.pi + 0.01 * (j // 2), [0, 0, 2])
            for j in range(12)]
    result = symba.categorize(np.array(hyps))
    assert result.type == "discrete"
    assert result.reference == 0
    assert len(result.clusters) == 2
    assert result.clusters[0].theta == 0.0
    assert abs(abs(result.clusters[1].theta) - math.pi) < 1e-9
    np.testing.assert_array_equal(result.clusters[0].members, [0, 2, 4, 6, 8, 10])
    np.testing.assert_array_equal(result.clusters[1].members, [1, 3, 5, 7, 9, 11])
    np.testing.assert_array_equal(result.inliers, np.arange(12))
    assert abs(abs(result.axis_o[2]) - 1.0) < 1e-9
    np.testing.assert_allclose(result.t_co, [0, 0, 2], rtol=0, atol=1e-12)
    assert result.twist.shape == (12,)

    single = symba.categorize(np.array([IDENTITY]))
    assert single.type == "asymmetric"


def test_backend_options_are_attributes_with_the_cpp_defaults():
    options = symba.BackendOptions()
    assert options.method == "symba"
    assert options.window_size == 10
    assert options.window_policy == "marginalize"
    assert options.chain_prior == "conditional"
    assert options.object_loss == "cauchy"
    assert options.confirm_keyframes == 5
    assert options.categorization.min_points == 3
    assert options.mixture.use_null_hypothesis is False
    options.mixture.use_null_hypothesis = True  # nested options by reference
    assert options.mixture.use_null_hypothesis is True
    tuned = symba.BackendOptions(method="sh", window_size=4,
                                 window_policy="drop")
    assert (tuned.method, tuned.window_size, tuned.window_policy) == (
        "sh", 4, "drop")
    backend = symba.Backend(tuned)
    assert backend.options.window_size == 4


def test_parse_class_prior():
    name, prior = symba.parse_class_prior("table=discrete:4:0,0,2")
    assert name == "table"
    assert (prior.symmetry, prior.order) == ("discrete", 4)
    np.testing.assert_array_equal(prior.axis_o, [0, 0, 2])
