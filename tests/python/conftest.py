"""Shared fixtures of the Python tests. ctest sets PYTHONPATH to the build
tree's python/ directory, SYMBA_CLI to the `symba` command of the same build
and SYMBA_SOURCE_DIR to the repository (tests/python/CMakeLists.txt)."""

import os
import pathlib
import subprocess

import pytest


def _env(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"{name} is not set; run these tests through ctest "
                    "(ctest --test-dir build -R python)")
    return value


@pytest.fixture(scope="session")
def source_dir():
    return pathlib.Path(_env("SYMBA_SOURCE_DIR"))


@pytest.fixture(scope="session")
def cli():
    """Runs the C++ `symba` command; fails the test on a non-zero exit."""
    binary = _env("SYMBA_CLI")

    def run(*args):
        result = subprocess.run([binary, *map(str, args)],
                                capture_output=True, text=True)
        if result.returncode != 0:
            pytest.fail(f"symba {' '.join(map(str, args))} exited "
                        f"{result.returncode}: {result.stderr}")
        return result

    return run


@pytest.fixture(scope="session")
def simulated_log(tmp_path_factory, cli):
    """A small simulated sequence written by the C++ command: the disc
    scene (discrete and other objects, points, a drifting front end),
    seed 3, 24 keyframes."""
    out = tmp_path_factory.mktemp("sim") / "disc"
    cli("simulate", "--scene", "disc", "--seed", "3", "--keyframes", "24",
        "--out", out, "--quiet")
    return out / "log.jsonl"
