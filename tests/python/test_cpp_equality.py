"""The same sequence gives the same result through Python as through C++."""

import json
import pickle

import numpy as np
import pytest

import symba


def read_tum(path):
    rows = np.loadtxt(path, ndmin=2)
    return rows[:, 0], rows[:, 1:]  # timestamps, [tx ty tz qx qy qz qw]


def read_associations(path):
    lines = path.read_text().splitlines()
    assert lines[0] == "keyframe,detection,object,symmetry"
    return [tuple(line.split(",")) for line in lines[1:]]


def test_replay_matches_the_cli(simulated_log, cli, tmp_path):
    out = tmp_path / "out"
    cli("replay", simulated_log, "--out", out, "--quiet")
    times, poses = read_tum(out / "trajectory.tum")

    result = symba.replay(str(simulated_log))

    assert len(result.trajectory) == 24
    np.testing.assert_allclose(result.trajectory.timestamps, times,
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(result.trajectory.poses, poses,
                               rtol=0, atol=1e-9)
    objects = json.loads((out / "objects.json").read_text())["objects"]
    assert len(objects) == len(result.objects) > 0
    discrete = 0
    for expected, got in zip(objects, result.objects):
        assert got.id == expected["id"]
        assert got.class_name == expected["class"]
        assert got.symmetry == expected["symmetry"]
        assert got.observations == expected["observations"]
        np.testing.assert_allclose(got.t_wo, expected["t"], rtol=0, atol=1e-9)
        expected_poses = [p["t"] + p["q"] for p in expected["poses"]]
        np.testing.assert_allclose(got.poses, expected_poses, rtol=0,
                                   atol=1e-9)
        # Every object of this run is covered (docs/backend.md,
        # Covariances), the same in objects.json (6 significant digits) and
        # Python.
        assert got.covariance is not None
        position = got.covariance["position"]
        np.testing.assert_allclose(position, expected["position_covariance"],
                                   rtol=1e-5, atol=0)
        np.testing.assert_array_equal(position, position.T)
        assert np.all(np.linalg.eigvalsh(position) > 0)
        assert got.covariance["source"] == expected["covariance_source"]
        if got.symmetry == "discrete":
            discrete += 1
            np.testing.assert_array_equal(got.angle_evidence,
                                          expected["angle_evidence"])
            np.testing.assert_array_equal(got.angle_probabilities,
                                          expected["angle_probabilities"])
            assert got.angle_probabilities.sum() == pytest.approx(1.0)
        else:
            assert got.angle_evidence.size == 0
    assert discrete > 0  # the disc scene's table
    expected_rows = read_associations(out / "associations.csv")
    got_rows = [(str(a.keyframe), a.detection, str(a.object), a.symmetry)
                for a in result.assignments]
    assert got_rows == expected_rows


def test_backend_keyframe_by_keyframe_matches_replay(simulated_log):
    header, keyframes = symba.read_log(str(simulated_log))
    backend = symba.Backend(intrinsics=header.camera,
                            class_priors=header.classes)
    for keyframe in keyframes:
        assignments = backend.add_keyframe(keyframe)
        assert [a.detection for a in assignments] == [
            d.id for d in keyframe.detections]
        backend.optimize_window()

    result = symba.replay(str(simulated_log))
    trajectory = backend.keyframes()
    np.testing.assert_array_equal(trajectory.ids, result.trajectory.ids)
    np.testing.assert_array_equal(trajectory.poses, result.trajectory.poses)
    assert [o.id for o in backend.objects()] == [
        o.id for o in result.objects]
    assert all(o.covariance is None for o in backend.objects())
    covariances = backend.object_covariances()
    assert [c["id"] for c in covariances] == [o.id for o in result.objects]
    # Equal up to round-off: Ceres orders a covariance's blocks by address.
    for c, o in zip(covariances, result.objects):
        np.testing.assert_allclose(c["position"], o.covariance["position"],
                                   rtol=1e-9, atol=0)
    np.testing.assert_array_equal(backend.keyframe(keyframes[-1].id),
                                  trajectory.poses[-1])
    assert backend.keyframe(10**9) is None
    stats = backend.statistics()
    assert stats.keyframes == 24
    assert stats.solves == 24


def test_covariance_noise_is_what_the_covariances_used(simulated_log, cli,
                                                       tmp_path):
    header, keyframes = symba.read_log(str(simulated_log))

    def run(calibrate):
        options = symba.BackendOptions()
        options.calibrate_covariances = calibrate
        backend = symba.Backend(options, intrinsics=header.camera,
                                class_priors=header.classes)
        for keyframe in keyframes:
            backend.add_keyframe(keyframe)
            backend.optimize_window()
        assert backend.covariance_noise() == []  # none computed yet
        return backend, backend.object_covariances()

    calibrated, with_factors = run(True)
    groups = calibrated.covariance_noise()
    assert any(g.name.startswith("motion ") for g in groups)
    assert any(g.name.startswith("detections ") for g in groups)
    for g in groups:
        assert g.edges >= g.residuals >= 0
        assert g.factor_t > 0 and g.factor_r > 0
        assert 0 <= g.correlation_t <= 0.98
        # A group the residuals may not show better than stated: at least 1.
        if not g.held_by_others:
            assert g.factor_t >= 1 and g.factor_r >= 1
    # The replay reports the same groups (summary.json covariances.noise).
    out = tmp_path / "out"
    cli("replay", simulated_log, "--out", out, "--quiet")
    with open(out / "summary.json") as f:
        reported = json.load(f)["covariances"]["noise"]
    assert [r["name"] for r in reported] == [g.name for g in groups]
    for r, g in zip(reported, groups):
        assert r["held_by_others"] == g.held_by_others
        assert r["edges"] == g.edges and r["residuals"] == g.residuals
        for key in ("residual_t", "residual_r", "correlation_t",
                    "correlation_r", "factor_t", "factor_r"):
            assert r[key] == pytest.approx(getattr(g, key), rel=1e-9), key
    stated, as_stated = run(False)
    assert stated.covariance_noise() == []
    assert [c["id"] for c in as_stated] == [c["id"] for c in with_factors]
    assert any(not np.allclose(a["position"], b["position"])
               for a, b in zip(as_stated, with_factors))


def test_batch_replay_matches_the_cli(simulated_log, cli, tmp_path):
    out = tmp_path / "out"
    cli("replay", simulated_log, "--out", out, "--quiet", "--mode", "batch",
        "--method", "mh")
    _, poses = read_tum(out / "trajectory.tum")
    result = symba.replay(str(simulated_log),
                          symba.BackendOptions(method="mh"), mode="batch")
    np.testing.assert_allclose(result.trajectory.poses, poses, rtol=0,
                               atol=1e-9)


def test_final_batch_replay_matches_the_cli(simulated_log, cli, tmp_path):
    out = tmp_path / "out"
    cli("replay", simulated_log, "--out", out, "--quiet", "--final-batch")
    times, poses = read_tum(out / "trajectory.tum")
    result = symba.replay(str(simulated_log), final_batch=True)
    np.testing.assert_allclose(result.trajectory.timestamps, times, rtol=0,
                               atol=1e-9)
    np.testing.assert_allclose(result.trajectory.poses, poses, rtol=0,
                               atol=1e-9)
    objects = json.loads((out / "objects.json").read_text())["objects"]
    assert [o.id for o in result.objects] == [o["id"] for o in objects]
    for expected, got in zip(objects, result.objects):
        np.testing.assert_allclose(got.t_wo, expected["t"], rtol=0, atol=1e-9)
    # The batch solve moved the window's trajectory: the flag was used.
    window = symba.replay(str(simulated_log))
    assert np.abs(window.trajectory.poses - result.trajectory.poses).max() > 1e-6


def test_simulate_matches_the_cli(cli, tmp_path):
    cli("simulate", "--scene", "cts", "--seed", "5", "--keyframes", "6",
        "--out", tmp_path / "cli", "--quiet")
    simulation = symba.simulate("cts", seed=5, num_keyframes=6)
    # The command converts its angle options from degrees, so its options
    # can differ from the library's defaults in the last bit: compare to
    # 1e-9, not byte for byte.
    _, expected = symba.read_log(str(tmp_path / "cli" / "log.jsonl"))
    assert [k.id for k in simulation.keyframes] == [k.id for k in expected]
    for got, want in zip(simulation.keyframes, expected):
        np.testing.assert_allclose(got.T_wc, want.T_wc, rtol=0, atol=1e-9)
        assert [d.id for d in got.detections] == [d.id for d in want.detections]
        for d_got, d_want in zip(got.detections, want.detections):
            np.testing.assert_allclose(d_got.hypotheses, d_want.hypotheses,
                                       rtol=0, atol=1e-9)
        np.testing.assert_array_equal(got.point_ids, want.point_ids)
        np.testing.assert_allclose(got.point_uv, want.point_uv, rtol=0,
                                   atol=1e-9)
    _, true_poses = read_tum(tmp_path / "cli" / "gt_trajectory.tum")
    np.testing.assert_allclose(simulation.true_poses, true_poses, rtol=0,
                               atol=1e-9)
    assert len(simulation.objects) > 0


def test_import_tum_matches_the_cli(source_dir, cli, tmp_path):
    seq = source_dir / "data" / "real" / "ycbv" / "0001"
    objects = [("003_cracker_box", seq / "dope_003_cracker_box_T_co.txt"),
               ("004_sugar_box", seq / "dope_004_sugar_box_T_co.txt")]
    cli("import", "tum", "--trajectory", seq / "orbslam3_T_wc.txt",
        "--object", f"{objects[0][0]}={objects[0][1]}",
        "--object", f"{objects[1][0]}={objects[1][1]}",
        "--first-pose", seq / "gt_T_wc.txt", "--out", tmp_path / "cli.jsonl")
    counts = symba.import_tum_to_log(
        str(tmp_path / "py.jsonl"), str(seq / "orbslam3_T_wc.txt"),
        [(name, str(path)) for name, path in objects],
        first_pose=str(seq / "gt_T_wc.txt"))
    # ceil(1111 / 5) keyframes, as in the CLI test (tests/CMakeLists.txt).
    assert counts == (223, 255)
    assert ((tmp_path / "py.jsonl").read_bytes() ==
            (tmp_path / "cli.jsonl").read_bytes())

    header, keyframes = symba.import_tum(
        str(seq / "orbslam3_T_wc.txt"),
        [(name, str(path)) for name, path in objects],
        first_pose=str(seq / "gt_T_wc.txt"))
    assert len(keyframes) == 223
    assert header.camera is None
    assert keyframes[0].T_wc is not None and keyframes[1].T_wc is None
    assert keyframes[1].odometry.sigma_t == 0.005
    assert keyframes[1].odometry.sigma_r == 0.01


def test_import_bop_matches_the_cli(source_dir, cli, tmp_path):
    data = source_dir / "tests" / "data" / "bop"
    files = {"results": str(data / "results.csv"),
             "scene_camera": str(data / "scene_camera.json"),
             "models_info": str(data / "models_info.json")}
    cli("import", "bop", "--results", files["results"], "--scene-camera",
        files["scene_camera"], "--models-info", files["models_info"],
        "--class-names", "1=table,2=mug", "--out", tmp_path / "cli.jsonl")
    names = {1: "table", 2: "mug"}
    report = symba.import_bop_to_log(str(tmp_path / "py.jsonl"),
                                     class_names=names, **files)
    # The worked example's counts (docs/import.md, tests/CMakeLists.txt).
    assert (report.keyframes, report.detections, report.rows) == (8, 16, 17)
    assert (report.skipped_images, report.skipped_rows) == (0, 0)
    assert report.symmetry_notes == []
    assert ((tmp_path / "py.jsonl").read_bytes() ==
            (tmp_path / "cli.jsonl").read_bytes())

    header, keyframes, report = symba.import_bop(class_names=names, **files)
    assert report.detections == 16
    assert [k.id for k in keyframes] == list(range(8))
    assert header.bop.scene_id == 7
    assert header.bop.obj_ids == {"mug": 2, "table": 1}
    table = header.classes["table"]
    assert (table.symmetry, table.order) == ("discrete", 2)
    assert header.classes["mug"].symmetry == "continuous"
    assert keyframes[0].detections[0].id == "0/0"
    # The header's bop key survives a write and a read.
    symba.write_log(str(tmp_path / "again.jsonl"), header, keyframes)
    assert ((tmp_path / "again.jsonl").read_bytes() ==
            (tmp_path / "cli.jsonl").read_bytes())


def test_maps_save_load_and_match_the_cli(simulated_log, cli, tmp_path):
    """Backend.save_map gives the text `symba replay --map-out` writes (up to
    the covariances' round-off); a backend loaded from it holds the same
    objects; replay(map_in=, map_out=) is --map-in/--map-out; a malformed
    map raises symba.Error naming the file and member."""
    header, keyframes = symba.read_log(str(simulated_log))
    backend = symba.Backend(intrinsics=header.camera,
                            class_priors=header.classes)
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()
    path = tmp_path / "map.json"
    text = backend.save_map(str(path))
    assert path.read_text() == text
    cli("replay", simulated_log, "--out", tmp_path / "out", "--quiet",
        "--map-out", tmp_path / "cli_map.json")
    ours, theirs = json.loads(text), json.loads(
        (tmp_path / "cli_map.json").read_text())
    assert ours["format"] == "symba-map" and ours["version"] == 1
    assert [o["id"] for o in ours["objects"]] == [
        o["id"] for o in theirs["objects"]]
    for a, b in zip(ours["objects"], theirs["objects"]):
        assert a["t"] == b["t"]
        np.testing.assert_allclose(a["position_covariance"],
                                   b["position_covariance"], rtol=1e-5)

    loaded = symba.Backend(intrinsics=header.camera,
                           class_priors=header.classes)
    loaded.load_map(str(path))
    assert [(o.id, o.class_name) for o in loaded.objects()] == [
        (o.id, o.class_name) for o in backend.objects()]
    for a, b in zip(loaded.objects(), backend.objects()):
        np.testing.assert_array_equal(a.t_wo, b.t_wo)
    also = symba.Backend(intrinsics=header.camera)
    also.load_map(text=text)
    assert len(also.objects()) == len(backend.objects())
    with pytest.raises(symba.Error, match="before the first keyframe"):
        loaded.add_keyframe(keyframes[0])
        loaded.load_map(str(path))

    result = symba.replay(str(simulated_log), map_in=str(path),
                          map_out=str(tmp_path / "again.json"))
    assert {o.id for o in result.objects} >= {
        o.id for o in backend.objects()}
    assert json.loads((tmp_path / "again.json").read_text())["objects"]

    bad = tmp_path / "bad.json"
    bad.write_text(text.replace('"symba-map"', '"symba-log"'))
    with pytest.raises(symba.Error, match=r"bad\.json: format: expected"):
        symba.Backend().load_map(str(bad))
    with pytest.raises(ValueError, match="exactly one of path and text"):
        symba.Backend().load_map()


def pose_matrix(pose):
    """[tx, ty, tz, qx, qy, qz, qw] as a 4 x 4 matrix."""
    x, y, z, w = pose[3:]
    R = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = pose[:3]
    return T


def test_relocalization_through_python(cli, tmp_path):
    """A run through the room (seed 4) relocalises against the map of
    another run (seed 3), through Backend.load_map(relocalize=True) and
    replay(relocalize=True) alike, and says where."""
    for seed in (3, 4):
        cli("simulate", "--scene", "room", "--seed", seed, "--keyframes",
            "20", "--out", tmp_path / f"room{seed}", "--quiet")
    first = str(tmp_path / "room3" / "log.jsonl")
    second = str(tmp_path / "room4" / "log.jsonl")
    map_path = str(tmp_path / "map.json")
    symba.replay(first, map_out=map_path)

    header, keyframes = symba.read_log(second)
    # The second run's poses in a frame of its own: x_run = T_run_w x_w,
    # turned 1 rad about z and moved (3, -2, 0) m.
    c, s = np.cos(1.0), np.sin(1.0)
    T_run_w = np.array([[c, -s, 0, 3], [s, c, 0, -2], [0, 0, 1, 0],
                        [0, 0, 0, 1.0]])
    for keyframe in keyframes:
        if keyframe.T_wc is not None:
            keyframe.T_wc = T_run_w @ pose_matrix(keyframe.T_wc)
    backend = symba.Backend(intrinsics=header.camera,
                            class_priors=header.classes)
    backend.load_map(map_path, relocalize=True)
    assert backend.relocalization().state == "searching"
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()
    report = backend.relocalization()
    assert report.state == "relocalized"
    assert len(report.correspondences) >= 3
    assert report.keyframe is not None
    map_ids = {o["id"] for o in json.load(open(map_path))["objects"]}
    assert {m for _, m in report.correspondences} <= map_ids
    # T_map_run is T_run_w's inverse (the map's frame is the world here).
    found = pose_matrix(report.T_map_run)
    np.testing.assert_allclose(found @ T_run_w, np.eye(4), atol=0.05)

    # Pickled while it searches, the copy relocalises where the original
    # did, on the same objects (test_pickle.py has the rest).
    searching = symba.Backend(intrinsics=header.camera,
                              class_priors=header.classes)
    searching.load_map(map_path, relocalize=True)
    for keyframe in keyframes[:2]:
        searching.add_keyframe(keyframe)
        searching.optimize_window()
    copied = pickle.loads(pickle.dumps(searching))
    assert copied.relocalization().state == "searching"
    for keyframe in keyframes[2:]:
        copied.add_keyframe(keyframe)
        copied.optimize_window()
    again = copied.relocalization()
    assert (again.state, again.keyframe) == (report.state, report.keyframe)
    assert again.correspondences == report.correspondences
    np.testing.assert_array_equal(copied.keyframes().poses,
                                  backend.keyframes().poses)

    result = symba.replay(second, map_in=map_path, relocalize=True)
    assert result.relocalization.state == "relocalized"
    assert result.relocalization.keyframe == report.keyframe
    assert symba.replay(second).relocalization is None
    with pytest.raises(ValueError, match="needs map_in"):
        symba.replay(second, relocalize=True)


def noise_as_summary(noise):
    """Backend.noise() / ReplayResult.noise in summary.json's layout."""
    def samples(s):
        return {"levels": s.levels, "increments": s.increments,
                "sigma_level": s.sigma_level,
                "sigma_increment": s.sigma_increment,
                "correlation": s.correlation, "inflation": s.inflation}
    return [{"class": c.class_name, "sigma_t": c.sigma_t,
             "sigma_r": c.sigma_r, "weight_sigma_t": c.weight_sigma_t,
             "weight_sigma_r": c.weight_sigma_r,
             "translation": samples(c.translation),
             "rotation": samples(c.rotation),
             "hypothesis_scatter": {"detections": c.scatter.detections,
                                    "sigma_t": c.scatter.sigma_t,
                                    "sigma_r": c.scatter.sigma_r},
             "claims": {"translation_samples": c.claims.translation_samples,
                        "rotation_samples": c.claims.rotation_samples,
                        "scale_t": c.claims.scale_t,
                        "scale_r": c.claims.scale_r,
                        "factor_t": c.claims.factor_t,
                        "factor_r": c.claims.factor_r},
             "track_ratio": c.track_ratio,
             "weights": {"declared": c.weights.declared,
                         "scatter": c.weights.scatter,
                         "unstated": c.weights.unstated,
                         "sigma_t": c.weights.sigma_t,
                         "sigma_r": c.weights.sigma_r}}
            for c in noise]


def motion_as_summary(motion):
    return {"odometry": {"steps": motion.odometry_steps,
                         "sigma_t": motion.odometry_sigma_t,
                         "sigma_r": motion.odometry_sigma_r},
            "frontend_poses": {"steps": motion.frontend_steps,
                               "sigma_t": motion.frontend_sigma_t,
                               "sigma_r": motion.frontend_sigma_r},
            "claims": [{"stated_sigma_t": g.stated_sigma_t,
                        "stated_sigma_r": g.stated_sigma_r,
                        "pairs": g.pairs, "scale": g.scale,
                        "factor": g.factor} for g in motion.claims]}


def test_noise_matches_the_summary(cli, tmp_path):
    # A detector that declares no noise: the backend weighs the table by
    # its hypotheses' scatter and estimates the class's noise
    # (docs/backend.md, Real detectors); summary.json writes full precision.
    cli("simulate", "--scene", "disc", "--seed", "3", "--keyframes", "40",
        "--declare-noise", "false", "--out", tmp_path / "sim", "--quiet")
    log = tmp_path / "sim" / "log.jsonl"
    cli("replay", log, "--out", tmp_path / "out", "--quiet")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())

    result = symba.replay(str(log))
    assert noise_as_summary(result.noise) == summary["noise"]
    assert motion_as_summary(result.motion) == summary["motion"]
    table = result.noise[0]
    assert table.class_name == "table"
    assert table.sigma_t is not None and table.sigma_t > 0
    assert table.scatter.detections > 0
    assert table.claims.scale_t is None  # nothing declared, nothing tested
    # Its edges use the scatter, not weight_sigma_t (which a detection
    # stating neither would get).
    assert table.weights.scatter > 0
    assert table.weights.declared == table.weights.unstated == 0
    assert table.weights.sigma_t < 0.1 < table.weight_sigma_t
    assert "track_ratio" in repr(table) and "EdgeWeights" in repr(table)
    assert result.motion.odometry_steps == 39
    assert result.motion.odometry_sigma_t == 0.01
    assert len(result.motion.claims) == 2  # rich and featureless steps

    header, keyframes = symba.read_log(str(log))
    backend = symba.Backend(intrinsics=header.camera,
                            class_priors=header.classes)
    assert backend.noise() == []  # no detection yet
    assert backend.motion_noise().odometry_steps == 0
    for keyframe in keyframes:
        backend.add_keyframe(keyframe)
        backend.optimize_window()
    assert noise_as_summary(backend.noise()) == summary["noise"]
    assert motion_as_summary(backend.motion_noise()) == summary["motion"]
    # Without estimate_noise there is nothing to report per class.
    plain = symba.replay(str(log), symba.BackendOptions(estimate_noise=False))
    assert plain.noise == []
