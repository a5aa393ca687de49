"""Described mechanisms from Python (doc/mechanisms.md, "Described mechanisms"): every shipped
description is a model by its file name, its IKM and FKM are inverse, and a leg's declared
`stroke` is reported by the IKM as for the built-in hexapod."""
import os
import pathlib

import numpy as np
import pytest

import mire
from frames import rot, transform

mech = mire.mechanism
SOURCE_DIR = pathlib.Path(os.environ.get("MIRE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE_DIR / "examples" / "mechanisms"


@pytest.mark.parametrize("file", ["linear-delta.yaml", "6-rus.yaml", "6-pus.yaml", "delta.yaml", "gough-stewart.yaml"])
def test_described_examples_round_trip(file):
    model = mech.makeRegisteredModel(str(EXAMPLES / file))
    geometric = model.nominal.values()
    reference = model.mechanism.referencePose(geometric)
    dof = model.mechanism.poseDof()
    rng = np.random.default_rng(11)
    steps = np.concatenate([np.full(3, 0.01), np.full(dof - 3, 0.02)])
    poses = reference + rng.uniform(-1, 1, (10, dof)) * steps
    joints = model.mechanism.ikm(geometric, poses)
    assert joints.shape == (10, len(model.mechanism.jointColumnNames()))
    assert np.isfinite(joints).all()
    np.testing.assert_allclose(model.mechanism.fkm(geometric, joints), poses, atol=1e-9)


def test_a_declared_stroke_is_reported(tmp_path):
    # The linear delta's carriages read z + √(0.25² − 0.16²) = z + 0.1921 m on the axis.
    text = (EXAMPLES / "linear-delta.yaml").read_text().replace("    branch: +1", "    stroke: [0.25, 0.34]\n    branch: +1")
    (tmp_path / "printer.yaml").write_text(text)
    model = mech.makeRegisteredModel(str(tmp_path / "printer.yaml"))
    geometric = model.nominal.values()
    inside = model.mechanism.inverseKinematics(geometric, model.mechanism.poseToTransform([0.0, 0.0, 0.10]))
    assert inside.reachable() and inside.withinStroke()
    low = model.mechanism.inverseKinematics(geometric, model.mechanism.poseToTransform([0.0, 0.0, 0.0]))
    assert low.reachable() and not low.withinStroke()
    assert low.out_of_stroke_joints == [0, 1, 2]
    np.testing.assert_allclose(low.joints, np.full(3, np.sqrt(0.25 ** 2 - 0.16 ** 2)), atol=1e-12)


def test_described_linear_delta_identified_through_the_pipeline():
    """mire identify's recipe on a linear delta drawn 0.5 mm off, 60 poses with 0.2 mm / 0.03°
    noise: the rank the analysis finds, and the joint residual of the returned (target-aligned)
    model at the noise's level, as after the fit."""
    file = str(EXAMPLES / "linear-delta.yaml")
    model = mech.makeRegisteredModel(file)
    truth = model.mechanism.nominal()  # a copy: the model keeps its nominal
    rng = np.random.default_rng(5)
    for name in truth.names():
        truth.setValue(name, truth.value(name) + rng.uniform(-0.5e-3, 0.5e-3))
    bTc = transform(rot(2, 0.3) @ rot(0, 0.05), [0.03, -0.02, -1.9])
    mTe = transform(rot(0, 3.1) @ rot(2, 0.05), [0.012, -0.008, 0.005])
    poses = np.array([0.0, 0.0, 0.10]) + rng.uniform(-1, 1, (60, 3)) * [0.023, 0.023, 0.0115]
    joints = model.mechanism.ikm(truth.values(), poses)
    t_sigma, r_sigma = 0.2e-3, 0.03 * np.pi / 180
    cTm = np.array([mech.toPoseVector(np.linalg.inv(bTc) @ model.mechanism.poseToTransform(p) @ np.linalg.inv(mTe))
                    for p in poses])
    cTm += np.column_stack([rng.normal(0, t_sigma, (60, 3)), rng.normal(0, r_sigma, (60, 3))])
    covariance = np.tile(np.diag([t_sigma ** 2] * 3 + [r_sigma ** 2] * 3), (60, 1, 1))
    observations = mech.observationsFromArrays([f"p{j + 1}" for j in range(60)], cTm, joints, covariance)
    identification = mire.pipeline.identify(mire.pipeline.chooseModel(file), observations)
    result = identification.result
    assert result.converged
    assert len(result.free_names) == 21
    assert 0.7 < result.residual_scale < 1.3
    after = mech.jointResidualCriteria(result.model, observations)
    assert after.pose_count == 60
    assert after.v2_rad < 1.5 * result.rms_joint_residual
