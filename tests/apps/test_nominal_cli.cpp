// Every model's own identified file goes through every reader (doc/mechanisms.md, "Files"):
// identify → fkm → ikm → plan --nominal → identify --nominal, and a Delta of another size than
// the built-in one is identified from its own nominal geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "held_out_score.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

// A plan workspace around the model's reference pose: ±50 mm (Delta, H4) or ±20 mm and ±3° (hexapod).
std::string workspaceAround(const mech::RegisteredModel& model) {
  const mech::Mechanism& m = *model.mechanism;
  const Eigen::VectorXd ref = m.referencePose(model.nominal.values());
  const bool spatial = m.motionType() == mech::MotionType::Spatial;
  const double half = spatial ? 0.02 : 0.05;
  std::ostringstream out;
  const char* axes[3] = {"x_m", "y_m", "z_m"};
  for (int k = 0; k < 3; ++k) out << axes[k] << ": [" << ref[k] - half << ", " << ref[k] + half << "]\n";
  if (m.motionType() == mech::MotionType::Schoenflies) out << "theta_deg: [-15, 15]\n";
  if (spatial) out << "rx_deg: [-3, 3]\nry_deg: [-3, 3]\nrz_deg: [-3, 3]\n";
  return out.str();
}

// The largest angle (|value|, rad) of a written parameter file.
double largestAngle(const fs::path& file, const mech::RegisteredModel& model) {
  const mech::ParameterFile written = mech::readParameterFile(file);
  double largest = 0.0;
  for (const mech::Parameter& p : model.nominal.parameters())
    if (const auto* entry = written.find(p.name); entry && p.unit == mech::Unit::Radian)
      largest = std::max(largest, std::abs(written.number(*entry)));
  return largest;
}

TEST(NominalCli, EveryModelsIdentifiedFileGoesThroughEveryReader) {
  for (const mech::ModelInfo& info : mech::registeredModels()) {
    SCOPED_TRACE(info.name);
    test::TempDir dir;
    const fs::path d = dir.path();
    const datasets::Campaign c = datasets::simulateCampaign(info.name, 21, 0.2e-3, 0.03 * datasets::kCampaignDeg);
    datasets::writeCampaignFiles(c, d, 0, c.poses.size());
    const std::string data = " --poses " + (d / "poses.csv").string() + " --joints " + (d / "joints.csv").string();
    ASSERT_EQ(test::runMireIn(dir, "identify --model " + info.name + data + " -o " + (d / "id.yaml").string()), 0)
        << test::readText(d / "stderr.txt");
    const mech::RegisteredModel model = mech::makeRegisteredModel(info.name);
    EXPECT_LE(largestAngle(d / "id.yaml", model), 2.0 * M_PI);
    ASSERT_EQ(test::runMireIn(dir, "fkm --params " + (d / "id.yaml").string() + " --joints " +
                                       (d / "joints.csv").string() + " -o " + (d / "effector.csv").string()),
              0)
        << test::readText(d / "stderr.txt");
    EXPECT_EQ(test::runMireIn(dir, "ikm --params " + (d / "id.yaml").string() + " --poses " +
                                       (d / "effector.csv").string() + " -o " + (d / "commands.csv").string()),
              0)
        << test::readText(d / "stderr.txt");
    test::writeText(d / "workspace.yaml", workspaceAround(model));
    const std::string plan = "plan --model " + info.name + " --nominal " + (d / "id.yaml").string() + " --workspace " +
                             (d / "workspace.yaml").string() + " --count 20 --candidates 400 -o " +
                             (d / "plan.csv").string();
    const std::string again = "identify --model " + info.name + " --nominal " + (d / "id.yaml").string() + data +
                              " -o " + (d / "again.yaml").string();
    if (!info.variants.empty() && info.name != mech::mechanismFamily(info.family).models.front()) {
      // Its variants start from model 12's values: the error says which file to give.
      EXPECT_EQ(test::runMireIn(dir, again), 1);
      EXPECT_NE(test::readText(d / "stderr.txt").find("give a h4-12 parameter file"), std::string::npos)
          << test::readText(d / "stderr.txt");
      continue;
    }
    EXPECT_EQ(test::runMireIn(dir, plan), 0) << test::readText(d / "stderr.txt");
    EXPECT_EQ(test::runMireIn(dir, again), 0) << test::readText(d / "stderr.txt");
  }
}

TEST(NominalCli, AFileOfAnotherModelIsNamed) {
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c = datasets::simulateCampaign("delta", 22);
  datasets::writeCampaignFiles(c, d, 0, c.poses.size());
  mech::writeParameterFile(d / "hexapod.yaml", mech::makeRegisteredModel("gough-stewart").nominal, {},
                           {{"model", "gough-stewart"}}, "a hexapod");
  EXPECT_EQ(test::runMireIn(dir, "identify --model delta --nominal " + (d / "hexapod.yaml").string() + " --poses " +
                                     (d / "poses.csv").string() + " --joints " + (d / "joints.csv").string() + " -o " +
                                     (d / "id.yaml").string()),
            1);
  const std::string err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("hexapod.yaml:"), std::string::npos) << err;
  EXPECT_NE(err.find("a 'gough-stewart' parameter file, not a nominal for --model delta"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "id.yaml"));
}

// A Delta of R 0.12, r 0.04, L 0.22, l 0.50 m (not mire's built-in size): identified from its
// own nominal geometry, its held-out FKM predictions match the truth at their predicted σ.
TEST(NominalCli, ADeltaOfAnotherSizeIsIdentifiedFromItsNominal) {
  test::TempDir dir;
  const fs::path d = dir.path();
  mech::RegisteredModel small = mech::makeRegisteredModel("delta");
  for (const auto& [name, value] : {std::pair<const char*, double>{"R", 0.12}, {"r", 0.04}, {"L", 0.22}, {"l", 0.50}})
    small.nominal.setValue(name, value);
  const datasets::Campaign c = datasets::simulateCampaign(small, 23, 0.2e-3, 0.03 * datasets::kCampaignDeg, 20);
  const std::size_t train = c.poses.size() - 20;
  datasets::writeCampaignFiles(c, d, 0, train);
  datasets::writeCampaignFiles(c, d, train, 20, "held_poses.csv", "held_joints.csv");
  mech::writeParameterFile(d / "my_delta.yaml", small.nominal, {}, {{"model", "delta"}}, "a small Delta");
  ASSERT_EQ(test::runMireIn(dir, "identify --model delta --nominal " + (d / "my_delta.yaml").string() + " --poses " +
                                     (d / "poses.csv").string() + " --joints " + (d / "joints.csv").string() + " -o " +
                                     (d / "id.yaml").string()),
            0)
      << test::readText(d / "stderr.txt");
  ASSERT_EQ(test::runMireIn(dir, "fkm --params " + (d / "id.yaml").string() + " --joints " +
                                     (d / "held_joints.csv").string() + " -o " + (d / "pred.csv").string()),
            0)
      << test::readText(d / "stderr.txt");
  // The FKM gives the pose in the identified base frame (a gauge, above); the error to the truth
  // is measured through --frame camera.
  ASSERT_EQ(
      test::runMireIn(dir, "fkm --params " + (d / "id.yaml").string() + " --joints " +
                               (d / "held_joints.csv").string() + " --frame camera -o " + (d / "pred_c.csv").string()),
      0)
      << test::readText(d / "stderr.txt");
  const test::HeldOutScore score = test::scoreHeldOutPositions(d / "pred_c.csv", c);
  ASSERT_EQ(score.rows, 20u);
  const double rms_mm = 1e3 * score.rms_m;
  const double ratio = score.ratio;
  std::printf("small Delta, 20 held-out poses: RMS position error %.3f mm, error / predicted sigma %.2f\n", rms_mm,
              ratio);
  EXPECT_LT(rms_mm, 0.3);
  EXPECT_GT(ratio, 0.5);
  EXPECT_LT(ratio, 2.0);
}

// Every shipped description is a model `identify`, `fkm` and `ikm` take by its file name; the
// identified file carries a copy of the description, so it is all fkm needs.
TEST(NominalCli, DescribedMechanismsGoThroughIdentifyFkmAndIkm) {
  for (const auto& entry : fs::directory_iterator(test::sourceDir() / "examples" / "mechanisms")) {
    SCOPED_TRACE(entry.path().filename().string());
    test::TempDir dir;
    const fs::path d = dir.path();
    const datasets::Campaign c = datasets::simulateCampaign(mech::makeRegisteredModel(entry.path().string()), 24,
                                                            0.2e-3, 0.03 * datasets::kCampaignDeg, 20);
    const std::size_t train = c.poses.size() - 20;
    datasets::writeCampaignFiles(c, d, 0, train);
    datasets::writeCampaignFiles(c, d, train, 20, "held_poses.csv", "held_joints.csv");
    ASSERT_EQ(test::runMireIn(dir, "identify --model " + entry.path().string() + " --poses " + (d / "poses.csv").string() +
                                       " --joints " + (d / "joints.csv").string() + " -o " + (d / "id.yaml").string()),
              0)
        << test::readText(d / "stderr.txt");
    EXPECT_NE(test::readText(d / "id.yaml").find("id_mechanism.yaml"), std::string::npos);
    ASSERT_TRUE(fs::exists(d / "id_mechanism.yaml"));
    ASSERT_EQ(
        test::runMireIn(dir, "fkm --params " + (d / "id.yaml").string() + " --joints " +
                                 (d / "held_joints.csv").string() + " --frame camera -o " + (d / "pred.csv").string()),
        0)
        << test::readText(d / "stderr.txt");
    const test::HeldOutScore score = test::scoreHeldOutPositions(d / "pred.csv", c);
    ASSERT_EQ(score.rows, 20u);
    const double ratio = score.ratio;
    std::printf("%s: 20 held-out poses, RMS position error %.3f mm, error / predicted sigma %.2f\n",
                entry.path().filename().string().c_str(), 1e3 * score.rms_m, ratio);
    EXPECT_GT(ratio, 0.5);
    EXPECT_LT(ratio, 2.0);
    // ikm of the base-frame FKM poses gives the held-out joints back.
    test::expectFkmIkmRoundTrip(dir, 20u);
  }
}

}  // namespace
}  // namespace mire::app
