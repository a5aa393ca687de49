// `mire accuracy` (doc/accuracy.md) on a simulated ISO 9283 test: a Delta identified by
// `mire identify`, driven by its nominal model's commands to the 5 positions of the cube's
// diagonal plane for 30 cycles; the true robot's attained poses are measured with 0.2 mm / 0.03°
// noise. The figures against those of the true attained poses, the noise-only warnings, and bad
// input named.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "identified_frame.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/pose_accuracy.hpp"
#include "report_json.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct IsoTest {
  std::vector<mech::AccuracySample> truth;  // commanded and true attained poses
};

// The cycles of the ISO test: commanded.csv, poses.csv (measured, noise σ columns) in `d`.
// The commanded poses are written in the identified base frame (doc/conventions.md).
IsoTest writeIsoTest(const datasets::Campaign& c, const fs::path& d, double scatter, unsigned seed) {
  const Eigen::Isometry3d identified_to_true = test::identifiedToTrue(d / "id.yaml", c, c.poses.size());
  const mech::Mechanism& m = *c.model.mechanism;
  const Eigen::VectorXd ref = m.referencePose(c.truth.values());
  const Eigen::Vector3d centre(ref[0], ref[1], ref[2]);
  const Eigen::Vector3d corners[5] = {{0, 0, 0}, {-1, -1, 1}, {1, 1, 1}, {1, 1, -1}, {-1, -1, -1}};
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::ostringstream commanded;
  commanded << "pose_id,position,x_m,y_m,z_m\n";
  datasets::Campaign measured = c;
  measured.poses.clear();
  IsoTest out;
  for (int j = 0; j < 30; ++j)
    for (int p = 0; p < 5; ++p) {
      const Eigen::Vector3d target = centre + Eigen::Vector3d(0.08, 0.08, 0.05).cwiseProduct(corners[p]);
      const std::string id = "P" + std::to_string(p + 1) + "_" + std::to_string(j + 1);
      const Eigen::Vector3d in_identified = identified_to_true.inverse() * target;
      commanded << id << ",P" << p + 1 << ',' << support::formatNumber(in_identified.x()) << ','
                << support::formatNumber(in_identified.y()) << ',' << support::formatNumber(in_identified.z()) << '\n';
      const Eigen::Isometry3d bTe_cmd = m.poseToTransform(target);
      // The controller runs the nominal model; the true robot goes where those joints take it.
      const mech::IkmResult q = m.inverseKinematics(c.model.nominal.values(), bTe_cmd);
      const mech::FkmResult f = m.forwardKinematics(c.truth.values(), q.joints, target);
      EXPECT_TRUE(f.converged);
      Eigen::Isometry3d attained = f.bTe;
      attained.translation() += scatter * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      out.truth.push_back({id, "P" + std::to_string(p + 1), bTe_cmd, attained, {}});
      mech::PoseObservation o;
      o.id = id;
      o.cTm = mech::toPoseVector(c.bTc.inverse() * attained * c.mTe.inverse());
      for (int k = 0; k < 3; ++k) o.cTm[k] += 0.2e-3 * normal(rng);
      for (int k = 3; k < 6; ++k) o.cTm[k] += 0.03 * datasets::kCampaignDeg * normal(rng);
      o.joints = q.joints;
      measured.poses.push_back(o);
    }
  support::writeFileAtomically(d / "commanded.csv", commanded.str());
  datasets::writeCampaignFiles(measured, d, 0, measured.poses.size(), "cycles.csv", "cycle_joints.csv");
  return out;
}

// Two straight-line motions of 15 points, commanded with the nominal model and measured; the
// poses.csv columns plus line_id in `d`/lines.csv. Returns the true straightness (RMS) of each.
std::vector<double> writeLines(const datasets::Campaign& c, const fs::path& d, unsigned seed) {
  const mech::Mechanism& m = *c.model.mechanism;
  const Eigen::VectorXd ref = m.referencePose(c.truth.values());
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::ostringstream out;
  out << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
         "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px,line_id\n";
  std::vector<double> truth;
  const Eigen::Vector3d directions[2] = {{1, 0, 0}, {0.6, 0.6, 0.3}};
  for (int l = 0; l < 2; ++l) {
    std::vector<Eigen::Vector3d> attained;
    for (int k = 0; k < 15; ++k) {
      const Eigen::Vector3d target = Eigen::Vector3d(ref[0], ref[1], ref[2]) + (k - 7) * 0.012 * directions[l];
      const mech::IkmResult q = m.inverseKinematics(c.model.nominal.values(), m.poseToTransform(target));
      const mech::FkmResult f = m.forwardKinematics(c.truth.values(), q.joints, target);
      EXPECT_TRUE(f.converged);
      attained.push_back(f.bTe.translation());
      mech::PoseVector cTm = mech::toPoseVector(c.bTc.inverse() * f.bTe * c.mTe.inverse());
      for (int i = 0; i < 3; ++i) cTm[i] += 0.2e-3 * normal(rng);
      for (int i = 3; i < 6; ++i) cTm[i] += 0.03 * datasets::kCampaignDeg * normal(rng);
      out << "L" << l + 1 << "_" << k + 1 << ",10,10";
      for (int i = 0; i < 6; ++i) out << ',' << support::formatNumber(cTm[i]);
      out << ",0.2,0.2,0.2,0.03,0.03,0.03,0.1,L" << l + 1 << "\n";
    }
    truth.push_back(mech::lineStraightness("L", attained, {}).rms);
  }
  support::writeFileAtomically(d / "lines.csv", out.str());
  return truth;
}

class AccuracyCli : public ::testing::Test {
 protected:
  void SetUp() override {
    c_ = datasets::simulateCampaign("delta", 11);
    datasets::writeCampaignFiles(c_, d(), 0, c_.poses.size());
    ASSERT_EQ(test::runMireIn(dir_, "identify --model delta --poses " + (d() / "poses.csv").string() + " --joints " +
                                        (d() / "joints.csv").string() + " -o " + (d() / "id.yaml").string()),
              0)
        << test::readText(d() / "stderr.txt");
  }
  fs::path d() const { return dir_.path(); }
  int accuracy(const std::string& extra = {}) {
    return test::runMireIn(dir_, "accuracy --params " + (d() / "id.yaml").string() + " --commanded " +
                                     (d() / "commanded.csv").string() + " --poses " + (d() / "cycles.csv").string() +
                                     " -o " + (d() / "accuracy.json").string() + extra);
  }
  test::TempDir dir_;
  datasets::Campaign c_;
};

TEST_F(AccuracyCli, FiguresAgainstTheTrueAttainedPoses) {
  const IsoTest iso = writeIsoTest(c_, d(), 0.05e-3, 5);
  ASSERT_EQ(accuracy(), 0) << test::readText(d() / "stderr.txt");
  std::ifstream in(d() / "accuracy.json");
  const Json doc = Json::parse(in);
  ASSERT_EQ(doc["positions"].size(), 5u);
  ASSERT_EQ(doc["distances"].size(), 10u);
  const auto truth = mech::poseAccuracy(iso.truth);
  int flagged = 0;
  for (std::size_t p = 0; p < 5; ++p) {
    const Json& j = doc["positions"][p];
    EXPECT_EQ(j["cycles"], 30);
    // The identified mounting frames the attained poses: its own error (identification σ) adds
    // to the measurement's, so the bound is the σ plus the identification's 0.1 mm level.
    const double ap = j["AP_p_m"].get<double>();
    std::printf("%s: AP_p %.4f mm (truth %.4f, sigma %.4f), RP_l %.4f mm (truth %.4f, noise-only p95 %.4f)\n",
                truth[p].position.c_str(), ap * 1e3, truth[p].ap_p * 1e3, j["sigma_AP_p_m"].get<double>() * 1e3,
                j["RP_l_m"].get<double>() * 1e3, truth[p].rp_l * 1e3, j["noise_only_RP_l_m"]["p95"].get<double>() * 1e3);
    EXPECT_NEAR(ap, truth[p].ap_p, 3 * j["sigma_AP_p_m"].get<double>() + 0.1e-3);
    EXPECT_GT(truth[p].ap_p, 0.3e-3);  // the nominal controller's error is there to be measured
    for (const auto& w : j["warnings"]) flagged += w.get<std::string>().rfind("RP_l", 0) == 0;
  }
  // 0.05 mm of scatter under 0.2 mm of noise: RP_l is the noise's, and said so (at a position
  // the draw can exceed the noise-only 95th percentile; at most of them it does not).
  EXPECT_GE(flagged, 3);
  EXPECT_NE(test::readText(d() / "stdout.txt").find("warning: position P1: RP_l"), std::string::npos);

  // Straightness of measured straight-line motions against the true attained positions'.
  const std::vector<double> straight = writeLines(c_, d(), 8);
  ASSERT_EQ(accuracy(" --lines " + (d() / "lines.csv").string()), 0) << test::readText(d() / "stderr.txt");
  std::ifstream again(d() / "accuracy.json");
  const Json with_lines = Json::parse(again);
  ASSERT_EQ(with_lines["lines"].size(), 2u);
  for (std::size_t l = 0; l < 2; ++l) {
    const Json& j = with_lines["lines"][l];
    EXPECT_EQ(j["points"], 15);
    const double beyond = j["straightness_rms_beyond_noise_m"].get<double>();
    std::printf(
        "line %s: straightness RMS %.4f mm measured, %.4f mm beyond the noise (noise-only %.4f), true %.4f mm\n",
        j["line"].get<std::string>().c_str(), j["straightness_rms_m"].get<double>() * 1e3, beyond * 1e3,
        j["noise_only_rms_m"]["mean"].get<double>() * 1e3, straight[l] * 1e3);
    // The true lines are straight to 0.01 mm, far below 0.2 mm of noise: not resolved, and said so.
    EXPECT_LT(straight[l], 0.02e-3);
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_EQ(j["warnings"][0].get<std::string>().rfind("straightness", 0), 0u);
  }
}

TEST_F(AccuracyCli, BadInputIsNamed) {
  writeIsoTest(c_, d(), 0.0, 6);
  // A measured pose without a command: named by file and line.
  {
    std::ofstream out(d() / "cycles.csv", std::ios::app);
    out << "stray,10,10,0,0,1,0,0,0,0.2,0.2,0.2,0.03,0.03,0.03,0.1\n";
  }
  EXPECT_EQ(accuracy(), 1);
  EXPECT_NE(test::readText(d() / "stderr.txt").find("cycles.csv:152: measured pose 'stray' has no commanded pose"),
            std::string::npos)
      << test::readText(d() / "stderr.txt");
  EXPECT_FALSE(fs::exists(d() / "accuracy.json"));
  // A commanded file without the position column.
  writeIsoTest(c_, d(), 0.0, 6);
  std::string text = test::readText(d() / "commanded.csv");
  text.replace(text.find("position"), 8, "place");
  support::writeFileAtomically(d() / "commanded.csv", text);
  EXPECT_EQ(accuracy(), 1);
  EXPECT_NE(test::readText(d() / "stderr.txt").find("position"), std::string::npos);
  EXPECT_NE(test::readText(d() / "stderr.txt").find("commanded.csv"), std::string::npos);
  // A command never measured: the others are evaluated, exit 3.
  writeIsoTest(c_, d(), 0.0, 6);
  {
    std::ofstream out(d() / "commanded.csv", std::ios::app);
    out << "extra,P1,0,0,-0.65\n";
  }
  EXPECT_EQ(accuracy(), 3);
  EXPECT_NE(test::readText(d() / "stderr.txt").find("pose 'extra' has no measured pose"), std::string::npos);
  EXPECT_TRUE(fs::exists(d() / "accuracy.json"));
}

}  // namespace
}  // namespace mire::app
