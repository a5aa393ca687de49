#!/usr/bin/env python3
"""Calling overhead of the Python API: 10⁶ points projected by mire.calibration.Camera.project
(one call, numpy in and out) against the same projection in C++ (mire_bench_project, a loop
over Camera::project), in the same run. Prints both best-of-N times and their ratio.

    PYTHONPATH=build/python/module /usr/bin/python3 python/bench_project.py build/python/mire_bench_project
"""
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

import mire

ROOT = pathlib.Path(__file__).resolve().parents[1]
CAMERA = ROOT / "datasets" / "specs" / "reference_camera.yaml"
COUNT, REPEATS, ROUNDS = 1_000_000, 7, 5


def python_seconds(camera, points):
    best = float("inf")
    for _ in range(REPEATS):
        start = time.perf_counter()
        pixels = camera.project(points)
        best = min(best, time.perf_counter() - start)
    assert pixels.shape == (COUNT, 2) and np.isfinite(pixels).all()
    return best


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build" / "python" / "mire_bench_project")
    camera = mire.calibration.readCamera(CAMERA)
    rng = np.random.default_rng(1)
    z = rng.uniform(0.3, 2.0, COUNT)
    points = np.column_stack([rng.uniform(-0.55, 0.55, COUNT) * z, rng.uniform(-0.4, 0.4, COUNT) * z, z])
    # Interleaved rounds, the best time of each side: on a shared machine the minimum is the
    # least disturbed measurement of either.
    cpp = python = float("inf")
    for _ in range(ROUNDS):
        output = subprocess.run([binary, str(CAMERA), str(COUNT), str(REPEATS)], check=True, capture_output=True,
                                text=True).stdout
        cpp = min(cpp, float(re.search(r": ([0-9.]+) s", output).group(1)))
        python = min(python, python_seconds(camera, points))
    print(f"{COUNT} points, best of {ROUNDS}×{REPEATS}: C++ Camera::project loop {cpp * 1e3:.1f} ms, "
          f"Python Camera.project {python * 1e3:.1f} ms, ratio {python / cpp:.3f}")


if __name__ == "__main__":
    main()
