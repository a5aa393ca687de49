"""Mechanisms and identification on the simulated H4 of the C++ tests
(tests/mechanism/h4_test_robot.hpp: a true robot ≈1 mm / 0.5° from nominal, known camera and
target mountings, the 81-pose protocol, cTm noise 0.2 mm / 0.03°)."""
import numpy as np
import pytest

import mire
from frames import rot, transform

mech = mire.mechanism
DEG = np.pi / 180
SIGMA_T, SIGMA_R = 0.2e-3, 0.03 * DEG


class Robot:
    """The same truth as h4_test_robot.hpp."""

    def __init__(self):
        nominal = mech.H4Nominal()
        self.truth = mech.h4Model12Parameters(nominal)
        for name, delta in (("R", 1.0e-3), ("L", -0.8e-3), ("l", 1.2e-3), ("h", -0.7e-3)):
            self.truth.setValue(name, self.truth.value(name) + delta)
        for i, (da, dq) in enumerate(zip((0.5, -0.4, 0.3, -0.5), (0.5, -0.3, 0.4, -0.6)), start=1):
            self.truth.setValue(f"alpha{i}", self.truth.value(f"alpha{i}") + da * DEG)
            self.truth.setValue(f"q0{i}", dq * DEG)
        self.mechanism = mech.makeH4Mechanism(mech.H4ModelKind.Model12)
        self.bTc = transform(rot(2, 0.3) @ rot(1, 0.02) @ rot(0, 0.015), [0.03, -0.02, -1.25])
        self.mTe = transform(rot(0, np.pi) @ rot(2, 0.4) @ rot(1, 0.004), [0.012, -0.008, 0.03])

    @staticmethod
    def protocol():
        """81 poses (x, y, z, θ): 3×3×3 positions over 200×200×150 mm × θ ∈ {−20°, 0°, 20°}."""
        return np.array([[0.1 * ix, 0.1 * iy, -0.62 + 0.075 * iz, 20 * DEG * it]
                         for ix in (-1, 0, 1) for iy in (-1, 0, 1) for iz in (-1, 0, 1) for it in (-1, 0, 1)])

    def observe(self, poses, rng=None):
        """Arrays (ids, cTm (N, 6), joints (N, 4), covariances (N, 6, 6)) of effector poses."""
        joints = self.mechanism.ikm(self.truth.values(), poses)
        cTm = []
        for pose in poses:
            bTe = self.mechanism.poseToTransform(pose)
            cTm.append(mech.toPoseVector(np.linalg.inv(self.bTc) @ bTe @ np.linalg.inv(self.mTe)))
        cTm = np.array(cTm)
        if rng is not None:
            cTm += np.column_stack([rng.normal(0, SIGMA_T, (len(cTm), 3)), rng.normal(0, SIGMA_R, (len(cTm), 3))])
        covariance = np.tile(np.diag([SIGMA_T ** 2] * 3 + [SIGMA_R ** 2] * 3), (len(poses), 1, 1))
        ids = [f"p{j + 1}" for j in range(len(poses))]
        return ids, cTm, joints, covariance


@pytest.fixture(scope="module")
def robot():
    return Robot()


def test_registry_names_every_model():
    names = [m.name for m in mech.registeredModels()]
    for name in ("h4-12", "h4-31", "h4-31c", "delta", "gough-stewart"):
        assert name in names
    with pytest.raises(ValueError, match="unknown model 'nope'"):
        mech.makeRegisteredModel("nope")


def test_ikm_fkm_round_trip_vectorised(robot):
    poses = Robot.protocol()
    joints = robot.mechanism.ikm(robot.truth.values(), poses)
    assert joints.shape == (81, 4) and np.isfinite(joints).all()
    back = robot.mechanism.fkm(robot.truth.values(), joints)
    np.testing.assert_allclose(back, poses, atol=1e-9)
    # The single-pose calls agree with the vectorised ones.
    one = robot.mechanism.inverseKinematics(robot.truth.values(), robot.mechanism.poseToTransform(poses[5]))
    assert one.reachable()
    np.testing.assert_allclose(one.joints, joints[5], atol=0)
    far = robot.mechanism.ikm(robot.truth.values(), np.array([[0.0, 0.0, -5.0, 0.0]]))
    assert np.isnan(far).all()


@pytest.mark.parametrize("name", ["delta", "gough-stewart"])
def test_other_mechanisms_by_name_round_trip(name):
    model = mech.makeRegisteredModel(name)
    geometric = model.nominal.values()
    reference = model.mechanism.referencePose(geometric)
    rng = np.random.default_rng(3)
    poses = reference + rng.uniform(-0.02, 0.02, (10, model.mechanism.poseDof()))
    joints = model.mechanism.ikm(geometric, poses)
    assert np.isfinite(joints).all()
    np.testing.assert_allclose(model.mechanism.fkm(geometric, joints), poses, atol=1e-8)


def test_identification_recovers_the_truth_within_sigma(robot):
    ids, cTm, joints, covariance = robot.observe(Robot.protocol(), np.random.default_rng(7))
    poses = mech.observationsFromArrays(ids, cTm, joints, covariance)
    model = mech.makeH4VariantModel("D", mech.H4Nominal(), poses)
    assert model.parameters.freeCount() == 19
    result = mech.identify(model, poses)
    assert result.converged and result.weighted
    assert result.identifiability.fullRank() and result.identifiability.rank == 19
    assert result.residual_scale == pytest.approx(1.0, abs=0.2)
    truth = robot.truth.asDict()
    errors = []
    for name in ("R", "L", "l", "h", "alpha1", "alpha2", "alpha3", "alpha4", "q01", "q02", "q03", "q04"):
        error = result.model.parameters.value(name) - truth[name]
        errors.append(error / result.sigmaOf(name))
        assert abs(error) < 3.5 * result.sigmaOf(name), name
    assert result.covariance.shape == (19, 19)
    np.testing.assert_allclose(np.sqrt(np.diag(result.covariance)),
                               [result.sigmaOf(n) for n in result.free_names], rtol=1e-12)
    # Validation on other, exact poses: the identified model predicts the joints far better.
    ids, cTm, joints, covariance = robot.observe(Robot.protocol()[::3] * [0.8, 0.8, 1, 0.5])
    criteria = mech.jointResidualCriteria(result.model, mech.observationsFromArrays(ids, cTm, joints, covariance))
    before = mech.jointResidualCriteria(model, mech.observationsFromArrays(ids, cTm, joints, covariance))
    assert criteria.pose_count == 27
    print(f"V2 before {before.v2_rad:.3g} rad, after {criteria.v2_rad:.3g} rad")
    assert criteria.v2_rad < 0.1 * before.v2_rad


def test_noise_free_identification_is_exact(robot):
    ids, cTm, joints, _ = robot.observe(Robot.protocol())
    poses = mech.observationsFromArrays(ids, cTm, joints)
    result = mech.identifyH4Variant("D", mech.H4Nominal(), poses)
    assert not result.weighted
    identified = result.model.parameters.asDict()
    for name, value in robot.truth.asDict().items():
        if name != "d":
            assert identified[name] == pytest.approx(value, abs=1e-9), name
    assert result.rms_joint_residual < 1e-10


def test_identifiability_names_the_eq24_combination(robot):
    ids, cTm, joints, _ = robot.observe(Robot.protocol())
    poses = mech.observationsFromArrays(ids, cTm, joints)
    model = mech.makeH4VariantModel("D", mech.H4Nominal(), poses)
    model.parameters.setFixed("z_ME", False)
    report = mech.analyzeIdentifiability(model, poses)
    assert report.rank == 19 and len(report.parameter_names) == 20
    assert len(report.combinations) == 1
    direction = dict(report.combinations[0].direction)
    assert set(direction) == {"z_ME", "z_BC"}
    assert direction["z_BC"] / direction["z_ME"] == pytest.approx(-1.0, abs=1e-6)
    assert "z_ME" in report.combinations[0].text()
    jacobian = mech.identificationJacobian(model, poses)
    assert jacobian.shape == (81 * 4, 20)
    assert mech.analyzeJacobian(jacobian, model.parameters.freeNames()).rank == 19


def test_straightness_of_a_rebuilt_line(robot):
    line = np.column_stack([np.linspace(-0.1, 0.1, 11), np.zeros(11), np.full(11, -0.62), np.zeros(11)])
    joints = robot.mechanism.ikm(robot.truth.values(), line)
    exact = mech.straightnessCriterion(robot.mechanism, robot.truth.values(), [joints])
    assert exact.ok and exact.v3_m < 1e-9
    nominal = mech.straightnessCriterion(robot.mechanism, mech.h4Model12Parameters().values(), [joints])
    assert nominal.v3_m > 1e-5  # the nominal model bends the truly straight line
    assert mech.straightness(line[:, :3]) == pytest.approx(0.0, abs=1e-15)


def test_bad_input_raises_with_the_pose_named(robot):
    ids, cTm, joints, _ = robot.observe(Robot.protocol()[:10])
    joints[3, 2] = np.nan
    with pytest.raises(ValueError, match="p4"):
        mech.validatePoses(mech.observationsFromArrays(ids, cTm, joints), 4)
    with pytest.raises(ValueError, match=r"\(10, 6\)"):
        mech.observationsFromArrays(ids, cTm[:, :5], joints)
    options = mech.IdentificationOptions()
    options.fix = ["no_such_parameter"]
    poses = mech.observationsFromArrays(*robot.observe(Robot.protocol())[:3])
    with pytest.raises(ValueError, match="no_such_parameter"):
        mech.identify(mech.makeH4VariantModel("D", mech.H4Nominal(), poses), poses, options)
