// `mire measure` from image folders: bad input is reported per pose, the other poses are
// still measured and written, exit code 3 (doc/conventions.md "Exit codes").
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include "chessboard_views.hpp"
#include "test_support.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>

namespace {

namespace fs = std::filesystem;

// Writes camera.yaml, target.yaml and poses/<id>/ folders: two good poses, then bad ones.
struct Campaign {
  explicit Campaign(const fs::path& root) : root(root) {
    const auto camera = mire::datasets::referenceCamera();
    mire::support::writeFileAtomically(root / "camera.yaml", mire::calibration::cameraYamlString(camera));
    mire::support::writeFileAtomically(root / "target.yaml", mire::test::chessboard9x6().yamlString());
    const mire::datasets::Renderer renderer(camera, mire::test::chessboard9x6());
    int seed = 1;
    for (const auto& [id, pose] : {std::pair{std::string("good1"), mire::test::tiltedBoardPose(0.0, 0.0, 0.6, 5)},
                                   std::pair{std::string("good2"), mire::test::tiltedBoardPose(0.05, -0.03, 0.7, -10)}}) {
      const auto rendering = renderer.render(pose);
      fs::create_directories(root / "poses" / id);
      for (int i = 0; i < 3; ++i)
        cv::imwrite((root / "poses" / id / ("img" + std::to_string(i) + ".png")).string(),
                    mire::datasets::addNoise(rendering.radiance, {1.5, 0.0}, static_cast<std::uint64_t>(seed++)));
      if (id == "good1") good_image = mire::datasets::addNoise(rendering.radiance, {1.5, 0.0}, 99);
    }
  }
  fs::path root;
  cv::Mat good_image;
};

}  // namespace

TEST(MeasureCli, BadPoseFoldersAreReportedAndTheOthersWritten) {
  mire::test::TempDir dir;
  Campaign campaign(dir.path());
  const fs::path poses = dir.path() / "poses";
  // Target never found: uniform grey images.
  fs::create_directories(poses / "blank");
  for (int i = 0; i < 2; ++i)
    cv::imwrite((poses / "blank" / ("img" + std::to_string(i) + ".png")).string(),
                cv::Mat(768, 1024, CV_8UC1, cv::Scalar(128)));
  // Mixed image sizes.
  fs::create_directories(poses / "mixed");
  cv::imwrite((poses / "mixed" / "a.png").string(), campaign.good_image);
  cv::Mat small;
  cv::resize(campaign.good_image, small, cv::Size(640, 480));
  cv::imwrite((poses / "mixed" / "b.png").string(), small);
  // Unreadable image.
  fs::create_directories(poses / "broken");
  cv::imwrite((poses / "broken" / "a.png").string(), campaign.good_image);
  std::ofstream(poses / "broken" / "b.png") << "this is not a png";
  // Wrong size for the camera (all images agree with each other).
  fs::create_directories(poses / "wrongsize");
  cv::imwrite((poses / "wrongsize" / "a.png").string(), small);

  int code = -1;
  const fs::path output = dir.path() / "out" / "poses.csv";
  fs::create_directories(output.parent_path());
  const std::string out = mire::test::captureCommand(
      mire::test::mireBinary().string() + " measure --camera " + (dir.path() / "camera.yaml").string() + " --target " +
          (dir.path() / "target.yaml").string() + " --poses " + poses.string() + " -o " + output.string(),
      &code);
  EXPECT_EQ(code, 3) << out;
  // A blank image is named (not counted as a view without the target).
  EXPECT_NE(out.find("pose blank: FAILED: image "), std::string::npos) << out;
  EXPECT_NE(out.find("img0.png' is blank"), std::string::npos) << out;
  EXPECT_NE(out.find("pose mixed: FAILED: mixed image sizes"), std::string::npos) << out;
  EXPECT_NE(out.find("b.png"), std::string::npos) << out;
  EXPECT_NE(out.find("pose broken: FAILED: "), std::string::npos) << out;
  EXPECT_NE(out.find("unreadable image"), std::string::npos) << out;
  EXPECT_NE(out.find("pose wrongsize: FAILED: "), std::string::npos) << out;
  EXPECT_NE(out.find("calibrated at 1024x768"), std::string::npos) << out;
  ASSERT_TRUE(fs::exists(output)) << out;
  ASSERT_TRUE(fs::exists(dir.path() / "out" / "poses_covariance.csv"));
  const auto records = mire::mechanism::readPosesCsv(output, dir.path() / "out" / "poses_covariance.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].observation.id, "good1");
  EXPECT_EQ(records[1].observation.id, "good2");
  const auto table = mire::support::readCsv(output);
  EXPECT_EQ(table.number(0, table.column("images_used")), 3);
  EXPECT_EQ(table.number(0, table.column("images_total")), 3);
  // Against the truth (rendered): within a millimetre / a tenth of a degree.
  const Eigen::Isometry3d truth = mire::test::tiltedBoardPose(0.0, 0.0, 0.6, 5);
  EXPECT_LT((records[0].observation.cTm.head<3>() - truth.translation()).norm(), 1e-3);
  EXPECT_LT((records[0].observation.cTm.tail<3>() - mire::metrology::rotationVector(truth.linear())).norm(),
            0.1 * M_PI / 180);
}

TEST(MeasureCli, NoPoseMeasuredExitsOneAndWritesNothing) {
  mire::test::TempDir dir;
  const auto camera = mire::datasets::referenceCamera();
  mire::support::writeFileAtomically(dir.path() / "camera.yaml", mire::calibration::cameraYamlString(camera));
  mire::support::writeFileAtomically(dir.path() / "target.yaml", mire::test::chessboard9x6().yamlString());
  fs::create_directories(dir.path() / "poses" / "blank");
  cv::imwrite((dir.path() / "poses" / "blank" / "a.png").string(), cv::Mat(768, 1024, CV_8UC1, cv::Scalar(128)));
  int code = -1;
  const std::string out = mire::test::captureCommand(
      mire::test::mireBinary().string() + " measure --camera " + (dir.path() / "camera.yaml").string() + " --target " +
          (dir.path() / "target.yaml").string() + " --poses " + (dir.path() / "poses").string() + " -o " +
          (dir.path() / "poses.csv").string(),
      &code);
  EXPECT_EQ(code, 1) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "poses.csv"));
  EXPECT_NE(out.find("pose blank: FAILED"), std::string::npos) << out;
}

// A camera file that does not fit the images (another lens and pixel aspect): a warning with
// the residual RMS against the calibration's, not a note (doc/measurement.md, "Warnings with
// numbers"); the poses are still written.
TEST(MeasureCli, CameraThatDoesNotFitTheImagesIsAWarningWithTheRms) {
  mire::test::TempDir dir;
  Campaign campaign(dir.path());
  auto wrong = mire::datasets::referenceCamera();
  wrong.params[1] *= 1.03;  // fy: another pixel aspect ratio
  wrong.params[4] = 0.3;    // k1 of another lens (the images' is -0.30)
  wrong.rms_px = 0.15;
  mire::support::writeFileAtomically(dir.path() / "wrong.yaml", mire::calibration::cameraYamlString(wrong));
  int code = -1;
  const std::string out = mire::test::captureCommand(
      mire::test::mireBinary().string() + " measure --camera " + (dir.path() / "wrong.yaml").string() + " --target " +
          (dir.path() / "target.yaml").string() + " --poses " + (dir.path() / "poses").string() + " -o " +
          (dir.path() / "poses.csv").string() + " --threads 1 2>&1",
      &code);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("pose good1: warning: the camera does not fit the images: reprojection RMS"), std::string::npos)
      << out;
  EXPECT_NE(out.find("px against 0.150 px expected"), std::string::npos) << out;
  std::printf("%s", out.substr(0, out.find("measured ")).c_str());
  // The right camera file: no such warning.
  const std::string right = mire::test::captureCommand(
      mire::test::mireBinary().string() + " measure --camera " + (dir.path() / "camera.yaml").string() + " --target " +
          (dir.path() / "target.yaml").string() + " --poses " + (dir.path() / "poses").string() + " -o " +
          (dir.path() / "poses_right.csv").string() + " --threads 1 2>&1",
      &code);
  EXPECT_EQ(code, 0) << right;
  EXPECT_EQ(right.find("does not fit"), std::string::npos) << right;
}
