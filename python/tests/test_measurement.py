"""Targets and measurement on rendered images (`mire simulate poses`, true cTm known):
detection against the true projections, poses against the truth within their σ, equality
with `mire measure`."""
import numpy as np
import pytest

import mire
from conftest import POSE_LIST, assert_relative, read_csv, run_cli

cal = mire.calibration
met = mire.metrology
mech = mire.mechanism


def truth_poses(folder):
    return {row["pose_id"]: np.array([float(row[k]) for k in ("tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad")])
            for row in read_csv(folder / "truth_poses.csv")}


def load_png(path):
    mpimg = pytest.importorskip("matplotlib.image")
    return np.round(mpimg.imread(path) * 255).astype(np.uint8)


def test_target_file_and_feature_layout(tiny_poses):
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    points = target.points()
    assert points.shape == (35, 3)
    # Chessboard: corner (c, r) at (c·s, r·s, 0), index r·cols + c.
    np.testing.assert_allclose(points[8], [0.025, 0.025, 0.0], atol=1e-15)
    assert target.spec().type == met.TargetType.Chessboard
    assert target.featureSpacing() == pytest.approx(0.025)
    with pytest.raises(ValueError):
        spec = met.TargetSpec()
        spec.cols = 0
        met.Target(spec)


def test_detection_in_a_numpy_image_lands_on_the_true_projections(tiny_poses):
    camera = cal.readCamera(tiny_poses / "camera.yaml")
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    pose = truth_poses(tiny_poses)["a1"]
    image = load_png(sorted((tiny_poses / "poses" / "a1").glob("*.png"))[0])
    detection = met.detectTarget(target, image)
    assert detection.found and len(detection) == 35
    cTm = mech.toIsometry(pose)
    truth = camera.project(target.points() @ cTm[:3, :3].T + cTm[:3, 3])[detection.ids]
    error = np.linalg.norm(detection.pixels - truth, axis=1)
    assert np.sqrt(np.mean(error ** 2)) < 0.3, error
    # A BGR image gives the same features.
    colour = met.detectTarget(target, np.repeat(image[:, :, None], 3, axis=2))
    np.testing.assert_allclose(colour.pixels, detection.pixels, atol=1e-9)
    with pytest.raises(ValueError, match="8-bit image"):
        met.detectTarget(target, np.zeros((2, 3, 4, 5), np.uint8))


def test_measured_poses_agree_with_the_truth_within_sigma(tiny_poses):
    camera = cal.readCamera(tiny_poses / "camera.yaml")
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    truths = truth_poses(tiny_poses)
    for pose_id, _, _ in POSE_LIST:
        m = met.measurePoseFromFolder(camera, target, tiny_poses / "poses" / pose_id)
        assert m.ok, m.error
        e = m.estimate
        assert m.features.images_used == 4 and e.covariance.shape == (6, 6)
        measured = np.concatenate([e.translation, e.rotation_vector])
        error = measured - truths[pose_id]
        assert np.abs(error[:3]).max() < 1e-3 and np.abs(error[3:]).max() < np.radians(0.2), error
        assert np.all(np.abs(error) < 5 * e.sigmas), error / e.sigmas
        np.testing.assert_allclose(e.cTm, mech.toIsometry(measured), atol=1e-12)
        np.testing.assert_allclose(e.covariance, e.covariance_noise + e.covariance_intrinsics, rtol=1e-12)
        assert isinstance(m.flags, list)


def test_measure_from_numpy_arrays_equals_the_files(tiny_poses):
    camera = cal.readCamera(tiny_poses / "camera.yaml")
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    files = met.listPoseImages(tiny_poses / "poses" / "b2")
    from_files = met.measurePoseFromFiles(camera, target, files)
    from_arrays = met.measurePose(camera, target, [load_png(f) for f in files], [f.name for f in files])
    assert from_arrays.ok
    assert_relative(from_arrays.estimate.translation, from_files.estimate.translation, 0, "translation")
    assert_relative(from_arrays.estimate.covariance, from_files.estimate.covariance, 0, "covariance")


def test_measure_failures_name_the_image(tiny_poses, tmp_path):
    camera = cal.readCamera(tiny_poses / "camera.yaml")
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    blank = np.full((240, 320), 128, np.uint8)
    m = met.measurePose(camera, target, [blank, blank], ["blank_0.png", "blank_1.png"])
    assert not m.ok and m.error
    (tmp_path / "broken.png").write_bytes(b"not an image")
    m = met.measurePoseFromFiles(camera, target, [tmp_path / "broken.png"])
    assert not m.ok and "broken.png" in m.error


def test_equals_mire_measure(tiny_poses, tmp_path):
    """Python and the CLI on the same pose folders: the same poses and covariances to 1e-12."""
    run_cli("measure", "--camera", tiny_poses / "camera.yaml", "--target", tiny_poses / "target.yaml",
            "--poses", tiny_poses / "poses", "--threads", "1", "-o", tmp_path / "poses.csv")
    cli = mech.readPosesCsv(tmp_path / "poses.csv", tmp_path / "poses_covariance.csv")
    camera = cal.readCamera(tiny_poses / "camera.yaml")
    target = met.Target.fromFile(tiny_poses / "target.yaml")
    measured = []
    for row in cli:
        m = met.measurePoseFromFolder(camera, target, tiny_poses / "poses" / row.observation.id)
        python = np.concatenate([m.estimate.translation, m.estimate.rotation_vector])
        assert_relative(python, row.observation.cTm, 1e-12, f"pose {row.observation.id}")
        assert_relative(m.estimate.covariance, row.observation.covariance, 1e-12, f"covariance {row.observation.id}")
        measured.append(met.MeasuredPose(row.observation.id, m.features.images_used, 4, m.estimate, m.flags))
    # The files written from Python are the CLI's, byte for byte.
    measured, _, _ = met.screenCampaign(measured)
    assert met.posesCsvString(measured) == (tmp_path / "poses.csv").read_text()
