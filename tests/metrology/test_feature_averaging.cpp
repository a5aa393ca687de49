// Multi-image averaging (outlier images, scatter) and the poses.csv files.
#include "mire/datasets/feature_campaign.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/side_files.hpp"

#include "chessboard_views.hpp"
#include "test_support.hpp"

#include <fstream>
#include <random>

namespace {

std::vector<mire::metrology::Detection> noisyImages(double sigma, int images, std::uint64_t seed,
                                                    Eigen::Isometry3d* truth = nullptr) {
  const auto camera = mire::datasets::referenceCamera();
  std::mt19937_64 rng(seed);
  mire::datasets::CampaignGeometry geometry;
  geometry.target_centre_m = Eigen::Vector3d(0.12, 0.075, 0);
  const Eigen::Isometry3d pose = mire::datasets::drawCampaignPose(geometry, rng);
  if (truth != nullptr) *truth = pose;
  const auto exact = mire::datasets::exactDetection(camera, mire::test::chessboard9x6().points(), pose);
  return mire::datasets::noisyDetections(exact, std::vector<double>(mire::test::chessboard9x6().points().size(), sigma),
                                         images, rng);
}

}  // namespace

TEST(FeatureAveraging, MeanAndCovarianceOfTheMean) {
  const auto images = noisyImages(0.2, 10, 3);
  const auto averaged = mire::metrology::averageDetections(images);
  EXPECT_EQ(averaged.images_total, 10);
  EXPECT_EQ(averaged.images_used, 10);
  EXPECT_EQ(averaged.size(), mire::test::chessboard9x6().points().size());
  // Pooled single-observation variance ≈ 0.04 px² (σ = 0.2 px), dof = 54 × 9.
  EXPECT_NEAR(averaged.pooled_covariance(0, 0), 0.04, 0.008);
  EXPECT_NEAR(averaged.pooled_covariance(1, 1), 0.04, 0.008);
  EXPECT_EQ(averaged.pooled_dof, 54 * 9);
  // Equal noise: the empirical Bayes prior should lean on the pool.
  EXPECT_GT(averaged.prior_dof, 30.0);
  for (const auto& c : averaged.covariance) EXPECT_NEAR(c(0, 0), 0.004, 0.0015);
}

TEST(FeatureAveraging, RejectsADisplacedImageAndAnOutlierObservation) {
  auto images = noisyImages(0.1, 10, 4);
  for (auto& p : images[6].pixels) p += Eigen::Vector2d(0.15, -0.1);  // the camera shook
  images[2].pixels[5] += Eigen::Vector2d(3.0, 0.0);                   // one wrong corner
  const auto averaged = mire::metrology::averageDetections(images);
  EXPECT_EQ(averaged.images_used, 9);
  ASSERT_EQ(averaged.rejected_images.size(), 1u);
  EXPECT_EQ(averaged.rejected_images[0], 6);
  EXPECT_GE(averaged.rejected_observations, 1);
  // The mean of feature 5 is not pulled by the outlier.
  const auto reference = noisyImages(0.0, 1, 4);
  EXPECT_LT((averaged.pixels[5] - reference[0].pixels[5]).norm(), 0.1);
}

TEST(FeatureAveraging, ImagesWhereTheTargetWasNotFoundCountInTheTotalOnly) {
  auto images = noisyImages(0.1, 5, 5);
  images[1].found = false;
  const auto averaged = mire::metrology::averageDetections(images);
  EXPECT_EQ(averaged.images_total, 5);
  EXPECT_EQ(averaged.images_used, 4);
}

TEST(FeatureAveraging, SingleImageFallsBackOnTheFitResiduals) {
  Eigen::Isometry3d truth;
  const auto images = noisyImages(0.2, 1, 6, &truth);
  const auto averaged = mire::metrology::averageDetections(images);
  EXPECT_FALSE(averaged.hasScatter());
  const auto estimate =
      mire::metrology::estimatePose(mire::datasets::referenceCamera(), mire::test::chessboard9x6().points(), averaged);
  ASSERT_TRUE(estimate.valid) << estimate.reason;
  EXPECT_TRUE(estimate.scatter_from_residuals);
  EXPECT_NEAR(estimate.rms_px, 0.2 * std::sqrt(2.0), 0.08);
  const auto sigma = mire::metrology::PoseEstimate::sigmas(estimate.covariance);
  EXPECT_LT(std::abs(estimate.translation.z() - truth.translation().z()), 4 * sigma[2]);
  EXPECT_GT(sigma[2], 0.0);
}

TEST(PosesCsv, HeaderIsExactlyTheBriefsAndRoundTrips) {
  Eigen::Isometry3d truth;
  const auto images = noisyImages(0.1, 10, 8, &truth);
  auto camera = mire::datasets::referenceCamera();
  camera.covariance = Eigen::MatrixXd::Identity(9, 9) * 1e-8;
  camera.covariance.topLeftCorner(4, 4) = Eigen::Matrix4d::Identity() * 0.25;
  const auto estimate = mire::metrology::estimatePose(camera, mire::test::chessboard9x6().points(),
                                                      mire::metrology::averageDetections(images));
  ASSERT_TRUE(estimate.valid);
  EXPECT_GT(estimate.covariance_intrinsics(0, 0), 0.0);
  const std::vector<mire::metrology::MeasuredPose> poses = {{"p01", 10, 10, estimate}, {"p02", 9, 10, estimate}};
  mire::test::TempDir dir;
  const auto path = dir.path() / "poses.csv";
  mire::metrology::writePosesCsv(path, poses);
  mire::metrology::writePosesCovarianceCsv(mire::support::covarianceSidePath(path), poses);
  EXPECT_EQ(mire::support::covarianceSidePath(path).filename(), "poses_covariance.csv");
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,"
                         "sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px",
                         0),
            0u)
      << header;
  // Read back by the reader `mire identify` uses.
  const auto records = mire::mechanism::readPosesCsv(path, mire::support::covarianceSidePath(path));
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[1].observation.id, "p02");
  const auto table = mire::support::readCsv(path);
  EXPECT_EQ(table.number(1, table.column("images_used")), 9);
  const auto& first = records[0].observation;
  EXPECT_LT((first.cTm.head<3>() - estimate.translation).norm(), 1e-15);
  EXPECT_LT((first.cTm.tail<3>() - estimate.rotation_vector).norm(), 1e-15);
  ASSERT_TRUE(first.covariance.has_value());
  EXPECT_LT((*first.covariance - estimate.covariance).norm(), 1e-12 * estimate.covariance.norm());
  // Without the side file: the diagonal from the σ columns (6 significant digits).
  const auto diagonal = mire::mechanism::readPosesCsv(path);
  ASSERT_TRUE(diagonal[0].observation.covariance.has_value());
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR((*diagonal[0].observation.covariance)(c, c), estimate.covariance(c, c), 1e-5 * estimate.covariance(c, c));
}
