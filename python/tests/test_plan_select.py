"""`mire plan` and `mire select` through the Python API (doc/plan-and-select.md): the plan equals
the CLI's plan.csv for the same inputs and seed, the planned poses determine the H4's geometry
better than random ones, and the selection on a simulated exact-model-12 H4 campaign recommends a
model-12 variant, the same one `mire select` prints."""
import numpy as np
import pytest

import mire
from conftest import assert_relative, read_csv, run_cli
from test_cli_equality import write_campaign
from test_mechanisms import Robot

mech = mire.mechanism
DEG = np.pi / 180  # the CLI's degree (3.14159265358979323846 / 180): the same double
SEED, CANDIDATES, COUNT = 3, 2000, 15
WORKSPACE_YAML = "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_deg: [-20, 20]\njoint_margin_deg: 1\n"


def h4_workspace():
    """The workspace WORKSPACE_YAML describes, built as `mire plan` reads it."""
    w = mech.Workspace()
    w.x, w.y, w.z = mech.Interval(-0.1, 0.1), mech.Interval(-0.1, 0.1), mech.Interval(-0.70, -0.55)
    w.rotations = [mech.Interval(-20 * DEG, 20 * DEG)]
    w.joint_margin = 1.0 * DEG
    return w


@pytest.fixture(scope="module")
def plan():
    """The h4-12 plan of 15 poses among 2000 candidates, as `mire plan` computes it."""
    model = mech.makeDesignModel("h4-12")
    mechanism, geometric = model.registered.mechanism, model.registered.nominal.values()
    workspace = h4_workspace()
    poses = mech.generateCandidatePoses(mechanism, geometric, workspace, CANDIDATES, SEED)
    options = mech.DesignOptions()
    options.count, options.seed = COUNT, SEED
    info = mech.candidateInformation(model, mech.defaultMountingGuess(workspace), poses, options)
    return poses, options, info, mech.planExperiment(info, options)


def test_plan_equals_mire_plan(plan, tmp_path):
    poses, options, info, report = plan
    assert poses.shape == (CANDIDATES, 4) and info.poses.shape == (CANDIDATES, 4)
    (tmp_path / "workspace.yaml").write_text(WORKSPACE_YAML)
    stdout = run_cli("plan", "--model", "h4-12", "--workspace", tmp_path / "workspace.yaml", "--count", COUNT,
                     "--candidates", CANDIDATES, "--seed", SEED, "-o", tmp_path / "plan.csv",
                     "--report", tmp_path / "report")
    rows = read_csv(tmp_path / "plan.csv")
    assert len(rows) == COUNT == len(report.design) == len(set(report.design))
    pose_columns = ["x_m", "y_m", "z_m", "theta_rad"]
    joint_columns = info.model.mechanism.jointColumnNames()
    candidate_poses, observations = info.poses, info.observations  # each access converts: once
    for k, (row, j) in enumerate(zip(rows, report.design)):
        assert row["pose_id"] == f"p{k + 1:03d}"
        # 17 significant digits in the file: the same doubles.
        np.testing.assert_array_equal([float(row[c]) for c in pose_columns], candidate_poses[j], err_msg=row["pose_id"])
        np.testing.assert_array_equal([float(row[c]) for c in joint_columns], observations[j].joints)
    sigma = read_csv(tmp_path / "report" / "plan_sigma.csv")
    assert [r["name"] for r in sigma] == report.names == info.free_names
    for column in ("sigma_plan", "sigma_random", "sigma_all"):  # 6 significant digits in the file
        assert_relative([float(r[column]) for r in sigma], getattr(report, column), 5e-6, column)
    # The printed report is designReportText (but for the time line).
    text = "\n".join(l for l in mech.designReportText(report).splitlines() if not l.startswith("poses chosen:"))
    printed = "\n".join(l for l in stdout.splitlines() if not l.startswith("poses chosen:"))
    assert text in printed


def test_planned_sigma_beats_random(plan):
    poses, options, info, report = plan
    g = report.geometric_free
    assert g == 12 and len(report.names) == 19
    np.testing.assert_allclose(mech.designSigma(info, report.design), report.sigma_plan, rtol=1e-12)
    # Recomputed here: 50 random 15-subsets of the same candidates, median σ per parameter.
    rng = np.random.default_rng(5)
    random = np.array([mech.designSigma(info, sorted(rng.choice(CANDIDATES, COUNT, replace=False).tolist()))
                       for _ in range(50)])
    ratio = np.median(report.sigma_plan[:g] / np.median(random, axis=0)[:g])
    print(f"median sigma ratio plan/random: report {report.median_ratio_plan_random:.3f}, recomputed {ratio:.3f}; "
          f"position sigma rms plan {report.position_sigma_plan_rms * 1e3:.4f} mm, "
          f"random {report.position_sigma_random_rms * 1e3:.4f} mm")
    assert report.median_ratio_plan_random < 0.6
    assert ratio < 0.6
    assert report.position_sigma_plan_rms < report.position_sigma_random_rms
    assert np.all(report.sigma_all[:g] < report.sigma_plan[:g])  # 2000 poses know more than 15
    # Ds-criterion (log det of the Schur complement on the geometric block): the plan's is larger
    # than every random subset's.
    def ds(design):
        m = mech.fisherInformation(info, design)
        return np.linalg.slogdet(m)[1] - np.linalg.slogdet(m[g:, g:])[1]
    assert mech.fisherInformation(info, report.design).shape == (19, 19)
    planned = ds(report.design)
    assert all(planned > ds(sorted(rng.choice(CANDIDATES, COUNT, replace=False).tolist())) for _ in range(20))
    with pytest.raises(ValueError, match="poses are needed"):
        options3 = mech.DesignOptions()
        options3.count = 3
        mech.chooseDesign(info, options3)


def test_select_recommends_the_model_12_variant_mire_select_prints(tmp_path):
    write_campaign(tmp_path, Robot(), np.random.default_rng(21))
    stdout = run_cli("select", "--poses", tmp_path / "poses.csv", "--joints", tmp_path / "joints.csv")
    mechanism = mech.makeRegisteredModel("h4-12").mechanism
    observations = mech.readObservations(tmp_path / "poses.csv", tmp_path / "joints.csv", None,
                                         mechanism.jointColumnNames())
    models = mech.defaultSelectionModels(4, mech.Unit.Radian)
    candidates = mech.parseSelectionCandidates(models)
    assert [c.label for c in candidates] == list("ABCDEFGH")
    assert [c.variant for c in candidates] == list("ABCDEFGH")
    result = mech.selectModel(candidates, observations.poses, [], mech.SelectionOptions())
    label = result.recommendedLabel()
    print(mech.selectionTable(result, mech.Unit.Radian) + f"recommended: {label} ({result.seconds:.2f} s)")
    assert stdout.splitlines()[-1] == f"recommended: {label}"
    assert mech.h4Variant(label).model == mech.H4ModelKind.Model12  # the truth is a model-12 robot
    assert candidates[result.recommended].label == label
    assert mech.selectionTable(result, mech.Unit.Radian) in stdout
    best = result.scores[result.best]
    recommended = result.scores[result.recommended]
    assert all(s.ok for s in result.scores)
    assert recommended.cv_mse <= best.cv_mse + best.cv_se  # the one-SE rule
    # The fit residual is at the simulated noise level (0.2 mm / 0.03° of cTm ≈ 1e-4 rad of joint).
    assert 1e-5 < recommended.fit_rms < 1e-3
    with pytest.raises(ValueError, match="variant E does not belong to h4-12"):
        mech.parseSelectionCandidates("h4-12:E")


def test_pose_covariance_callable_weights_the_information(plan):
    """A Python covariance provider (the C++ PoseCovarianceProvider): the options' σ give the
    same information; 2× the σ doubles every predicted σ."""
    poses, options, info, report = plan
    model = mech.makeDesignModel("h4-12")
    mounting = mech.defaultMountingGuess(h4_workspace())
    base = np.diag([options.sigma_translation ** 2] * 3 + [options.sigma_rotation ** 2] * 3)
    calls = []

    def same(cTm):
        calls.append(cTm.shape)
        return base

    subset = poses[:200]
    reference = mech.candidateInformation(model, mounting, subset, options)
    weighted = mech.candidateInformation(model, mounting, subset, options, covariance=same)
    assert len(calls) == 200 and calls[0] == (6,)
    np.testing.assert_array_equal(np.array(weighted.rows), np.array(reference.rows))
    doubled = mech.candidateInformation(model, mounting, subset, options, covariance=lambda cTm: 4 * base)
    design = list(range(40))
    np.testing.assert_allclose(mech.designSigma(doubled, design), 2 * mech.designSigma(reference, design), rtol=1e-9)
    with pytest.raises(ValueError, match="4 columns"):
        mech.candidateInformation(model, mounting, subset[:, :3], options)


def test_shared_calibration_term_enters_the_design_covariance_once(plan):
    """The calibration's error shared by every pose (a focal-scale-like error: ∂tz/∂k = tz):
    the design covariance is the fit's term from the independent part plus G Σ_k Gᵀ, as
    doc/plan-and-select.md states, here recomputed from the rows the binding exposes."""
    poses, options, info, report = plan
    model = mech.makeDesignModel("h4-12")
    mounting = mech.defaultMountingGuess(h4_workspace())
    base = np.diag([options.sigma_translation ** 2] * 3 + [options.sigma_rotation ** 2] * 3)
    sigma_k = np.array([[1e-6]])

    def sensitivity(cTm):
        d = np.zeros((6, 1))
        d[2, 0] = cTm[2]
        return d

    def total(cTm):
        d = sensitivity(cTm)
        return base + d @ sigma_k @ d.T

    subset = poses[:200]
    info = mech.candidateInformation(model, mounting, subset, options, covariance=total,
                                     shared_covariance=sigma_k, shared_sensitivity=sensitivity)
    assert info.hasSharedTerm() and len(info.shared_rows) == 200
    design = list(range(40))
    A = [np.array(info.rows[j]) for j in design]
    R = [np.array(info.shared_rows[j]) for j in design]
    H_inv = np.linalg.inv(sum(a.T @ a for a in A))
    G = H_inv @ sum(a.T @ r for a, r in zip(A, R))
    B = sum(a.T @ r @ sigma_k @ r.T @ a for a, r in zip(A, R))
    np.testing.assert_allclose(mech.designSharedCovariance(info, design), G @ sigma_k @ G.T, rtol=1e-6, atol=1e-30)
    expected = H_inv - H_inv @ B @ H_inv + G @ sigma_k @ G.T
    np.testing.assert_allclose(mech.designCovariance(info, design), expected, rtol=1e-6, atol=1e-30)
    with pytest.raises(ValueError, match="go together"):
        mech.candidateInformation(model, mounting, subset, options, shared_covariance=sigma_k)
