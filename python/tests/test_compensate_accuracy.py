"""Closing the loop from Python (doc/accuracy.md): `mire.pipeline.compensate` and
`mire.pipeline.accuracy` against a simulated Delta whose legs differ (1 mm / 0.5° on every
parameter, known camera and target mountings, measurements 0.2 mm / 0.03°)."""
import numpy as np
import pytest

import mire

mech, pipe = mire.mechanism, mire.pipeline
DEG = np.pi / 180
SIGMA_T, SIGMA_R = 0.2e-3, 0.03 * DEG
MODEL = "delta-legs"


def rotation(v):
    angle = np.linalg.norm(v)
    if angle == 0:
        return np.eye(3)
    k = np.array(v) / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def transform(v, t):
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = rotation(v), t
    return m


class Delta:
    """A true robot, its mountings (mechanism_campaign.hpp's for a Delta) and its measurements."""

    def __init__(self, seed=5):
        registered = mech.makeRegisteredModel(MODEL)
        self.mechanism = registered.mechanism
        self.nominal = registered.nominal
        self.truth = mech.makeRegisteredModel(MODEL).nominal
        rng = np.random.default_rng(seed)
        for p in self.truth.parameters():
            if not p.fixed:
                size = 0.5 * DEG if p.unit == mech.Unit.Radian else 1e-3
                self.truth.setValue(p.name, p.value + size * rng.uniform(-1, 1))
        self.bTc = transform([0.05, -0.04, 0.3], [0.03, -0.02, -1.9])
        self.mTe = transform([3.1, 0.05, 0.0], [0.012, -0.008, 0.005])
        self.reference = self.mechanism.referencePose(self.truth.values())

    def box(self, rng, n, half=(0.15, 0.15, 0.075)):
        return self.reference + rng.uniform(-1, 1, (n, 3)) * np.array(half)

    def cTm(self, bTe):
        return mech.toPoseVector(np.linalg.inv(self.bTc) @ bTe @ np.linalg.inv(self.mTe))

    def observations(self, poses, rng):
        joints = self.mechanism.ikm(self.truth.values(), poses)
        cTm = np.array([self.cTm(self.mechanism.poseToTransform(x)) for x in poses])
        cTm += np.column_stack([rng.normal(0, SIGMA_T, (len(poses), 3)), rng.normal(0, SIGMA_R, (len(poses), 3))])
        covariance = np.tile(np.diag([SIGMA_T ** 2] * 3 + [SIGMA_R ** 2] * 3), (len(poses), 1, 1))
        return mech.observationsFromArrays([f"p{j + 1}" for j in range(len(poses))], cTm, joints, covariance)

    def identified(self, rng, extra):
        """The prediction model identified from the protocol's 27 positions and `extra` random poses."""
        grid = np.array([[x, y, z] for x in (-0.15, 0, 0.15) for y in (-0.15, 0, 0.15) for z in (-0.075, 0, 0.075)])
        poses = np.vstack([self.reference + grid, self.box(rng, extra)])
        identification = pipe.identify(pipe.chooseModel(MODEL, ""), self.observations(poses, rng))
        return mech.predictionModelFrom(MODEL, identification.result)

    def reached(self, joints):
        """Where the true robot goes for joint commands."""
        return self.mechanism.fkm(self.truth.values(), joints)

    def model(self):
        """The truth as a prediction model (true geometry and mountings, no covariance)."""
        mounting = mech.ExternalParameterization(mech.ExternalForm.Full).parameters()
        mounting.setValues(np.concatenate([mech.toPoseVector(np.linalg.inv(self.bTc)),
                                           mech.toPoseVector(np.linalg.inv(self.mTe))]))
        return mech.PredictionModel(MODEL, self.truth, mounting)


def aligned_rms(reached, desired):
    """RMS distance after the best rigid motion (Kabsch): the frame-free position error."""
    a, b = reached - reached.mean(0), desired - desired.mean(0)
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(u @ vt))
    r = (u @ np.diag([1, 1, d]) @ vt).T
    return np.sqrt(np.mean(np.sum((a @ r.T - b) ** 2, axis=1)))


@pytest.fixture(scope="module")
def delta():
    return Delta()


def test_correction_map_makes_the_nominal_controller_reach_the_truth(delta):
    desired = delta.box(np.random.default_rng(1), 20)
    out = pipe.compensate(delta.model(), desired, controller=delta.nominal.values())
    assert all(out["reachable"]) and out["commands"].shape == (20, 3)
    assert np.allclose(out["sigma"], 0.0)  # no covariance in this model
    # The nominal controller fed the corrected poses drives the true robot to the desired ones.
    reached = delta.reached(delta.mechanism.ikm(delta.nominal.values(), out["commands"]))
    assert np.abs(reached - desired).max() < 1e-8
    uncorrected = delta.reached(delta.mechanism.ikm(delta.nominal.values(), desired))
    assert np.sqrt(np.mean(np.sum((uncorrected - desired) ** 2, axis=1))) > 1e-3


def test_joint_commands_of_an_identified_robot_reach_the_noise_level(delta):
    model = delta.identified(np.random.default_rng(2), 27)
    desired = delta.box(np.random.default_rng(3), 20)
    out = pipe.compensate(model, desired)
    assert all(out["reachable"]) and out["joints"].shape == (20, 3) and out["covariance"].shape == (20, 3, 3)
    assert (out["sigma"] > 0).all() and np.allclose(out["sigma"] ** 2, np.diagonal(out["covariance"], 0, 1, 2))
    compensated = aligned_rms(delta.reached(out["joints"]), desired)
    nominal = aligned_rms(delta.reached(delta.mechanism.ikm(delta.nominal.values(), desired)), desired)
    print(f"delta-legs: compensated {compensated * 1e3:.3f} mm, nominal {nominal * 1e3:.3f} mm (frame-free RMS)")
    assert compensated < 0.12e-3 and compensated < 0.3 * nominal
    # A pose out of reach is named, not a command.
    far = pipe.compensate(model, np.array([[0.0, 0.0, 5.0]]))
    assert not far["reachable"][0] and np.isnan(far["joints"]).all() and "unreachable" in far["messages"][0]
    with pytest.raises(ValueError, match="3 columns"):
        pipe.compensate(model, np.zeros((2, 4)))


def test_controller_fit_states_the_error_expected_on_the_robot(delta):
    model = delta.identified(np.random.default_rng(4), 54)
    workspace = np.array([delta.reference + [x, y, z] for x in np.linspace(-0.1, 0.1, 5)
                          for y in np.linspace(-0.1, 0.1, 5) for z in (-0.05, 0, 0.05)])
    fit = mech.fitControllerModel(model, "delta", workspace)
    assert fit.converged and fit.draws > 90
    assert 0 < fit.sigma_rms_position_error < fit.expected_rms_position_error
    # The delta controller's commands run on the TRUE robot: within 3 of the stated σ.
    controller = mech.makeRegisteredModel("delta").mechanism
    targets = np.array([(fit.frame @ np.append(x, 1.0))[:3] for x in workspace])
    reached = delta.reached(controller.ikm(fit.parameters.values(), targets))
    true_rms = aligned_rms(reached, workspace)
    print(f"delta controller: true {true_rms * 1e3:.4f} mm, expected {fit.expected_rms_position_error * 1e3:.4f}"
          f" ± {fit.sigma_rms_position_error * 1e3:.4f} mm")
    assert abs(true_rms - fit.expected_rms_position_error) < 3 * fit.sigma_rms_position_error


def iso_cycles(delta, rng, cycles=30):
    """5 positions × `cycles`: each position biased (0.5 mm per axis) and scattered (0.05 mm)."""
    positions = delta.reference + 0.06 * np.array([[0, 0, 0], [-1, -1, -1], [1, 1, -1], [1, 1, 1], [-1, -1, 1]])
    bias = np.random.default_rng(7).uniform(-0.5e-3, 0.5e-3, (5, 3))
    ids, names, commanded, attained = [], [], [], []
    for c in range(cycles):
        for k in range(5):
            ids.append(f"c{c + 1}_P{k + 1}")
            names.append(f"P{k + 1}")
            commanded.append(positions[k])
            attained.append(positions[k] + bias[k] + rng.normal(0, 0.05e-3, 3))
    cTm = np.array([delta.cTm(transform([0, 0, 0], a)) for a in attained])
    cTm += np.column_stack([rng.normal(0, SIGMA_T, (len(ids), 3)), rng.normal(0, SIGMA_R, (len(ids), 3))])
    covariance = np.tile(np.diag([SIGMA_T ** 2] * 3 + [SIGMA_R ** 2] * 3), (len(ids), 1, 1))
    measured = mech.observationsFromArrays(ids, cTm, np.zeros((len(ids), 0)), covariance)
    return ids, names, np.array(commanded), np.array(attained), measured


def test_accuracy_equals_an_independent_computation(delta):
    model = delta.model()
    ids, names, commanded, _, measured = iso_cycles(delta, np.random.default_rng(4))
    out = pipe.accuracy(model, ids, names, commanded, measured[:-1], noise_draws=200)
    assert out["unmeasured"] == [ids[-1]] and out["cycles_used"] == len(ids) - 1
    assert [p["position"] for p in out["positions"]] == ["P1", "P2", "P3", "P4", "P5"]
    # ISO 9283 §7.2 by hand, from the measured cTm read through the mounting.
    cTb, eTm = model.cTb(), model.eTm()
    attained = np.array([(np.linalg.inv(cTb) @ mech.toIsometry(o.cTm) @ np.linalg.inv(eTm))[:3, 3] for o in measured])
    for k, p in enumerate(out["positions"]):
        rows = [j for j in range(len(ids) - 1) if names[j] == f"P{k + 1}"]
        x = attained[rows]
        barycentre = x.mean(0)
        assert p["ap_p"] == pytest.approx(np.linalg.norm(barycentre - commanded[rows[0]]), abs=1e-9)
        distances = np.linalg.norm(x - barycentre, axis=1)
        assert p["rp_l"] == pytest.approx(distances.mean() + 3 * distances.std(ddof=1), abs=1e-9)
        assert p["cycles"] == len(rows)
    pairs = [(d["from"], d["to"]) for d in out["distances"]]
    assert len(pairs) == 10 and pairs[0] == ("P1", "P2")
    with pytest.raises(ValueError, match="must agree"):
        pipe.accuracy(model, ids, names[:-1], commanded, measured)


def test_accuracy_sigma_predicts_the_error_against_the_truth(delta):
    model = delta.model()
    z = []
    for repetition in range(20):
        ids, names, commanded, attained, measured = iso_cycles(delta, np.random.default_rng(100 + repetition))
        out = pipe.accuracy(model, ids, names, commanded, measured, noise_draws=50)
        for k, p in enumerate(out["positions"]):
            rows = [j for j in range(len(ids)) if names[j] == f"P{k + 1}"]
            true_ap = attained[rows].mean(0) - commanded[rows[0]]
            z.extend((p["ap_xyz"] - true_ap) / p["sigma_ap_xyz"])
    z = np.array(z)
    print(f"AP_x/y/z: std(error/sigma) {z.std():.3f} over {len(z)}, max |z| {np.abs(z).max():.2f}")
    assert 0.8 <= z.std() <= 1.25
    assert np.abs(z).max() < 4.0
