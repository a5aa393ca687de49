// The bad-input matrix (doc/robustness.md): table-driven, one gtest per case (BadInput/Matrix.Run/<name>).
// The cases themselves are in bad_input_cases.cpp; this file makes the fixture and runs them.
#include "bad_input_fixture.hpp"

#include "mire/datasets/h4_true_robot.hpp"

#include <unistd.h>

#include <random>

namespace mire::app::badinput {
namespace {

int runMire(const std::string& arguments, std::string* output) {
  int code = -1;
  // `timeout` turns a hang into exit 124 (the cases assert their own code).
  *output = test::captureCommand("timeout 60 " + test::mireBinary().string() + " " + arguments + " </dev/null", &code);
  return code;
}

std::string smallCamera() {
  return "%YAML:1.0\n---\nimage_width: 480\nimage_height: 360\nmodel: \"opencv\"\n"
         "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
         "   data: [ 420., 0., 239.5, 0., 420., 179.5, 0., 0., 1. ]\n"
         "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
         "   data: [ -0.1, 0.02, 0., 0., 0. ]\n";
}

std::string smallTarget() { return "%YAML:1.0\n---\ntype: chessboard\ncols: 6\nrows: 5\nsquare_size_m: 0.02\n"; }

std::string specText(const std::string& poses_block, const std::string& calibration_block) {
  return "%YAML:1.0\n---\ncamera: \"camera.yaml\"\ntarget: \"target.yaml\"\nseed: 3\n"
         "render:\n  supersampling: 2\n  cluttered_background: 0\nnoise:\n  gaussian_sigma: 2.0\n" +
         poses_block + calibration_block;
}

}  // namespace

std::string posesBlock(const std::string& list) { return "poses:\n  images_per_pose: 2\n  list:\n" + list; }

std::string validPoseList() {
  return "    - { id: \"p1\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n"
         "    - { id: \"p2\", t: [ 0.02, -0.01, 0.5 ], r: [ 0.3, 0.1, 0.0 ] }\n";
}

const Fixture& fixture() {
  static const Fixture made = [] {
    Fixture f;
    f.root = fs::temp_directory_path() / ("mire-badinput-" + std::to_string(::getpid()));
    fs::remove_all(f.root);
    fs::create_directories(f.root / "specs");
    spit(f.root / "specs/camera.yaml", smallCamera());
    spit(f.root / "specs/target.yaml", smallTarget());
    f.spec = f.root / "specs/poses.yaml";
    spit(f.spec, specText(posesBlock(validPoseList()), ""));
    f.cal_spec = f.root / "specs/calibration.yaml";
    spit(f.cal_spec, specText("", "calibration:\n  views: 4\n  distance_m: [ 0.4, 0.6 ]\n  max_tilt_deg: 30\n"));
    f.sim = f.root / "sim";
    f.cal = f.root / "cal";
    f.campaign = f.root / "campaign";
    std::string output;
    if (runMire("simulate poses --spec " + f.spec.string() + " -o " + f.sim.string(), &output) != 0)
      f.error = "simulate poses failed: " + output;
    else if (runMire("simulate calibration --spec " + f.cal_spec.string() + " -o " + f.cal.string(), &output) != 0)
      f.error = "simulate calibration failed: " + output;
    else if (runMire("measure --camera " + (f.sim / "camera.yaml").string() + " --target " +
                         (f.sim / "target.yaml").string() + " --poses " + (f.sim / "poses").string() + " -o " +
                         (f.root / "check/poses.csv").string(),
                     &output) != 0)
      f.error = "the valid measure failed: " + output;
    fs::remove_all(f.root / "check");
    // The simulated H4 (no unmodelled defects), as identify reads it.
    const auto sizes = datasets::H4ErrorSizes::withoutUnmodelledDefects();
    const datasets::H4TrueKinematics robot(datasets::makeTrueGeometry({}, sizes, 3));
    datasets::H4MeasurementNoise noise;
    const auto measurements = datasets::simulateMeasurements(robot, datasets::protocolPoses(), noise, 1);
    std::mt19937_64 rng(2);
    std::vector<std::vector<datasets::H4Joints>> lines;
    for (const auto& line : datasets::straightLineMotions())
      lines.push_back(datasets::recordJoints(robot, line, 1e-4, rng));
    datasets::writeSimulatedCampaign(f.campaign, measurements, noise, lines);
    return f;
  }();
  return made;
}

class Matrix : public ::testing::TestWithParam<Case> {
 public:
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(fixture().root, ignored);
  }
};

TEST_P(Matrix, Run) {
  const Fixture& f = fixture();
  ASSERT_TRUE(f.error.empty()) << f.error;
  const Case& c = GetParam();
  const CaseEnv env{f, f.root / "cases" / c.name};
  fs::remove_all(env.dir);
  fs::create_directories(env.dir);
  const std::string arguments = c.arguments(env);
  const auto inputs_before = snapshot(f.root);  // the fixture and this case's own inputs

  std::string output;
  const int code = runMire(arguments, &output);

  EXPECT_EQ(code, c.exit_code) << "mire " << arguments << "\n" << output;
  for (std::string expected : c.message) {
    const auto at = expected.find("{dir}");
    if (at != std::string::npos) expected.replace(at, 5, env.dir.string());
    EXPECT_NE(output.find(expected), std::string::npos) << "expected '" << expected << "' in:\n" << output;
  }
  EXPECT_EQ(output.find("terminate called"), std::string::npos) << output;
  // Nothing written (no output, no temporary), no input touched: the whole tree is unchanged.
  const auto inputs_after = snapshot(f.root);
  for (const auto& [path, bytes] : inputs_after) {
    const auto before = inputs_before.find(path);
    EXPECT_TRUE(before != inputs_before.end()) << "written: " << path;
    if (before != inputs_before.end()) {
      EXPECT_TRUE(before->second == bytes) << "modified: " << path;
    }
  }
  for (const auto& [path, bytes] : inputs_before) EXPECT_TRUE(inputs_after.count(path)) << "removed: " << path;
  fs::remove_all(env.dir);
}

INSTANTIATE_TEST_SUITE_P(BadInput, Matrix, ::testing::ValuesIn(allCases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace mire::app::badinput
