"""Calibration: synthetic views of a known camera (truth within the reported σ), rendered
images (`mire simulate calibration`), and equality with `mire calibrate` on those images."""
import numpy as np
import pytest

import mire
from conftest import TINY_TRUTH, assert_relative, run_cli

cal = mire.calibration
met = mire.metrology


def rotation(rvec):
    angle = np.linalg.norm(rvec)
    if angle == 0:
        return np.eye(3)
    k = np.asarray(rvec) / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def synthetic_views(camera, board, count, noise_px, seed):
    """Views of the board from random poses, projected by the true camera, plus Gaussian noise."""
    rng = np.random.default_rng(seed)
    centre = board.mean(axis=0)
    views = []
    for v in range(count):
        r = rotation(rng.uniform(-0.5, 0.5, 3) * [1, 1, 0.6])
        t = np.array([rng.uniform(-0.05, 0.05), rng.uniform(-0.04, 0.04), rng.uniform(0.35, 0.6)]) - r @ centre
        pixels = camera.project(board @ r.T + t)
        inside = (pixels[:, 0] > 0) & (pixels[:, 0] < camera.width - 1) & (pixels[:, 1] > 0) & (pixels[:, 1] < camera.height - 1)
        ids = np.flatnonzero(inside)
        noisy = pixels[ids] + rng.normal(0, noise_px, (len(ids), 2))
        views.append(cal.CalibrationView(f"view_{v:02d}", ids.tolist(), noisy))
    return views


@pytest.fixture(scope="module")
def synthetic():
    truth = cal.cameraFromOpenCV(640, 480, 520.0, 518.0, 322.0, 241.0, [-0.28, 0.09, 5e-4, -4e-4, -0.012])
    spec = met.TargetSpec()
    spec.type, spec.cols, spec.rows, spec.square_size_m = met.TargetType.Chessboard, 9, 6, 0.03
    board = met.Target(spec).points()
    views = synthetic_views(truth, board, 20, 0.1, seed=7)
    result = cal.calibrateCamera(board, views, 640, 480)
    return truth, board, views, result


def test_synthetic_calibration_recovers_the_truth_within_its_sigma(synthetic):
    truth, _, _, result = synthetic
    estimate = np.array(result.camera.params)
    sigma = np.array(result.camera.sigmas())
    assert result.used_views == 20
    assert sigma.shape == (9,) and (sigma > 0).all()
    assert np.all(np.abs(estimate - truth.params) < 4 * sigma), (estimate - truth.params) / sigma
    assert abs(estimate[0] - 520.0) < 1.0
    # The pixel noise is recovered: σ̂ of the residuals ≈ the 0.1 px that was added.
    assert result.sigma_px == pytest.approx(0.1, rel=0.15)
    assert result.camera.covariance.shape == (9, 9)


def test_residuals_and_projection_uncertainty(synthetic):
    _, _, views, result = synthetic
    view = result.views[0]
    assert view.used and view.residuals.shape == (len(view.ids), 2)
    assert view.inlier.dtype == bool and view.inlier.all()
    # Residuals are projected − observed: their RMS is the view's rms_px.
    assert np.sqrt(np.mean(np.sum(view.residuals ** 2, axis=1))) == pytest.approx(view.rms_px, rel=1e-9)
    pixels = np.array([[319.5, 239.5], [639.0, 239.5], [0.0, 0.0]])
    sigma = cal.projectionUncertaintyPx(result, pixels)
    summary = cal.summarizeProjectionUncertainty(result)
    assert sigma[0] == pytest.approx(summary.centre_px, rel=1e-12)
    assert sigma[2] == pytest.approx(summary.corner_px, rel=1e-12)
    # Centre well covered by the views (0.1 px noise, 20 views): a few hundredths of a pixel;
    # the corner, outside every view, is an extrapolation of the distortion: much worse.
    assert 0 < sigma[0] < 0.1 < sigma[2]
    covariance = cal.projectionCovariancePx(result, pixels)
    assert covariance.shape == (3, 2, 2)
    np.testing.assert_allclose(np.sqrt(np.linalg.eigvalsh(covariance)[:, -1]), sigma, rtol=1e-9)


def test_object_and_image_point_overload_gives_the_same_camera(synthetic):
    _, board, views, result = synthetic
    objects = [board[v.ids] for v in views]
    images = [v.pixels for v in views]
    again = cal.calibrateCamera(objects, images, 640, 480)
    assert_relative(again.camera.params, result.camera.params, 1e-9, "params")


def test_calibrate_from_rendered_images_and_numpy_arrays(tiny_calibration):
    target = met.Target.fromFile(tiny_calibration / "target.yaml")
    images = sorted((tiny_calibration / "images").glob("*.png"))
    result = cal.calibrateFromImages(target, images)
    sigma = np.array(result.camera.sigmas())
    error = np.array(result.camera.params) - TINY_TRUTH
    assert result.used_views >= 10
    assert np.all(np.abs(error[:4]) < 1.5), error
    assert np.all(np.abs(error) < 5 * sigma), error / sigma
    # The same images as numpy arrays: the same detections, hence the same camera exactly.
    mpimg = pytest.importorskip("matplotlib.image")
    arrays = [np.round(mpimg.imread(p) * 255).astype(np.uint8) for p in images]
    assert arrays[0].shape == (240, 320)
    again = cal.calibrateFromImages(target, arrays)
    assert all(v.name.startswith("image_") for v in again.views)
    assert_relative(again.camera.params, result.camera.params, 0, "params from arrays")


def test_equals_mire_calibrate(tiny_calibration, tmp_path):
    """Python and the CLI on the same images: the same camera to 1e-12 relative."""
    target_file = tiny_calibration / "target.yaml"
    run_cli("calibrate", "--target", target_file, "--images", tiny_calibration / "images", "--threads", "1",
            "-o", tmp_path / "camera.yaml")
    cli = cal.readCamera(tmp_path / "camera.yaml")
    images = sorted((tiny_calibration / "images").glob("*.png"))
    python = cal.calibrateFromImages(met.Target.fromFile(target_file), images).camera
    assert_relative(python.params, cli.params, 1e-12, "camera parameters")
    assert_relative(python.covariance, cli.covariance, 1e-12, "camera covariance")
    assert python.rms_px == pytest.approx(cli.rms_px, rel=1e-12)


def test_calibration_errors_are_value_errors(synthetic):
    _, board, views, _ = synthetic
    options = cal.CalibrationOptions()
    options.fixed_parameters = ["nope"]
    with pytest.raises(ValueError, match="nope"):
        cal.calibrateCamera(board, views, 640, 480, options)
    with pytest.raises(ValueError, match="opencv5"):
        cal.parseDistortionModel("brown")


def test_calibrate_from_a_detections_file_equals_the_images(tiny_calibration, tmp_path):
    """`mire calibrate --save-detections` writes every view's features; calibrating from them
    in Python gives the camera calibrating from the images gave."""
    target_file = tiny_calibration / "target.yaml"
    run_cli("calibrate", "--target", target_file, "--images", tiny_calibration / "images", "--threads", "1",
            "--save-detections", tmp_path / "detections.csv", "-o", tmp_path / "camera.yaml")
    target = met.Target.fromFile(target_file)
    detections = met.readDetectionsFile(tmp_path / "detections.csv", target)
    assert (detections.width, detections.height) == (320, 240)
    views = [cal.CalibrationView(d.image, d.ids, d.pixels) for d in detections.images]
    result = cal.calibrateCamera(target.points(), views, detections.width, detections.height)
    assert_relative(result.camera.params, cal.readCamera(tmp_path / "camera.yaml").params, 1e-12, "params")
