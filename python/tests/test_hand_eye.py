"""Hand-eye calibration from Python (mire.mechanism.solveHandEye; doc/mechanisms.md, "Hand-eye
calibration"): a simulated camera on the effector with known eTc and stated noise, the result
against the truth and its σ, order independence, the closed forms, robot_poses.csv; ViSP's real
Franka Panda data when ../shared is present."""
import os
import pathlib
import re

import numpy as np
import pytest

import mire

mech = mire.mechanism
DEG = np.pi / 180
SOURCE_DIR = pathlib.Path(os.environ.get("MIRE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SHARED_DIR = pathlib.Path(os.environ.get("MIRE_SHARED_DIR", SOURCE_DIR.parent / "shared"))
VISP = SHARED_DIR / "datasets" / "external" / "visp-handeye"


def rodrigues(r):
    theta = np.linalg.norm(r)
    if theta < 1e-12:
        return np.eye(3)
    k = r / theta
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(theta) * K + (1 - np.cos(theta)) * K @ K


def log_rotation(R):
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * np.sin(angle))
    return w * angle


def matrix(pose):
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = rodrigues(np.asarray(pose[3:])), pose[:3]
    return m


def vector(m):
    return np.concatenate([m[:3, 3], log_rotation(m[:3, :3])])


def simulated_campaign(rng, count=15):
    """Camera on the effector 0.3–0.5 m from a fixed target; robot σ 0.2 mm / 0.02°, camera σ
    0.1 mm / 0.03° per component (its stated covariance)."""
    eTc = matrix([0.05, -0.012, 0.045, 0.1, -0.2, 1.5])
    bTm = matrix([0.55, 0.08, -0.05, 3.0, 0.2, -0.1])
    robot = mech.RobotPoseSigma(0.2e-3, 0.02 * DEG)
    covariance = np.diag([0.1e-3] * 3 + [0.03 * DEG] * 3) ** 2
    poses = []
    for j in range(count):
        cTm = np.eye(4)
        tilt = rng.uniform(-1, 1, 3) * np.array([25, 25, 60]) * DEG
        cTm[:3, :3] = rodrigues([np.pi, 0, 0]) @ rodrigues([tilt[0], 0, 0]) @ rodrigues([0, tilt[1], 0]) @ rodrigues(
            [0, 0, tilt[2]])
        cTm[:3, 3] = [0.05 * rng.uniform(-1, 1), 0.05 * rng.uniform(-1, 1), 0.4 + 0.1 * rng.uniform(-1, 1)]
        bTe = bTm @ np.linalg.inv(cTm) @ np.linalg.inv(eTc)
        reported = bTe.copy()
        reported[:3, :3] = rodrigues(rng.normal(0, robot.rotation_rad, 3)) @ bTe[:3, :3]
        reported[:3, 3] += rng.normal(0, robot.translation_m, 3)
        measured = vector(cTm) + rng.multivariate_normal(np.zeros(6), covariance)
        poses.append(mech.HandEyeObservation(f"p{j}", vector(reported), robot, measured, covariance))
    return eTc, poses


def test_simulated_campaign_recovers_etc_within_its_sigma_and_ignores_order():
    rng = np.random.default_rng(4)
    eTc, poses = simulated_campaign(rng)
    result = mech.solveHandEye(poses, mech.HandEyeMounting.CameraOnEffector)
    assert result.converged
    assert [result.parameters[k].name for k in range(12)] == mech.handEyeParameterNames(
        mech.HandEyeMounting.CameraOnEffector)
    error = np.array([result.parameters[k].value for k in range(6)]) - vector(eTc)
    assert np.all(np.abs(error) < 4 * result.sigma[:6]), (error, result.sigma[:6])
    assert np.all(result.sigma[:3] > 1e-5) and np.all(result.sigma[:3] < 1e-3)
    assert result.covariance.shape == (12, 12)
    assert np.allclose(result.X[:3, 3], [result.parameters[k].value for k in range(3)])
    reversed_result = mech.solveHandEye(poses[::-1], mech.HandEyeMounting.CameraOnEffector)
    assert np.abs(reversed_result.X[:3, 3] - result.X[:3, 3]).max() < 1e-6  # 1 µm
    X, Z = mech.handEyeClosedForm(poses, mech.HandEyeMounting.CameraOnEffector, "park")
    assert np.linalg.norm(X[:3, 3] - eTc[:3, 3]) < 2e-3
    assert len(result.poses) == 15 and result.outliers == []


def test_bad_input_raises_with_the_reason(tmp_path):
    rng = np.random.default_rng(5)
    _, poses = simulated_campaign(rng, count=2)
    with pytest.raises(ValueError, match="at least 3 poses"):
        mech.solveHandEye(poses, mech.HandEyeMounting.CameraOnEffector)
    with pytest.raises(ValueError, match="camera-on-effector or camera-fixed"):
        mech.parseHandEyeMounting("sideways")
    path = tmp_path / "robot_poses.csv"
    path.write_text("pose_id,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_t_mm,sigma_r_deg\na,0.1,0.2,0.3,0,0,1.5,0.1,0.02\n")
    rows = mech.readRobotPosesCsv(path)
    assert rows[0].id == "a" and rows[0].line == 2
    assert rows[0].sigma.translation_m == pytest.approx(1e-4)
    path.write_text("pose_id,tx_m\na,0.1\n")
    with pytest.raises(RuntimeError, match="ty_m"):
        mech.readRobotPosesCsv(path)


def read_visp(name):
    return np.array([float(v) for v in re.findall(r"\[([-0-9.e+]+)\]", (VISP / name).read_text())])


def test_visp_panda_data():
    if not VISP.exists():
        pytest.skip(f"needs {VISP} (../shared, external data), absent: skipped")
    robot = mech.RobotPoseSigma(1e-3, 0.1 * DEG)
    poses = [mech.HandEyeObservation(str(i), read_visp(f"pose_fPe_{i}.yaml"), robot, read_visp(f"pose_cPo_{i}.yaml"))
             for i in range(1, 9)]
    result = mech.solveHandEye(poses, mech.HandEyeMounting.CameraOnEffector)
    visp = matrix([0.05345567035, -0.009516983454, -0.04510223842, -0.0234728216, -0.07938837693, 1.574587196])
    # Within 2σ per component (the data determine eTc to about 1.3 mm: doc/studies/2026-11-26-hand-eye.md).
    assert np.all(np.abs(result.X[:3, 3] - visp[:3, 3]) < 2 * result.sigma[:3])
    assert np.linalg.norm(log_rotation(result.X[:3, :3] @ visp[:3, :3].T)) < 0.1 * DEG
    assert result.sigma_from_residuals


def test_plan_chooses_poses_with_a_smaller_predicted_sigma():
    rng = np.random.default_rng(6)
    eTc, poses = simulated_campaign(rng, count=60)
    model = mech.HandEyeDesignModel()
    model.X = eTc
    model.Z = matrix([0.55, 0.08, -0.05, 3.0, 0.2, -0.1])
    model.robot_sigma = mech.RobotPoseSigma(0.2e-3, 0.02 * DEG)
    model.camera_covariance = np.diag([0.1e-3] * 3 + [0.03 * DEG] * 3) ** 2
    candidates = [matrix(p.bTe) for p in poses]
    plan = mech.planHandEye(model, candidates, 10)
    assert len(plan.chosen) == 10 and len(set(plan.chosen)) == 10
    first = sum(mech.handEyePoseInformation(model, c) for c in candidates[:10])
    first_sigma = np.sqrt(np.diag(np.linalg.inv(first)))
    assert np.linalg.norm(plan.sigma[:3]) < np.linalg.norm(first_sigma[:3])
    assert np.allclose(plan.covariance, plan.covariance.T)
    with pytest.raises(ValueError, match="between 3 and 60"):
        mech.planHandEye(model, candidates, 2)
