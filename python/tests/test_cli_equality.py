"""The Python path equals the CLI: identification on a simulated campaign (default suite), and
the whole demo campaign — camera, poses and identified parameters — to 1e-12 relative
(about 40 s: skipped by a plain pytest run unless MIRE_SLOW_TESTS=1; ctest runs it as its own
test, python_demo_equality)."""
import os

import numpy as np
import pytest

import mire
from conftest import SOURCE_DIR, assert_relative, read_csv, run_cli
from test_mechanisms import Robot, rot, transform

cal = mire.calibration
met = mire.metrology
mech = mire.mechanism
pipe = mire.pipeline

POSE_COLUMNS = ("tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad")


def write_campaign(folder, robot, rng):
    """poses.csv (σ columns: the diagonal covariance) and joints.csv of the simulated H4."""
    ids, cTm, joints, _ = robot.observe(Robot.protocol(), rng)
    sigma = [0.2] * 3 + [0.03] * 3  # mm, deg
    header = "pose_id,images_used,images_total," + ",".join(POSE_COLUMNS) + \
        ",sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n"
    rows = [",".join([i, "10", "10", *map(repr, map(float, c)), *map(repr, sigma), "0.1"]) for i, c in zip(ids, cTm)]
    (folder / "poses.csv").write_text(header + "\n".join(rows) + "\n")
    rows = [",".join([i, *map(repr, map(float, q))]) for i, q in zip(ids, joints)]
    (folder / "joints.csv").write_text("pose_id,q1_rad,q2_rad,q3_rad,q4_rad\n" + "\n".join(rows) + "\n")


def nominal_from_file(path):
    """What `mire identify --nominal` reads (apps/src/cmd_identify.cpp readNominal)."""
    file = mech.readParameterFile(path)
    ignored = ["amplification"]
    for form in (mech.ExternalForm.AxisAligned, mech.ExternalForm.Full, mech.ExternalForm.CameraFrame):
        ignored += mech.ExternalParameterization(form).parameters().names()
    values = mech.applyParameterFile(file, mech.h4Model12Parameters(), ignored).asDict()
    nominal = mech.H4Nominal()
    nominal.R, nominal.L, nominal.l, nominal.h, nominal.d = (values[k] for k in ("R", "L", "l", "h", "d"))
    nominal.alpha = [values[f"alpha{i}"] for i in range(1, 5)]
    nominal.q0 = [values[f"q0{i}"] for i in range(1, 5)]
    return nominal


def identify_like_the_cli(poses_csv, joints_csv, letter="D", nominal=None):
    """The steps of `mire identify --model h4-12 --variant D`, through the Python API."""
    nominal = nominal or nominal_from_file(SOURCE_DIR / "datasets" / "specs" / "h4_nominal.yaml")
    registered = mech.makeRegisteredModel("h4-12", nominal)
    side = mech.defaultCovariancePath(poses_csv)
    observations = mech.readObservations(poses_csv, joints_csv, side if side.exists() else None,
                                         registered.mechanism.jointColumnNames())
    options = mech.IdentificationOptions()
    initial = mech.makeH4VariantModel(letter, nominal, observations.poses, options)
    result = mech.identify(initial, observations.poses, options)
    assert mech.alignTranslatingTarget(result, observations.poses) is None  # the H4's target turns
    return result


def assert_same_parameters(result, yaml_path):
    file = mech.readParameterFile(yaml_path)
    for i, name in enumerate(result.model.parameters.names()):
        value = file.number(file.find(name))
        assert_relative(result.model.parameters.value(name), value, 1e-12, name)
        entry = file.find("sigma_" + name)
        if entry is not None:
            assert_relative(result.sigma[i], file.number(entry), 1e-12, "sigma_" + name)
        else:
            assert result.sigma[i] == 0.0, name


def test_identify_equals_mire_identify(tmp_path):
    write_campaign(tmp_path, Robot(), np.random.default_rng(11))
    run_cli("identify", "--poses", tmp_path / "poses.csv", "--joints", tmp_path / "joints.csv",
            "-o", tmp_path / "identified.yaml")
    result = identify_like_the_cli(tmp_path / "poses.csv", tmp_path / "joints.csv")
    assert result.weighted and result.model.parameters.freeCount() == 19
    assert_same_parameters(result, tmp_path / "identified.yaml")
    # The same through the stage the command runs (mire/pipeline/identify.hpp).
    choice = pipe.chooseModel("", "", nominal_from_file(SOURCE_DIR / "datasets" / "specs" / "h4_nominal.yaml"))
    assert choice.label() == "h4-12, variant D"
    data = pipe.readPoseSet(pipe.PoseSetFiles.beside(tmp_path / "poses.csv", tmp_path / "joints.csv"),
                            mech.makeRegisteredModel("h4-12").mechanism.jointColumnNames())
    assert_same_parameters(pipe.identify(choice, data.observations.poses, data.shared).result,
                           tmp_path / "identified.yaml")


def test_choose_model_names_the_option_at_fault():
    with pytest.raises(ValueError, match="--variant 'Z'"):
        pipe.chooseModel("h4-12", "Z")
    with pytest.raises(ValueError, match="--variant E does not belong to --model h4-12"):
        pipe.chooseModel("h4-12", "E")
    with pytest.raises(ValueError, match="--model 'nope'"):
        pipe.chooseModel("nope", "")
    assert pipe.chooseModel("", "F").model == "h4-31c"
    assert pipe.chooseModel("delta", "").variant == ""


@pytest.mark.skipif(os.environ.get("MIRE_SLOW_TESTS") != "1", reason="slow (the whole demo): ctest python_demo_equality, or MIRE_SLOW_TESTS=1")
def test_demo_campaign_equals_the_cli(tmp_path):
    """`mire demo --quick` (simulate, calibrate, measure, identify) against the Python pipeline
    on the same campaign files: camera, every pose and variant D's parameters."""
    out = tmp_path / "demo"
    run_cli("demo", "--quick", "-o", out)
    campaign = out / "campaign"
    target = met.Target.fromFile(campaign / "target.yaml")
    images = sorted((campaign / "calibration" / "images").glob("*.png"))
    options = cal.CalibrationOptions()
    options.model = cal.DistortionModel.OpenCV5
    camera = cal.calibrateFromImages(target, images, options).camera
    cli_camera = cal.readCamera(out / "camera.yaml")
    assert_relative(camera.params, cli_camera.params, 1e-12, "camera")
    assert_relative(camera.covariance, cli_camera.covariance, 1e-12, "camera covariance")

    measure = met.MeasurementOptions()
    measure.integrity.split = met.SplitPolicy.KeepLargest
    cli_poses = {row.observation.id: row.observation
                 for row in mech.readPosesCsv(out / "poses.csv", out / "poses_covariance.csv")}
    measured, ids, measurements = [], [], []
    for folder in sorted(p for p in (campaign / "poses").iterdir() if p.is_dir()):
        m = met.measurePoseFromFolder(cli_camera, target, folder, measure)
        ids.append(folder.name)
        measurements.append(m)
        assert m.ok, m.error
        pose = np.concatenate([m.estimate.translation, m.estimate.rotation_vector])
        assert_relative(pose, cli_poses[folder.name].cTm, 1e-12, f"pose {folder.name}")
        assert_relative(m.estimate.covariance, cli_poses[folder.name].covariance, 1e-12, f"covariance {folder.name}")
        total = len(met.listPoseImages(folder))
        measured.append(met.MeasuredPose(folder.name, m.features.images_used, total, m.estimate))
    assert len(measured) == len(cli_poses) == 81

    met.writePosesCsv(tmp_path / "poses.csv", measured)
    met.writePosesCovarianceCsv(tmp_path / "poses_covariance.csv", measured)
    # The shared terms (the calibration's error, the detector's bias when it shows) as the CLI wrote them.
    bias = met.estimateDetectorBias(cli_camera, target, ids, measurements, measure.pose)
    assert (out / "poses_shared.csv").read_text() == met.sharedTermCsvString(cli_camera, measured, bias)
    # Variant D with the calibration term shared by every pose, as the demo runs `mire identify`'s stage.
    files = pipe.PoseSetFiles.beside(tmp_path / "poses.csv", campaign / "joints.csv")
    files.shared = out / "poses_shared.csv"
    data = pipe.readPoseSet(files, mech.makeRegisteredModel("h4-12").mechanism.jointColumnNames())
    result = pipe.identify(pipe.chooseModel("h4-12", "D"), data.observations.poses, data.shared).result
    assert "shared" in result.covariance_method
    assert_same_parameters(result, out / "identified_D.yaml")


@pytest.mark.parametrize("name", ["delta", "delta-legs", "gough-stewart", "gough-stewart-gains"])
def test_an_identified_file_is_a_nominal_in_python(tmp_path, name):
    """`mire identify --model NAME` writes a file Python's readers take as it is (every angle
    included), and pipeline.applyNominalFile starts the same model from it."""
    model = mech.makeRegisteredModel(name)
    truth = model.nominal.values().copy()
    rng = np.random.default_rng(5)
    truth[[not p.fixed for p in model.nominal.parameters()]] += rng.uniform(-1e-3, 1e-3, sum(
        not p.fixed for p in model.nominal.parameters()))
    reference = model.mechanism.referencePose(truth)
    spread = np.array([0.08, 0.08, 0.05, 0.05, 0.05, 0.05][:model.mechanism.poseDof()])
    if model.mechanism.poseDof() == 6:
        spread[:3] = 0.03
    poses = reference + rng.uniform(-1, 1, (60, model.mechanism.poseDof())) * spread
    joints = model.mechanism.ikm(truth, poses)
    keep = np.isfinite(joints).all(axis=1)
    poses, joints = poses[keep], joints[keep]
    bTc = transform(rot(0, 0.02) @ rot(2, 0.4), [0.03, -0.02, 1.3 if model.mechanism.poseDof() == 6 else -1.3])
    cTm = [mech.toPoseVector(np.linalg.inv(bTc) @ model.mechanism.poseToTransform(p)) for p in poses]
    ids = [f"p{j + 1}" for j in range(len(poses))]
    header = "pose_id,images_used,images_total," + ",".join(POSE_COLUMNS) + \
        ",sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n"
    sigma = [0.2] * 3 + [0.03] * 3  # mm, deg
    rows = [",".join([i, "10", "10", *map(repr, map(float, c)), *map(repr, sigma), "0.1"]) for i, c in zip(ids, cTm)]
    (tmp_path / "poses.csv").write_text(header + "\n".join(rows) + "\n")
    columns = model.mechanism.jointColumnNames()
    rows = [",".join([i, *map(repr, map(float, q))]) for i, q in zip(ids, joints)]
    (tmp_path / "joints.csv").write_text("pose_id," + ",".join(columns) + "\n" + "\n".join(rows) + "\n")
    identified = tmp_path / "identified.yaml"
    run_cli("identify", "--model", name, "--poses", tmp_path / "poses.csv", "--joints", tmp_path / "joints.csv",
            "-o", identified)
    ignored = []
    for form in (mech.ExternalForm.AxisAligned, mech.ExternalForm.Full, mech.ExternalForm.CameraFrame):
        ignored += mech.ExternalParameterization(form).parameters().names()
    values = mech.applyParameterFile(mech.readParameterFile(identified), model.nominal, ignored + ["amplification"])
    choice = pipe.applyNominalFile(pipe.chooseModel(name), identified)
    np.testing.assert_array_equal(choice.registered().nominal.values(), values.values())
