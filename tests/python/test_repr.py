"""Every result type has a readable repr (its name and what its attributes
give; arrays and lists longer than 7 by their size), and the README's
Python snippet runs as printed."""

import contextlib
import inspect
import io
import math
import re

import numpy as np

import symba

# Classes that are not results: a live backend, the log streams and the
# option sets (their attributes are documented in docs/python.md).
WITHOUT_REPR = {"Backend", "LogReader", "LogWriter", "BackendOptions",
                "CategorizationOptions", "MixtureOptions"}


def test_every_result_class_defines_a_repr():
    without = {name for name, cls in
               inspect.getmembers(symba._symba, inspect.isclass)
               if not issubclass(cls, Exception) and
               "__repr__" not in vars(cls)}
    assert without == WITHOUT_REPR


def test_replay_results(source_dir):
    result = symba.replay(str(source_dir / "tests/data/replay/table.jsonl"),
                          symba.BackendOptions(confirm_keyframes=1))
    assert re.fullmatch(r"ReplayResult\(4 keyframes, 1 map object, "
                        r"4 assignments, seconds=[0-9.e-]+\)", repr(result))
    assert repr(result.trajectory) == (
        "Trajectory(ids=[0, 1, 2, 3], timestamps=[0.0, 0.1, 0.2, "
        "0.30000000000000004], poses=<array (4, 7) float64>)")
    assert re.fullmatch(
        r"BackendStatistics\(keyframes=4, detections=4, objects=1, points=2, "
        r"object_upgrades=0, objects_turned=0, objects_dropped=0, rotation_outliers=0, "
        r"folded_angles=0, marginalized_keyframes=0, "
        r"ambiguous_edges_dropped=0, solves=4, solve_seconds=[0-9.e-]+, "
        r"solve_iterations=4, loop_closures=0, object_loop_closures=0, "
        r"objects_merged=0, revisits_moved_past=0\)", repr(result.statistics))
    assert re.fullmatch(
        r"SolveReport\(iterations=1, initial_cost=[0-9.e-]+, "
        r"final_cost=[0-9.e-]+, seconds=[0-9.e-]+, converged=True, "
        r"free_keyframes=3, residual_blocks=27, parameter_blocks=14, "
        r"prior_size=0\)", repr(result.last_solve))
    assert repr(result.header) == (
        "LogHeader(version=1, camera=PinholeIntrinsics(fx=500.0, fy=500.0, "
        "cx=320.0, cy=240.0), classes={'table': ClassPrior("
        "symmetry='discrete', order=2)}, bop=None)")
    assert repr(result.objects) == (
        "[MapObject(id=0, class_name='table', symmetry='discrete', "
        "observations=4)]")
    assert repr(result.assignments[1]) == (
        "Assignment(keyframe=1, detection='1/0', object=0, "
        "symmetry='discrete')")


def test_categorization_results():
    # Two modes half a turn apart about z (test_api's two-fold table).
    hyps = [[0, 0, 2, 0, 0, math.sin(((j % 2) * math.pi + 0.01 * (j // 2)) / 2),
             math.cos(((j % 2) * math.pi + 0.01 * (j // 2)) / 2)]
            for j in range(12)]
    result = symba.categorize(np.array(hyps))
    assert repr(result) == "Categorization(type='discrete', 2 clusters, 12 inliers)"
    assert re.fullmatch(r"AngleCluster\(theta=0\.0, spread=[0-9.e-]+, "
                        r"weight=6\.0, members=\[0, 2, 4, 6, 8, 10\]\)",
                        repr(result.clusters[0]))
    single = symba.categorize([[0, 0, 1, 0, 0, 0, 1]])
    assert repr(single.diagnostics) == (
        "CategorizationDiagnostics(passes=1, axis_support=0.0, "
        "num_axis_inliers=0, num_raw_clusters=0, num_noise=0, "
        "max_cluster_extent=0.0, min_cluster_separation=0.0, "
        "empty_fraction=0.0, prior_axis_used=False, "
        "prior_order_snapped=False, prior_type_used=False)")


def test_input_and_simulation_results():
    odometry = symba.Odometry([0.1, 0, 0, 0, 0, 0, 1.0])
    assert repr(odometry) == ("Odometry(T_prev_cur=[0.1, 0.0, 0.0, 0.0, 0.0, "
                              "0.0, 1.0], sigma_t=0.01, sigma_r=0.005)")
    simulation = symba.simulate("disc", seed=0, num_keyframes=6)
    assert repr(simulation) == (
        "Simulation(scene='disc', seed=0, 6 keyframes, 1 objects)")
    assert repr(simulation.objects[0]).startswith(
        "SimulatedObject(class_name='table', symmetry='discrete', order=2, "
        "axis_o=[0.0, 0.0, 1.0], T_wo=[")


def test_import_report(source_dir):
    data = source_dir / "tests" / "data" / "bop"
    _, _, report = symba.import_bop(
        results=str(data / "results.csv"),
        scene_camera=str(data / "scene_camera.json"),
        models_info=str(data / "models_info.json"),
        class_names={1: "table", 2: "mug"})
    assert repr(report) == (
        "BopImportReport(rows=17, keyframes=8, detections=16, "
        "skipped_images=0, skipped_rows=0, other_scene_rows=0, "
        "symmetry_notes=[])")


def test_the_readme_python_snippet_runs(source_dir):
    text = (source_dir / "README.md").read_text()
    code = re.search(r"```python\n(.*?)\n```", text, re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "README.md", "exec"), {})
    lines = out.getvalue().splitlines()
    assert re.fullmatch(
        r"SolveReport\(iterations=1, initial_cost=0\.0, final_cost=0\.0, "
        r"seconds=[0-9.e-]+, converged=True, free_keyframes=1, "
        r"residual_blocks=1, parameter_blocks=4, prior_size=0\)", lines[0])
    assert lines[1] == ("Trajectory(ids=[0, 1], timestamps=[0.0, 0.1], "
                        "poses=<array (2, 7) float64>)")
    assert len(lines) == 2
