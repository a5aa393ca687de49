// `mire measure` on an imperfect campaign (doc/measurement.md, "Imperfect campaigns"): a pose folder
// mixing two views fails naming the moved images, or with --split-moving keep-largest keeps the
// majority and lists the rest; copied frames are counted once; the flags column and the
// terminal say why.
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include "chessboard_views.hpp"
#include "test_support.hpp"

#include <opencv2/imgcodecs.hpp>

namespace {

namespace fs = std::filesystem;

void writeImage(const fs::path& path, const cv::Mat& image) {
  fs::create_directories(path.parent_path());
  cv::imwrite(path.string(), image);
}

// Five static poses of 3 images, "moving" (img0-2 one view, img3-4 the view 1 mm away) and
// "copies" (4 copies of one frame).
struct Campaign {
  explicit Campaign(const fs::path& root) : root(root) {
    const auto camera = mire::datasets::referenceCamera();
    mire::support::writeFileAtomically(root / "camera.yaml", mire::calibration::cameraYamlString(camera));
    mire::support::writeFileAtomically(root / "target.yaml", mire::test::chessboard9x6().yamlString());
    const mire::datasets::Renderer renderer(camera, mire::test::chessboard9x6());
    const mire::datasets::NoiseOptions noise{1.5, 20.0};
    std::uint64_t seed = 1;
    for (int p = 0; p < 5; ++p) {
      const auto rendering =
          renderer.render(mire::test::tiltedBoardPose(0.02 * p - 0.04, 0.01 * p, 0.6 + 0.02 * p, 8.0 * p - 16));
      for (int i = 0; i < 3; ++i)
        writeImage(root / "poses" / ("static" + std::to_string(p)) / ("img" + std::to_string(i) + ".png"),
                   mire::datasets::addNoise(rendering.radiance, noise, seed++));
    }
    const Eigen::Isometry3d still = mire::test::tiltedBoardPose(0.01, 0.0, 0.65, 3);
    Eigen::Isometry3d moved = still;
    moved.translation().x() += 1e-3;
    const auto a = renderer.render(still), b = renderer.render(moved);
    for (int i = 0; i < 5; ++i)
      writeImage(root / "poses" / "moving" / ("img" + std::to_string(i) + ".png"),
                 mire::datasets::addNoise(i < 3 ? a.radiance : b.radiance, noise, seed++));
    const cv::Mat frame = mire::datasets::addNoise(a.radiance, noise, seed++);
    for (int i = 0; i < 4; ++i) writeImage(root / "poses" / "copies" / ("img" + std::to_string(i) + ".png"), frame);
  }
  std::string command(const std::string& extra) const {
    return mire::test::mireBinary().string() + " measure --camera " + (root / "camera.yaml").string() + " --target " +
           (root / "target.yaml").string() + " --poses " + (root / "poses").string() + " -o " +
           (root / "out" / "poses.csv").string() + extra;
  }
  fs::path root;
};

int row(const mire::support::CsvTable& table, const std::string& id) {
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    if (table.rows[r][table.column("pose_id")] == id) return static_cast<int>(r);
  return -1;
}

}  // namespace

TEST(MeasureIntegrityCli, MovingPoseFailsOrSplitsAndCopiesCountOnce) {
  mire::test::TempDir dir;
  const Campaign campaign(dir.path());
  fs::create_directories(dir.path() / "out");
  int code = -1;
  std::string out = mire::test::captureCommand(campaign.command(""), &code);
  EXPECT_EQ(code, 3) << out;
  EXPECT_NE(out.find("pose moving: FAILED: the images do not show one static pose"), std::string::npos) << out;
  EXPECT_NE(out.find("img3.png, img4.png disagree with img0.png, img1.png, img2.png"), std::string::npos) << out;
  EXPECT_NE(out.find("pose copies: note: 3 frame(s) identical to img0.png"), std::string::npos) << out;
  EXPECT_EQ(out.find("outlier"), std::string::npos) << out;
  auto table = mire::support::readCsv(dir.path() / "out" / "poses.csv");
  EXPECT_EQ(table.rows.size(), 6u);
  EXPECT_EQ(row(table, "moving"), -1);
  const int copies = row(table, "copies");
  ASSERT_GE(copies, 0);
  EXPECT_EQ(table.number(static_cast<std::size_t>(copies), table.column("images_used")), 1);
  EXPECT_EQ(table.number(static_cast<std::size_t>(copies), table.column("reduced_chi2")), 1);
  const std::string flags = table.rows[static_cast<std::size_t>(copies)][table.column("flags")];
  EXPECT_EQ(flags.rfind("duplicates:3;sigma_from_residuals", 0), 0u) << flags;
  // One image among poses of three: flagged by the campaign screening, with the reason.
  EXPECT_NE(flags.find("few_images:3x"), std::string::npos) << flags;
  EXPECT_NE(out.find("pose copies: FLAGGED: images used 1"), std::string::npos) << out;
  for (int p = 0; p < 5; ++p)
    EXPECT_EQ(table.rows[static_cast<std::size_t>(row(table, "static" + std::to_string(p)))][table.column("flags")], "");

  out = mire::test::captureCommand(campaign.command(" --split-moving keep-largest"), &code);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("pose moving: note: the images do not show one static pose"), std::string::npos) << out;
  EXPECT_NE(out.find("left out: img3.png, img4.png"), std::string::npos) << out;
  table = mire::support::readCsv(dir.path() / "out" / "poses.csv");
  const int moving = row(table, "moving");
  ASSERT_GE(moving, 0);
  EXPECT_EQ(table.number(static_cast<std::size_t>(moving), table.column("images_used")), 3);
  EXPECT_EQ(table.number(static_cast<std::size_t>(moving), table.column("images_total")), 5);
  EXPECT_EQ(table.rows[static_cast<std::size_t>(moving)][table.column("flags")].rfind("moved_left_out:2", 0), 0u);
}
