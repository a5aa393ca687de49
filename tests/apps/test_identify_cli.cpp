// `mire identify` end to end on files written from the simulated true H4: a happy path, and bad
// input that must stop with a message naming the cause, a non-zero exit and nothing written.
#include <gtest/gtest.h>

#include "mire/datasets/h4_true_robot.hpp"
#include "mire/mechanism/io.hpp"
#include "test_support.hpp"

#include <fstream>
#include <random>
#include <sstream>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

// A defect-free true robot (so the identified values can be compared with the truth).
struct CliCampaign {
  test::TempDir dir;
  datasets::H4Model12Values truth;
  CliCampaign() {
    const auto sizes = datasets::H4ErrorSizes::withoutUnmodelledDefects();
    truth = datasets::drawModel12Values({}, sizes, 3);
    const datasets::H4TrueKinematics robot(datasets::makeTrueGeometry({}, sizes, 3));
    datasets::H4MeasurementNoise noise;
    const auto measurements = datasets::simulateMeasurements(robot, datasets::protocolPoses(), noise, 1);
    std::mt19937_64 rng(2);
    std::vector<std::vector<datasets::H4Joints>> lines;
    for (const auto& line : datasets::straightLineMotions())
      lines.push_back(datasets::recordJoints(robot, line, 1e-4, rng));
    datasets::writeSimulatedCampaign(dir.path(), measurements, noise, lines);
  }
  std::string run(const std::string& extra, const std::string& poses = "poses.csv",
                  const std::string& joints = "joints.csv", int* code = nullptr) const {
    const fs::path d = dir.path();
    const std::string command = test::mireBinary().string() + " identify --poses " + (d / poses).string() +
                                " --joints " + (d / joints).string() + " -o " + (d / "out.yaml").string() + " " +
                                extra + " > " + (d / "stdout.txt").string() + " 2> " + (d / "stderr.txt").string();
    const int status = test::runCommand(command);
    if (code) *code = status;
    return test::readText(d / "stderr.txt");
  }
};

TEST(IdentifyCli, HappyPathWritesIdentifiedParametersAndReport) {
  const CliCampaign c;
  int code = -1;
  const std::string err = c.run("--lines " + (c.dir.path() / "lines.csv").string() +
                                    " --mc 15 --mc-repeats 4 --report " + (c.dir.path() / "report").string(),
                                "poses.csv", "joints.csv", &code);
  ASSERT_EQ(code, 0) << err;
  const std::string out = test::readText(c.dir.path() / "stdout.txt");
  EXPECT_NE(out.find("joint residual RMS"), std::string::npos) << out;
  EXPECT_NE(out.find("straightness V3"), std::string::npos) << out;
  EXPECT_NE(out.find("15 poses"), std::string::npos) << out;
  const auto file = mechanism::readParameterFile(c.dir.path() / "out.yaml");
  mechanism::ParameterSet geometric = mechanism::h4Model12Parameters({});
  std::vector<std::string> external;
  for (const auto& n : mechanism::ExternalParameterization(mechanism::ExternalForm::AxisAligned).parameters().names())
    external.push_back(n);
  mechanism::applyParameterFile(file, geometric, external);
  // The identified geometry agrees with the truth within 4 of its reported σ (81 poses at
  // 0.2 mm / 0.03°: σ ≈ 0.1–1 mm, 0.07°).
  const auto truth = mechanism::h4Model12Parameters(c.truth);
  for (const std::string name :
       {"R", "L", "l", "h", "alpha1", "alpha2", "alpha3", "alpha4", "q01", "q02", "q03", "q04"}) {
    ASSERT_NE(file.find("sigma_" + name), nullptr) << name;
    const double sigma = file.number(*file.find("sigma_" + name));
    EXPECT_GT(sigma, 0.0) << name;
    EXPECT_LT(sigma, name.size() == 1 ? 2e-3 : 0.2 * datasets::kH4Degree) << name;
    EXPECT_NEAR(geometric.value(name), truth.value(name), 4.0 * sigma) << name;
  }
  EXPECT_NE(file.find("x_BC"), nullptr);
  EXPECT_EQ(file.find("variant")->text, "D");
  for (const char* name : {"report.md", "report.html", "residuals.svg", "singular_values.svg", "monte_carlo_spread.svg"})
    EXPECT_TRUE(fs::exists(c.dir.path() / "report" / name)) << name;
}

TEST(IdentifyCli, PoseWithoutJoints) {
  const CliCampaign c;
  std::string joints = test::readText(c.dir.path() / "joints.csv");
  joints.erase(joints.find("\n5,") + 1, joints.find('\n', joints.find("\n5,") + 1) - joints.find("\n5,"));
  std::ofstream(c.dir.path() / "joints_missing.csv") << joints;
  int code = 0;
  const std::string err = c.run("", "poses.csv", "joints_missing.csv", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("poses.csv:6: pose '5' has no joints"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.dir.path() / "out.yaml"));
}

TEST(IdentifyCli, DuplicateId) {
  const CliCampaign c;
  std::string joints = test::readText(c.dir.path() / "joints.csv");
  const auto start = joints.find("\n7,") + 1;
  joints += joints.substr(start, joints.find('\n', start) - start + 1);
  std::ofstream(c.dir.path() / "joints_dup.csv") << joints;
  int code = 0;
  const std::string err = c.run("", "poses.csv", "joints_dup.csv", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("joints_dup.csv:83: duplicate pose_id '7'"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.dir.path() / "out.yaml"));
}

TEST(IdentifyCli, NonFiniteValue) {
  const CliCampaign c;
  std::string poses = test::readText(c.dir.path() / "poses.csv");
  const auto row = poses.find("\n3,10,10,") + 9;
  poses.replace(row, poses.find(',', row) - row, "nan");
  std::ofstream(c.dir.path() / "poses_nan.csv") << poses;
  int code = 0;
  const std::string err = c.run("", "poses_nan.csv", "joints.csv", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("poses_nan.csv:4: column 'tx_m'"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.dir.path() / "out.yaml"));
}

TEST(IdentifyCli, UnknownParameterName) {
  const CliCampaign c;
  std::ofstream(c.dir.path() / "nominal.yaml") << "R: 0.22\nL: 0.30\nforearm: 0.7\n";
  int code = 0;
  std::string err = c.run("--nominal " + (c.dir.path() / "nominal.yaml").string(), "poses.csv", "joints.csv", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("nominal.yaml:3: unknown parameter name 'forearm'"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.dir.path() / "out.yaml"));
  err = c.run("--fix Rx", "poses.csv", "joints.csv", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("Rx"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.dir.path() / "out.yaml"));
}

}  // namespace
}  // namespace mire::app
