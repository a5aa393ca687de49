"""Shared fixtures: the `mire` binary (for CLI comparisons), the source tree, small simulated
campaigns written with `mire simulate` (rendered images with a known camera and known poses)."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import mire

SOURCE_DIR = pathlib.Path(os.environ.get("MIRE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SPECS = SOURCE_DIR / "datasets" / "specs"


def mire_binary():
    path = os.environ.get("MIRE_BINARY")
    if not path or not os.path.exists(path):
        pytest.skip("MIRE_BINARY (the built `mire` command) is not set: run the tests through ctest")
    return path


def run_cli(*args, cwd=None):
    """Runs `mire ARGS...`; returns its stdout, fails the test with stderr on a non-zero exit."""
    done = subprocess.run([mire_binary(), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, f"mire {' '.join(map(str, args))} exited {done.returncode}:\n{done.stderr}"
    return done.stdout


# The reference camera at a quarter of its size and a small chessboard: the spec of the C++
# test tests/apps/test_simulate.cpp.
TINY_SPEC = """%YAML:1.0
---
camera:
  image_width: 320
  image_height: 240
  camera_matrix: !!opencv-matrix
    rows: 3
    cols: 3
    dt: d
    data: [ 255.4, 0., 159.5, 0., 255.4, 119.5, 0., 0., 1. ]
  distortion_coefficients: !!opencv-matrix
    rows: 5
    cols: 1
    dt: d
    data: [ -0.30, 0.10, 4.0e-4, -3.0e-4, -0.015 ]
target: board.yaml
seed: 4
noise:
  gaussian_sigma: 2.0
"""
TINY_TRUTH = [255.4, 255.4, 159.5, 119.5, -0.30, 0.10, 4.0e-4, -3.0e-4, -0.015]
BOARD = "%YAML:1.0\n---\ntype: chessboard\ncols: 7\nrows: 5\nsquare_size_m: 0.025\n"


def write_tiny_spec(folder, extra):
    folder = pathlib.Path(folder)
    (folder / "board.yaml").write_text(BOARD)
    (folder / "spec.yaml").write_text(TINY_SPEC + extra)
    return folder / "spec.yaml"


@pytest.fixture(scope="session")
def tiny_calibration(tmp_path_factory):
    """12 rendered calibration views of the tiny camera (`mire simulate calibration`)."""
    folder = tmp_path_factory.mktemp("calibration")
    spec = write_tiny_spec(folder, "calibration:\n  views: 12\n  distance_m: [ 0.35, 0.5 ]\n  margin_px: 5\n")
    run_cli("simulate", "calibration", "--spec", spec, "-o", folder / "out")
    return folder / "out"


POSE_LIST = [("a1", [0.0, 0.0, 0.42], [0.0, 0.0, 0.0]),
             ("b2", [-0.02, -0.01, 0.45], [0.3, 0.1, 0.0]),
             ("c3", [0.015, 0.01, 0.40], [-0.2, 0.25, 0.3])]


@pytest.fixture(scope="session")
def tiny_poses(tmp_path_factory):
    """3 poses x 4 rendered images of the tiny camera (`mire simulate poses`), true cTm known."""
    folder = tmp_path_factory.mktemp("poses")
    rows = "".join(f"    - {{ id: \"{i}\", t: [ {t[0]}, {t[1]}, {t[2]} ], r: [ {r[0]}, {r[1]}, {r[2]} ] }}\n"
                   for i, t, r in POSE_LIST)
    spec = write_tiny_spec(folder, "poses:\n  images_per_pose: 4\n  list:\n" + rows)
    run_cli("simulate", "poses", "--spec", spec, "-o", folder / "out")
    return folder / "out"


def read_csv(path):
    """Rows of a CSV with '#' comment lines, as dicts of strings."""
    lines = [l for l in pathlib.Path(path).read_text().splitlines() if l and not l.startswith("#")]
    header = lines[0].split(",")
    return [dict(zip(header, l.split(","))) for l in lines[1:]]


def assert_relative(actual, expected, tolerance=1e-12, what=""):
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, what
    scale = np.maximum(np.abs(expected), np.finfo(float).tiny)
    error = np.max(np.abs(actual - expected) / scale) if actual.size else 0.0
    assert error <= tolerance, f"{what}: relative difference {error:.3g} > {tolerance:g}"
