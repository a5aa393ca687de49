// `mire compensate` (doc/accuracy.md, "Compensation") on a Delta whose true geometry departs from
// the nominal by 1 mm / 0.5° per parameter, identified by `mire identify` (its gauge holds the
// same parameters as the simulation, so the identified base frame is the true one): the true
// robot driven by the compensated commands reaches the desired poses at the identification's
// noise level, the nominal commands miss them by millimetres; the correction map's commands run
// through the nominal model give the same joints, and their σ matches their spread over
// repeated identifications.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "identified_frame.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/controller_fit.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

void identify(const test::TempDir& dir, const datasets::Campaign& c, std::size_t count) {
  const fs::path d = dir.path();
  datasets::writeCampaignFiles(c, d, 0, count);
  ASSERT_EQ(test::runMireIn(dir, "identify --model delta --poses " + (d / "poses.csv").string() + " --joints " +
                                     (d / "joints.csv").string() + " -o " + (d / "id.yaml").string()),
            0)
      << test::readText(d / "stderr.txt");
}

// Where the true robot goes with joints q.
Eigen::Vector3d truePosition(const datasets::Campaign& c, const Eigen::VectorXd& q, const Eigen::VectorXd& guess) {
  const mech::Mechanism& m = *c.model.mechanism;
  const mech::FkmResult f = m.forwardKinematics(c.truth.values(), q, guess);
  EXPECT_TRUE(f.converged);
  return f.pose.head<3>();
}

TEST(CompensateCli, CommandsReachTheDesiredPoses) {
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c = datasets::simulateCampaign("delta", 21, 0.2e-3, 0.03 * datasets::kCampaignDeg, 20);
  const std::size_t train = c.poses.size() - 20;
  identify(dir, c, train);
  const Eigen::Isometry3d to_true = test::identifiedToTrue(d / "id.yaml", c, train);
  std::ostringstream desired;
  desired << "pose_id,x_m,y_m,z_m\n";
  for (std::size_t j = train; j < c.bTe.size(); ++j) {
    const Eigen::Vector3d t = to_true.inverse() * c.bTe[j].translation();
    desired << "d" << j << ',' << support::formatNumber(t.x()) << ',' << support::formatNumber(t.y()) << ','
            << support::formatNumber(t.z()) << '\n';
  }
  desired << "far,0,0,-5\n";
  support::writeFileAtomically(d / "desired.csv", desired.str());
  EXPECT_EQ(test::runMireIn(dir, "compensate --params " + (d / "id.yaml").string() + " --poses " +
                                     (d / "desired.csv").string() + " -o " + (d / "commands.csv").string()),
            3);
  EXPECT_NE(test::readText(d / "stderr.txt").find("pose 'far' is unreachable"), std::string::npos)
      << test::readText(d / "stderr.txt");
  const support::CsvTable commands = support::readCsv(d / "commands.csv");
  ASSERT_EQ(commands.rows.size(), 20u);
  const mech::Mechanism& m = *c.model.mechanism;
  double compensated = 0.0, nominal = 0.0;
  for (std::size_t r = 0; r < 20; ++r) {
    const Eigen::Vector3d want = c.bTe[train + r].translation();
    Eigen::VectorXd q(3);
    for (int k = 0; k < 3; ++k) q[k] = commands.number(r, commands.column("q" + std::to_string(k + 1) + "_rad"));
    compensated += (truePosition(c, q, want) - want).squaredNorm();
    const Eigen::VectorXd q_nominal = m.inverseKinematics(c.model.nominal.values(), c.bTe[train + r]).joints;
    nominal += (truePosition(c, q_nominal, want) - want).squaredNorm();
  }
  compensated = std::sqrt(compensated / 20);
  nominal = std::sqrt(nominal / 20);
  std::printf(
      "delta, 20 held-out desired poses: RMS position error of the true robot %.3f mm with compensated "
      "commands, %.3f mm with nominal ones\n",
      compensated * 1e3, nominal * 1e3);
  EXPECT_LT(compensated, 0.15e-3);  // the identification's noise level (0.2 mm measurements, 27 poses)
  EXPECT_GT(nominal, 5 * compensated);
}

TEST(CompensateCli, CorrectionMapSigmaMatchesItsSpread) {
  const std::string box = " --workspace -0.1,0.1,-0.1,0.1,-0.7,-0.6";
  std::vector<double> z;
  double worst_joint = 0.0, nominal_rms = 0.0, corrected_rms = 0.0;
  int points = 0;
  for (unsigned seed = 31; seed < 37; ++seed) {
    test::TempDir dir;
    const fs::path d = dir.path();
    // One true robot (seed 31's defects), a new measurement noise each time.
    datasets::Campaign c = datasets::simulateCampaign("delta", 31, 0.2e-3, 0.03 * datasets::kCampaignDeg);
    if (seed != 31) {
      std::mt19937 rng(seed);
      std::normal_distribution<double> normal;
      for (auto& p : c.poses) {
        p.cTm = mech::toPoseVector(c.bTc.inverse() * c.bTe[std::stoul(p.id) - 1] * c.mTe.inverse());
        for (int k = 0; k < 3; ++k) p.cTm[k] += 0.2e-3 * normal(rng);
        for (int k = 3; k < 6; ++k) p.cTm[k] += 0.03 * datasets::kCampaignDeg * normal(rng);
      }
    }
    identify(dir, c, c.poses.size());
    const Eigen::Isometry3d to_true = test::identifiedToTrue(d / "id.yaml", c, c.poses.size());
    ASSERT_EQ(test::runMireIn(dir, "compensate --params " + (d / "id.yaml").string() + " --grid 0.1" + box + " -o " +
                                       (d / "map.csv").string()),
              0)
        << test::readText(d / "stderr.txt");
    const support::CsvTable map = support::readCsv(d / "map.csv");
    ASSERT_EQ(map.rows.size(), 18u);  // 3 × 3 × 2
    const mech::Mechanism& m = *c.model.mechanism;
    const Eigen::VectorXd nominal = c.model.nominal.values();
    for (std::size_t r = 0; r < map.rows.size(); ++r) {
      Eigen::VectorXd want(3), command(3), sigma(3);
      const char* axes[3] = {"x", "y", "z"};
      for (int k = 0; k < 3; ++k) {
        want[k] = map.number(r, map.column(std::string(axes[k]) + "_m"));
        command[k] = map.number(r, map.column(std::string("command_") + axes[k] + "_m"));
        sigma[k] = map.number(r, map.column(std::string("sigma_command_") + axes[k] + "_mm")) * 1e-3;
      }
      // `want` is in the identified frame; the true robot must reach the same physical point.
      const Eigen::Vector3d physical = to_true * Eigen::Vector3d(want.head<3>());
      Eigen::VectorXd physical_pose = want;
      physical_pose.head<3>() = physical;
      // σ is the command's uncertainty in the frame the model's gauge defines, the simulation's
      // true base frame (its held parameters are the truth's): against the exact command there.
      const Eigen::VectorXd q_true = m.inverseKinematics(c.truth.values(), m.poseToTransform(want)).joints;
      const mech::FkmResult exact = m.forwardKinematics(nominal, q_true, want);
      ASSERT_TRUE(exact.converged);
      for (int k = 0; k < 3; ++k) z.push_back((command[k] - exact.pose[k]) / sigma[k]);
      const Eigen::VectorXd q_physical = m.inverseKinematics(c.truth.values(), m.poseToTransform(physical_pose)).joints;
      // The nominal controller fed the command drives the true robot to `want` (up to the identification).
      const Eigen::VectorXd q = m.inverseKinematics(nominal, m.poseToTransform(command)).joints;
      corrected_rms += (truePosition(c, q, physical_pose) - physical).squaredNorm();
      const Eigen::VectorXd q_plain = m.inverseKinematics(nominal, m.poseToTransform(physical_pose)).joints;
      nominal_rms += (truePosition(c, q_plain, physical_pose) - physical).squaredNorm();
      worst_joint = std::max(worst_joint, (q - q_physical).cwiseAbs().maxCoeff());
      ++points;
    }
  }
  double s = 0;
  for (double v : z) s += v * v;
  const double rms_z = std::sqrt(s / static_cast<double>(z.size()));
  corrected_rms = std::sqrt(corrected_rms / points);
  nominal_rms = std::sqrt(nominal_rms / points);
  std::printf(
      "delta correction map, 6 identifications x 18 grid points: rms(error/sigma) %.3f in the gauge's frame; "
      "true robot RMS error %.3f mm corrected (frames aligned), %.3f mm nominal; worst joint %.2e rad\n",
      rms_z, corrected_rms * 1e3, nominal_rms * 1e3, worst_joint);
  EXPECT_GT(rms_z, 0.8);
  EXPECT_LT(rms_z, 1.25);
  EXPECT_LT(corrected_rms, 0.15e-3);
  EXPECT_GT(nominal_rms, 5 * corrected_rms);
}

// The residual RMS of the TRUE robot driven by a controller running `controller` at `values` over
// the grid, frame-free: the attained positions rigidly aligned onto the commanded ones.
double trueResidual(const datasets::Campaign& c, const mech::Mechanism& controller, const Eigen::VectorXd& values,
                    const std::vector<Eigen::VectorXd>& grid,
                    const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity()) {
  Eigen::Matrix3Xd attained(3, static_cast<Eigen::Index>(grid.size())), wanted(3, static_cast<Eigen::Index>(grid.size()));
  for (std::size_t j = 0; j < grid.size(); ++j) {
    const mech::IkmResult q = controller.inverseKinematics(
        values,
        controller.poseToTransform(mech::controllerCommand(controller, frame, controller.poseToTransform(grid[j]))));
    EXPECT_TRUE(q.reachable());
    attained.col(static_cast<Eigen::Index>(j)) = truePosition(c, q.joints, grid[j]);
    wanted.col(static_cast<Eigen::Index>(j)) = grid[j].head<3>();
  }
  const Eigen::Isometry3d align(Eigen::umeyama(attained, wanted, false));
  return std::sqrt(((align * attained) - wanted).colwise().squaredNorm().mean());
}

// The acceptance of doc/accuracy.md, "Controller model": a robot whose geometry departs from the
// richer model's nominal by 1 mm / 0.5° per parameter (a Delta's legs differ), identified with the
// richer model; the fitted simpler controller within 1.3× the best one's residual (fitted against
// the TRUE robot), full-model commands at the identification's noise level; both against the
// nominal controller. Positions only (frame-free after a rigid alignment).
// `best_above_noise`: the simpler model's own residual exceeds the identification's; when it does not
// (the hexapod's nominal joints leave 0.02 mm), the fitted controller is bounded by both added in
// quadrature instead of the 1.3× criterion.
void controllerAcceptance(const std::string& truth_model, const std::string& controller_model,
                          const Eigen::Vector3d& half_box, bool best_above_noise = true, unsigned seed = 41,
                          int extra = 400, double nominal_over_fitted = 2.0) {
  test::TempDir dir;
  const fs::path d = dir.path();
  // The protocol + 400 random poses: the fitted controller carries the part of the
  // identification's own error that the simpler model can represent (its residual lies near
  // √(best² + that part²)), so the 1.3× criterion needs an identification well below what the
  // simpler model cannot represent; with 54 random poses a Delta of seed 42 fails it at 1.76×
  // (identification 0.064 mm against best 0.042 mm), with 400 it passes at 1.11×
  // (doc/studies/2026-11-26-compensation.md).
  const datasets::Campaign c =
      datasets::simulateCampaign(truth_model, seed, 0.2e-3, 0.03 * datasets::kCampaignDeg, extra);
  datasets::writeCampaignFiles(c, d, 0, c.poses.size());
  ASSERT_EQ(test::runMireIn(dir, "identify --model " + truth_model + " --poses " + (d / "poses.csv").string() +
                                     " --joints " + (d / "joints.csv").string() + " -o " + (d / "id.yaml").string()),
            0)
      << test::readText(d / "stderr.txt");
  const mech::RegisteredModel controller = mech::makeRegisteredModel(controller_model);
  const Eigen::VectorXd ref = c.model.mechanism->referencePose(c.truth.values());
  const Eigen::Vector3d low = ref.head<3>() - half_box, high = ref.head<3>() + half_box;
  std::ostringstream box;
  box << support::formatNumber(low.x()) << ',' << support::formatNumber(high.x()) << ','
      << support::formatNumber(low.y()) << ',' << support::formatNumber(high.y()) << ','
      << support::formatNumber(low.z()) << ',' << support::formatNumber(high.z());
  ASSERT_EQ(test::runMireIn(dir, "compensate --params " + (d / "id.yaml").string() + " --controller-model " +
                                     controller_model + " --workspace " + box.str() + " -o " +
                                     (d / "controller.yaml").string()),
            0)
      << test::readText(d / "stderr.txt");
  EXPECT_NE(test::readText(d / "stdout.txt").find("cannot correct"), std::string::npos);
  EXPECT_NE(test::readText(d / "stdout.txt").find("expected on the robot, with the identification's uncertainty"),
            std::string::npos);
  mech::ParameterSet fitted = controller.nominal;
  const mech::ParameterFile file = mech::readParameterFile(d / "controller.yaml");
  const std::vector<std::string> frame_keys{"frame_tx", "frame_ty", "frame_tz", "frame_rx", "frame_ry", "frame_rz"};
  mech::applyParameterFile(file, fitted, frame_keys);
  mech::PoseVector f;
  for (int k = 0; k < 6; ++k) f[k] = file.number(*file.find(frame_keys[static_cast<std::size_t>(k)]));
  const Eigen::Isometry3d frame = mech::toIsometry(f);
  std::vector<Eigen::VectorXd> grid;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 3; ++k) {
        Eigen::VectorXd pose = Eigen::VectorXd::Zero(controller.mechanism->poseDof());
        pose.head<3>() = low + (high - low).cwiseProduct(Eigen::Vector3d(i / 4.0, j / 4.0, k / 2.0));
        grid.push_back(pose);
      }
  mech::PredictionModel truth;
  truth.model_name = truth_model;
  truth.mechanism = c.model.mechanism;
  truth.geometric = c.truth;
  const mech::ControllerFit best = mech::fitControllerModel(truth, controller, grid);
  ASSERT_TRUE(best.converged);
  const double r_fitted = trueResidual(c, *controller.mechanism, fitted.values(), grid, frame);
  const double r_best = trueResidual(c, *controller.mechanism, best.parameters.values(), grid, best.frame);
  const double r_nominal = trueResidual(c, *controller.mechanism, controller.nominal.values(), grid);
  const mech::LoadedPredictionModel identified = mech::loadPredictionModel(d / "id.yaml");
  const double r_full = trueResidual(c, *c.model.mechanism, identified.model.geometric.values(), grid);
  std::printf(
      "seed %u, %d extra poses: %s robot, 5x5x3 grid, frame-free RMS: fitted %s controller %.3f mm, best %s %.3f mm "
      "(ratio %.2f), nominal %s %.3f mm, full identified model %.3f mm\n",
      seed, extra, truth_model.c_str(), controller_model.c_str(), r_fitted * 1e3, controller_model.c_str(),
      r_best * 1e3, r_fitted / r_best, controller_model.c_str(), r_nominal * 1e3, r_full * 1e3);
  std::printf("%s", test::readText(d / "stdout.txt").c_str());
  if (best_above_noise)
    EXPECT_LT(r_fitted, 1.3 * r_best);
  else
    EXPECT_LT(r_fitted, 1.3 * std::hypot(r_best, r_full));
  EXPECT_LT(r_full, 0.15e-3);  // the identification's noise level (0.2 mm measurements, 81 poses)
  EXPECT_GT(r_nominal, nominal_over_fitted * r_fitted);
}

TEST(CompensateCli, DeltaControllerFromThePerLegModel) {
  controllerAcceptance("delta-legs", "delta", Eigen::Vector3d(0.1, 0.1, 0.05));
}
TEST(CompensateCli, H4Model12ControllerFromModel31) {
  controllerAcceptance("h4-31", "h4-12", Eigen::Vector3d(0.1, 0.1, 0.05));
}
// The hexapod's analogue of the Delta's: its legs differ (every joint centre and leg length off by
// about 1 mm), identified with the per-leg model, run by a controller with the symmetric layout.
// Measured (seed 41): fitted 0.149 mm, best 0.150 mm, nominal 0.227 mm frame-free — the symmetric
// layout corrects a third of the nominal's error (the per-leg differences stay), hence 1.3×.
TEST(CompensateCli, SymmetricHexapodControllerFromThePerLegModel) {
  controllerAcceptance("gough-stewart", "gough-stewart-symmetric", Eigen::Vector3d(0.04, 0.04, 0.03), true, 41, 400, 1.3);
}
TEST(CompensateCli, HexapodControllerWithNominalJoints) {
  controllerAcceptance("gough-stewart-gains", "gough-stewart", Eigen::Vector3d(0.04, 0.04, 0.03), false);
}

TEST(CompensateCli, BadArgumentsAreNamed) {
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c = datasets::simulateCampaign("delta", 12);
  identify(dir, c, c.poses.size());
  const std::string base = "compensate --params " + (d / "id.yaml").string() + " -o " + (d / "out.csv").string();
  EXPECT_EQ(test::runMireIn(dir, base), 2);
  EXPECT_NE(test::readText(d / "stderr.txt").find("give one of --poses, --grid"), std::string::npos);
  EXPECT_EQ(test::runMireIn(dir, base + " --grid 0.05"), 2);
  EXPECT_NE(test::readText(d / "stderr.txt").find("need --workspace"), std::string::npos);
  EXPECT_EQ(test::runMireIn(dir, base + " --grid 0.05 --workspace 0,1,0,1"), 2);
  EXPECT_NE(test::readText(d / "stderr.txt").find("expected xmin,xmax"), std::string::npos);
  EXPECT_EQ(test::runMireIn(dir, base + " --grid 0.0001 --workspace -1,1,-1,1,-1,0"), 2);
  EXPECT_NE(test::readText(d / "stderr.txt").find("take a larger step"), std::string::npos);
  EXPECT_FALSE(fs::exists(d / "out.csv"));
}

}  // namespace
}  // namespace mire::app
