"""Cameras: vectorised project/unproject against an independent numpy implementation of
OpenCV's model, every camera file format, errors as exceptions with mire's message."""
import numpy as np
import pytest

import mire
from conftest import SPECS

cal = mire.calibration


def opencv_project(params, points):
    """cv::projectPoints' radial-tangential model (k1 k2 p1 p2 k3), written out independently."""
    fx, fy, cx, cy, k1, k2, p1, p2, k3 = params
    x = points[:, 0] / points[:, 2]
    y = points[:, 1] / points[:, 2]
    r2 = x * x + y * y
    radial = 1 + k1 * r2 + k2 * r2 ** 2 + k3 * r2 ** 3
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return np.column_stack([fx * xd + cx, fy * yd + cy])


def fisheye_project(params, points):
    """cv::fisheye's equidistant model, written out independently."""
    fx, fy, cx, cy, k1, k2, k3, k4 = params
    x = points[:, 0] / points[:, 2]
    y = points[:, 1] / points[:, 2]
    r = np.hypot(x, y)
    theta = np.arctan(r)
    theta_d = theta * (1 + k1 * theta ** 2 + k2 * theta ** 4 + k3 * theta ** 6 + k4 * theta ** 8)
    scale = theta_d / r
    return np.column_stack([fx * x * scale + cx, fy * y * scale + cy])


@pytest.fixture
def reference_camera():
    return cal.readCamera(SPECS / "reference_camera.yaml")


def field_points(camera, n=2000, seed=1):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-0.55, 0.55, n)
    y = rng.uniform(-0.4, 0.4, n)
    z = rng.uniform(0.3, 2.0, n)
    return np.column_stack([x * z, y * z, z])


def test_reference_camera_reads_with_its_values(reference_camera):
    assert (reference_camera.width, reference_camera.height) == (1024, 768)
    assert reference_camera.modelName() == "opencv5"
    assert reference_camera.parameterNames() == ["fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"]
    assert reference_camera.params[4] == pytest.approx(-0.3)


def test_project_matches_opencv_model_and_marks_points_behind(reference_camera):
    points = field_points(reference_camera)
    pixels = reference_camera.project(points)
    assert pixels.shape == (len(points), 2)
    np.testing.assert_allclose(pixels, opencv_project(reference_camera.params, points), rtol=0, atol=1e-9)
    behind = reference_camera.project(np.array([[0.1, 0.2, -1.0], [0.0, 0.0, 0.0]]))
    assert np.isnan(behind).all()
    one = reference_camera.project([0.01, 0.02, 1.0])  # a single point, any sequence
    np.testing.assert_allclose(one, opencv_project(reference_camera.params, np.array([[0.01, 0.02, 1.0]])), atol=1e-9)


def test_unproject_inverts_project(reference_camera):
    points = field_points(reference_camera, seed=2)
    rays = reference_camera.unproject(reference_camera.project(points))
    np.testing.assert_allclose(rays, points[:, :2] / points[:, 2:], rtol=0, atol=1e-12)


def test_fisheye_projection_matches_the_equidistant_model():
    camera = cal.Camera(640, 480, [300.0, 301.0, 319.5, 239.5, 0.05, -0.01, 0.003, -0.0005], cal.LensModel.Fisheye)
    assert camera.modelName() == "fisheye"
    points = field_points(camera, seed=3)
    np.testing.assert_allclose(camera.project(points), fisheye_project(camera.params, points), rtol=0, atol=1e-9)
    rays = camera.unproject(camera.project(points))
    np.testing.assert_allclose(rays, points[:, :2] / points[:, 2:], rtol=0, atol=1e-10)


def test_bad_shapes_raise_value_errors(reference_camera):
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        reference_camera.project(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        cal.Camera(640, 480, [300.0, 300.0, 320.0], cal.LensModel.OpenCV)


@pytest.mark.parametrize("name,suffix", [("opencv", "yaml"), ("ros", "yaml"), ("visp", "xml")])
def test_formats_round_trip(tmp_path, name, suffix):
    camera = cal.cameraFromOpenCV(640, 480, 500.0, 501.0, 319.5, 239.5, [-0.2, 0.05, 0.0, 0.0, 0.0])
    if name == "visp":  # ViSP's one radial term: a camera it holds exactly
        camera = cal.cameraFromOpenCV(640, 480, 500.0, 501.0, 319.5, 239.5, [])
    path = tmp_path / f"camera.{suffix}"
    cal.writeCamera(camera, path, name)
    assert cal.cameraFormatName(cal.detectCameraFormat(path)) == name
    back = cal.readCamera(path)
    np.testing.assert_allclose(back.params, camera.params, rtol=1e-15)
    assert (back.width, back.height) == (640, 480)


def test_kalibr_and_mrcal_writers(tmp_path):
    camera = cal.cameraFromOpenCV(640, 480, 500.0, 501.0, 319.5, 239.5, [-0.2, 0.05, 0.001, -0.002])
    cal.writeCamera(camera, tmp_path / "camchain.yaml", "kalibr")
    np.testing.assert_allclose(cal.readCamera(tmp_path / "camchain.yaml").params, camera.params, rtol=1e-15)
    assert "LENSMODEL_OPENCV4" in cal.cameraMrcalString(camera)
    with pytest.raises(ValueError):  # Kalibr's radtan cannot hold k3
        cal.cameraKalibrYamlString(cal.cameraFromOpenCV(640, 480, 500, 500, 320, 240, [-0.2, 0.05, 0, 0, 0.01]))


def test_covariance_and_sigmas_read_from_a_calibrated_file(tmp_path):
    camera = cal.cameraFromOpenCV(640, 480, 500.0, 501.0, 319.5, 239.5, [-0.2, 0.05, 0.0, 0.0, 0.0])
    covariance = np.diag(np.arange(1, 10) * 1e-4)
    camera.covariance = covariance
    cal.writeCamera(camera, tmp_path / "c.yaml")
    back = cal.readCamera(tmp_path / "c.yaml")
    np.testing.assert_allclose(back.covariance, covariance, rtol=1e-15)
    np.testing.assert_allclose(back.sigmas(), np.sqrt(np.diag(covariance)), rtol=1e-15)


def test_errors_carry_mires_message(tmp_path):
    with pytest.raises(RuntimeError, match="file not found"):
        cal.readCamera(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("image_width: 640\nimage_height: -3\ncamera_matrix: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n")
    with pytest.raises(mire.YamlError, match=r"bad\.yaml:2: key 'image_height': -3 is out of range"):
        cal.readCamera(bad)
    assert issubclass(mire.YamlError, RuntimeError)
    with pytest.raises(ValueError, match="camera format"):
        cal.writeCamera(cal.cameraFromOpenCV(64, 48, 50, 50, 32, 24, []), tmp_path / "camera.txt")
