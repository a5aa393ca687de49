// The renderer: exact inverse mapping, ground truth, and what a detector finds in
// its images compared with that truth.
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/metrology/detection.hpp"

#include "test_support.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <iostream>

namespace {

using mire::calibration::Camera;
using mire::datasets::Renderer;
using mire::datasets::RenderOptions;
using mire::datasets::ViewPlacement;
using mire::metrology::Target;
using mire::metrology::TargetSpec;
using mire::metrology::TargetType;

constexpr double kDegree = M_PI / 180.0;

// datasets/specs/reference_camera.yaml (paper §5).
Camera referenceCamera() {
  return mire::calibration::cameraFromOpenCV(1024, 768, 817.2043010752688, 817.2043010752688, 511.5, 383.5,
                                             {-0.30, 0.10, 4.0e-4, -3.0e-4, -0.015});
}

Target chessboard() {
  TargetSpec spec;
  spec.type = TargetType::Chessboard;
  spec.cols = 10;
  spec.rows = 7;
  spec.square_size_m = 0.03;
  return Target(spec);
}

Target circleGrid() {
  TargetSpec spec;
  spec.type = TargetType::Circles;
  spec.cols = 7;
  spec.rows = 5;
  spec.spacing_m = 0.04;
  spec.diameter_m = 0.02;
  return Target(spec);
}

Eigen::Isometry3d place(const Camera& camera, const Target& target, double u, double v, double distance,
                        double tilt_deg, double axis_deg = 30.0, double roll_deg = 0.0) {
  ViewPlacement placement;
  placement.centre_pixel = Eigen::Vector2d(u, v);
  placement.distance_m = distance;
  placement.tilt_rad = tilt_deg * kDegree;
  placement.tilt_axis_rad = axis_deg * kDegree;
  placement.roll_rad = roll_deg * kDegree;
  return mire::datasets::placeTarget(camera, target, placement);
}

// RMS distance between detected features and the ground truth (every feature found).
double rmsAgainstTruth(const mire::metrology::Detection& detection, const mire::datasets::FeatureTruth& truth,
                       Eigen::Vector2d* mean_offset = nullptr) {
  double sum = 0.0;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < detection.size(); ++k) {
    const Eigen::Vector2d error = detection.pixels[k] - truth.pixels[static_cast<std::size_t>(detection.ids[k])];
    sum += error.squaredNorm();
    offset += error;
  }
  if (mean_offset) *mean_offset = offset / static_cast<double>(detection.size());
  return std::sqrt(sum / static_cast<double>(detection.size()));
}

TEST(RayGrid, CornersAreExactAndInterpolationErrorIsBelow1e4Px) {
  const Camera camera = referenceCamera();
  const mire::datasets::RayGrid grid(camera);
  for (const auto& [i, j] : {std::pair{0, 0}, {1024, 768}, {512, 384}, {1024, 0}, {17, 701}}) {
    Eigen::Vector2d exact;
    ASSERT_TRUE(camera.unproject(Eigen::Vector2d(i - 0.5, j - 0.5), &exact));
    EXPECT_LT((grid.corner(i, j) - exact).norm(), 1e-13) << i << "," << j;
  }
  const double bilinear = grid.maxInterpolationErrorPx(camera, 7, 4, false);
  const double refined = grid.maxInterpolationErrorPx(camera, 7, 4, true);
  std::cout << "[ render ] ray inside a pixel, max error over 4x4 sub-samples (every 7th pixel + the image "
               "corners): bilinear "
            << bilinear << " px, bilinear + 2 Newton steps with the pixel's Jacobian (what the renderer uses) "
            << refined << " px\n";
  EXPECT_LT(bilinear, 1e-3);
  EXPECT_LT(refined, 1e-4);
  EXPECT_LT(refined, 1e-9);
}

TEST(Render, IsDeterministicAndNoiseDependsOnlyOnItsSeed) {
  const Camera camera = referenceCamera();
  RenderOptions options;
  options.cluttered_background = true;
  options.seed = 5;
  options.blur_sigma_px = 0.7;
  options.vignetting = mire::datasets::Vignetting::Cos4;
  const Renderer renderer(camera, chessboard(), options);
  const Eigen::Isometry3d pose = place(camera, chessboard(), 500, 380, 0.5, 35.0);
  const auto first = renderer.render(pose), second = renderer.render(pose);
  EXPECT_EQ(cv::norm(first.radiance, second.radiance, cv::NORM_INF), 0.0);
  const Renderer other(camera, chessboard(), options);
  EXPECT_EQ(cv::norm(other.render(pose).image, first.image, cv::NORM_INF), 0.0);

  mire::datasets::NoiseOptions noise;
  noise.gaussian_sigma = 2.0;
  noise.shot_noise_gain = 20.0;
  const cv::Mat a = mire::datasets::addNoise(first.radiance, noise, 11);
  const cv::Mat b = mire::datasets::addNoise(first.radiance, noise, 11);
  const cv::Mat c = mire::datasets::addNoise(first.radiance, noise, 12);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
}

TEST(Render, NoiseHasTheRequestedStandardDeviation) {
  const cv::Mat flat(400, 400, CV_32F, cv::Scalar(100.0));
  mire::datasets::NoiseOptions noise;
  noise.gaussian_sigma = 3.0;
  noise.shot_noise_gain = 25.0;  // variance 100 / 25 = 4 grey levels^2
  cv::Mat noisy;
  mire::datasets::addNoise(flat, noise, 3).convertTo(noisy, CV_64F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(noisy, mean, stddev);
  const double expected = std::sqrt(9.0 + 4.0 + 1.0 / 12.0);  // + quantisation
  EXPECT_NEAR(mean[0], 100.0, 0.05);
  EXPECT_NEAR(stddev[0], expected, 0.03 * expected);
}

TEST(Render, AdaptiveSupersamplingEqualsFullSupersampling) {
  const Camera camera = referenceCamera();
  RenderOptions adaptive, full;
  adaptive.supersampling = full.supersampling = 2;  // same test for any n, 4x faster
  full.adaptive = false;
  for (const Target& target : {chessboard(), circleGrid()}) {
    const Eigen::Isometry3d pose = place(camera, target, 300, 250, 0.45, 50.0, 120.0, 10.0);
    const auto a = Renderer(camera, target, adaptive).render(pose);
    const auto b = Renderer(camera, target, full).render(pose);
    EXPECT_LT(cv::norm(a.radiance, b.radiance, cv::NORM_INF), 1e-3);
    EXPECT_LT(a.supersampled_pixels, camera.width * camera.height / 4);
  }
}

TEST(Render, GroundTruthIsTheCameraProjection) {
  const Camera camera = referenceCamera();
  const Target target = chessboard();
  const Eigen::Isometry3d pose = place(camera, target, 700, 500, 0.5, 40.0);
  const auto truth = mire::datasets::projectFeatures(camera, target, pose);
  ASSERT_EQ(truth.pixels.size(), target.points().size());
  for (std::size_t k = 0; k < target.points().size(); ++k) {
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.project(pose * target.points()[k], &pixel));
    EXPECT_EQ((pixel - truth.pixels[k]).norm(), 0.0);
    EXPECT_TRUE(truth.visible[k]);
  }
  // The square just outside the origin (x < 0, y < 0) is dark, the next one light (doc/file-formats.md).
  const auto rendering = Renderer(camera, target).render(pose);
  const auto levelAt = [&](double x, double y) {
    Eigen::Vector2d pixel;
    camera.project(pose * Eigen::Vector3d(x, y, 0.0), &pixel);
    return rendering.image.at<std::uint8_t>(cvRound(pixel.y()), cvRound(pixel.x()));
  };
  EXPECT_LT(levelAt(-0.015, -0.015), 60);
  EXPECT_GT(levelAt(0.015, -0.015), 200);
  EXPECT_GT(levelAt(-0.045, -0.045), 200);  // white margin
}

TEST(Render, ChessboardCornersDetectedWithin005PxOfTruth) {
  const Camera camera = referenceCamera();
  const Target target = chessboard();
  RenderOptions sharp, defocused;
  defocused.blur_sigma_px = 1.0;
  const Renderer sharp_renderer(camera, target, sharp), renderer(camera, target, defocused);
  struct Case {
    const char* name;
    double u, v, distance, tilt_deg, axis_deg;
  };
  const Case cases[] = {{"centre, tilt 0", 511.5, 383.5, 0.5, 0.0, 0.0},
                        {"centre, tilt 20", 511.5, 383.5, 0.5, 20.0, 30.0},
                        {"centre, tilt 40", 511.5, 383.5, 0.5, 40.0, 100.0},
                        {"centre, tilt 60", 511.5, 383.5, 0.45, 60.0, 0.0},
                        {"centre, tilt 60 (y axis)", 511.5, 383.5, 0.45, 60.0, 90.0},
                        {"top-left corner, tilt 30", 260, 190, 0.6, 30.0, 45.0},
                        {"bottom-right corner, tilt 30", 770, 580, 0.6, 30.0, 135.0},
                        {"top-right corner, tilt 45", 760, 190, 0.6, 45.0, 60.0}};
  for (const Case& c : cases) {
    const Eigen::Isometry3d pose = place(camera, target, c.u, c.v, c.distance, c.tilt_deg, c.axis_deg);
    const auto rendering = renderer.render(pose);
    ASSERT_EQ(rendering.truth.visibleCount(), target.points().size()) << c.name;
    const auto detection = mire::metrology::detectTarget(target, rendering.image);
    ASSERT_TRUE(detection.found) << c.name << ": " << detection.reason;
    ASSERT_EQ(detection.size(), target.points().size()) << c.name;
    const double rms = rmsAgainstTruth(detection, rendering.truth);
    const auto sharp_rendering = sharp_renderer.render(pose);
    const auto sharp_detection = mire::metrology::detectTarget(target, sharp_rendering.image);
    ASSERT_EQ(sharp_detection.size(), target.points().size()) << c.name << " (sharp)";
    Eigen::Vector2d sharp_offset;
    const double sharp_rms = rmsAgainstTruth(sharp_detection, sharp_rendering.truth, &sharp_offset);
    std::cout << "[ render ] chessboard " << c.name << ": corner RMS vs truth " << rms << " px (blur 1.0 px), "
              << sharp_rms << " px (sharp, mean offset " << sharp_offset.transpose() << ")\n";
    EXPECT_LT(rms, 0.05) << c.name;
  }
}

// Centre of the ellipse that disc (centre, radius) of the target plane images to, for a
// camera WITHOUT distortion: the conic H^-T Q H^-1 in pixels, centre = -A^-1 b.
Eigen::Vector2d ellipseCentre(const Camera& camera, const Eigen::Isometry3d& pose, const Eigen::Vector3d& centre,
                              double radius) {
  Eigen::Matrix3d disc;
  disc << 1, 0, -centre.x(), 0, 1, -centre.y(), -centre.x(), -centre.y(),
      centre.head<2>().squaredNorm() - radius * radius;
  Eigen::Matrix3d homography, intrinsics;
  homography << pose.linear().col(0), pose.linear().col(1), pose.translation();
  intrinsics << camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1;
  const Eigen::Matrix3d to_plane = (intrinsics * homography).inverse();
  const Eigen::Matrix3d conic = to_plane.transpose() * disc * to_plane;
  return -conic.topLeftCorner<2, 2>().inverse() * conic.topRightCorner<2, 1>();
}

// Darkness-weighted centroid of the blob around `guess` (the imaged disc's area centroid).
Eigen::Vector2d darkCentroid(const cv::Mat& image, const Eigen::Vector2d& guess, double radius_px, double light) {
  double sum = 0.0;
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  const int r = static_cast<int>(std::ceil(radius_px));
  for (int v = cvRound(guess.y()) - r; v <= cvRound(guess.y()) + r; ++v)
    for (int u = cvRound(guess.x()) - r; u <= cvRound(guess.x()) + r; ++u) {
      if ((Eigen::Vector2d(u, v) - guess).norm() > radius_px) continue;
      const double weight = std::max(0.0, light - image.at<float>(v, u));
      sum += weight;
      moment += weight * Eigen::Vector2d(u, v);
    }
  return moment / sum;
}

TEST(Render, CircleCentresAndTheirPerspectiveBias) {
  // A disc's image is an ellipse whose centre is not the projected disc centre. Without
  // distortion that ellipse centre is known exactly (conic), which checks the renderer to a
  // few thousandths of a pixel; the gap to the projected centre is the perspective bias a
  // calibration with circles must model. Recorded here (doc/simulation.md).
  const Target target = circleGrid();
  const double radius = 0.5 * target.spec().diameter_m;
  Camera pinhole = referenceCamera();
  for (std::size_t k = 4; k < pinhole.params.size(); ++k) pinhole.params[k] = 0.0;
  const Camera distorted = referenceCamera();
  RenderOptions options;
  const Renderer pinhole_renderer(pinhole, target, options), renderer(distorted, target, options);
  for (const double tilt : {0.0, 20.0, 40.0, 60.0}) {
    const Eigen::Isometry3d pose = place(pinhole, target, 511.5, 383.5, 0.45, tilt, 0.0);
    const auto rendering = pinhole_renderer.render(pose);
    double renderer_error = 0.0, bias_sum = 0.0, bias_max = 0.0;
    for (std::size_t k = 0; k < target.points().size(); ++k) {
      const Eigen::Vector2d ellipse = ellipseCentre(pinhole, pose, target.points()[k], radius);
      const double spacing_px = 0.04 * pinhole.fx() / (pose * target.points()[k]).z();
      const Eigen::Vector2d centroid = darkCentroid(rendering.radiance, ellipse, 0.3 * spacing_px, options.light_level);
      renderer_error = std::max(renderer_error, (centroid - ellipse).norm());
      const double bias = (ellipse - rendering.truth.pixels[k]).norm();
      bias_sum += bias * bias;
      bias_max = std::max(bias_max, bias);
    }
    const double bias_rms = std::sqrt(bias_sum / static_cast<double>(target.points().size()));

    // The reference (distorted) camera: centroid of each imaged disc vs its projected centre.
    const Eigen::Isometry3d distorted_pose = place(distorted, target, 511.5, 383.5, 0.45, tilt, 0.0);
    const auto distorted_rendering = renderer.render(distorted_pose);
    double distorted_sum = 0.0, distorted_max = 0.0;
    for (std::size_t k = 0; k < target.points().size(); ++k) {
      const Eigen::Vector2d truth = distorted_rendering.truth.pixels[k];
      const double spacing_px = 0.04 * distorted.fx() / (distorted_pose * target.points()[k]).z();
      const Eigen::Vector2d centroid =
          darkCentroid(distorted_rendering.radiance, truth, 0.3 * spacing_px, options.light_level);
      const double bias = (centroid - truth).norm();
      distorted_sum += bias * bias;
      distorted_max = std::max(distorted_max, bias);
    }
    std::cout << "[ render ] circles 7x5 (40 mm pitch, 20 mm discs) at 0.45 m, tilt " << tilt
              << " deg: pinhole: rendered disc centroid vs exact ellipse centre max " << renderer_error
              << " px; perspective bias (ellipse centre - projected centre) RMS " << bias_rms << " px, max " << bias_max
              << " px; reference camera (distorted): disc centroid - projected centre RMS "
              << std::sqrt(distorted_sum / static_cast<double>(target.points().size())) << " px, max " << distorted_max
              << " px\n";
    EXPECT_LT(renderer_error, 0.03) << "tilt " << tilt;
    if (tilt == 0.0) {
      EXPECT_LT(bias_max, 0.05);  // fronto-parallel: only the off-axis discs' small bias...
    } else if (tilt >= 40.0) {
      EXPECT_GT(bias_max, 0.05);  // ...which grows with the tilt
    }
  }
}

TEST(CalibrationViews, AreDeterministicSpreadAndFitTheImage) {
  const Camera camera = referenceCamera();
  const Target target = chessboard();
  mire::datasets::CalibrationViewsSpec spec;
  const auto views = mire::datasets::generateCalibrationViews(camera, target, spec, 3);
  const auto again = mire::datasets::generateCalibrationViews(camera, target, spec, 3);
  ASSERT_EQ(views.size(), 25u);
  double max_tilt = 0.0;
  Eigen::Vector2d min_pixel(1e9, 1e9), max_pixel(-1e9, -1e9);
  for (std::size_t k = 0; k < views.size(); ++k) {
    EXPECT_TRUE(views[k].isApprox(again[k], 0.0));
    const auto truth = mire::datasets::projectFeatures(camera, target, views[k]);
    EXPECT_EQ(truth.visibleCount(), target.points().size());
    for (const auto& pixel : truth.pixels) min_pixel = min_pixel.cwiseMin(pixel), max_pixel = max_pixel.cwiseMax(pixel);
    max_tilt = std::max(max_tilt, std::acos(views[k].linear()(2, 2)) / kDegree);
  }
  EXPECT_GT(max_tilt, 40.0);
  EXPECT_LT(min_pixel.x(), 80.0);
  EXPECT_LT(min_pixel.y(), 80.0);
  EXPECT_GT(max_pixel.x(), camera.width - 80.0);
  EXPECT_GT(max_pixel.y(), camera.height - 80.0);
}

TEST(PoseGrid, EveryPoseSeesTheWholeTarget) {
  const Camera camera = referenceCamera();
  const Target target = chessboard();
  const auto poses = mire::datasets::generatePoseGrid(target, mire::datasets::PoseGridSpec{});
  ASSERT_EQ(poses.size(), 81u);
  EXPECT_EQ(poses.front().id, "p001");
  for (const auto& pose : poses)
    EXPECT_EQ(mire::datasets::projectFeatures(camera, target, pose.camera_T_target).visibleCount(), target.points().size())
        << pose.id;
}

}  // namespace

namespace {

TEST(Render, AprilTagGridIsDetectedWithItsIdsAtTheTruth) {
  // Bit patterns come from libapriltag's own apriltag_to_image: the AprilTag detector must
  // decode every tag with the right id and put its corners where the truth says.
  const Camera camera = referenceCamera();
  TargetSpec spec;
  spec.type = TargetType::AprilTag;
  spec.family = "tag36h11";
  spec.cols = 4;
  spec.rows = 3;
  spec.tag_size_m = 0.05;
  spec.tag_spacing_m = 0.065;
  spec.first_id = 3;
  const Target target(spec);
  RenderOptions options;
  options.blur_sigma_px = 0.8;
  const Renderer renderer(camera, target, options);
  for (const double tilt : {0.0, 40.0}) {
    const Eigen::Isometry3d pose = place(camera, target, 480, 400, 0.5, tilt, 20.0, 10.0);
    const auto rendering = renderer.render(pose);
    const auto detection = mire::metrology::detectTarget(target, rendering.image);
    ASSERT_TRUE(detection.found) << detection.reason;
    EXPECT_EQ(detection.size(), target.points().size());
    const double rms = rmsAgainstTruth(detection, rendering.truth);
    std::cout << "[ render ] AprilTag 36h11 4x3 grid, tilt " << tilt << " deg: " << detection.size() / 4
              << " tags decoded, corner RMS vs truth " << rms << " px\n";
    EXPECT_LT(rms, 0.3);
  }
}

}  // namespace

namespace {

TEST(ReferenceCamera, SpecMatchesTheLensAndItsDistortionIsMonotonic) {
  const Camera camera =
      mire::calibration::readCameraYaml(std::string(MIRE_DATASETS_DIR) + "/specs/reference_camera.yaml");
  EXPECT_EQ(camera.width, 1024);
  EXPECT_EQ(camera.height, 768);
  EXPECT_NEAR(camera.fx(), 3.8e-3 / 4.65e-6, 1e-9);
  // Undistorted radius of the image corners, then the radial map's slope from the centre to
  // 1.5 x beyond it: positive everywhere (no fold-back inside the image).
  Eigen::Vector2d corner_ray;
  ASSERT_TRUE(camera.unproject(Eigen::Vector2d(-0.5, -0.5), &corner_ray));
  const double k1 = camera.params[4], k2 = camera.params[5], k3 = camera.params[8];
  for (double r = 0.0; r <= 1.5 * corner_ray.norm(); r += 1e-3)
    EXPECT_GT(1 + 3 * k1 * r * r + 5 * k2 * std::pow(r, 4) + 7 * k3 * std::pow(r, 6), 0.0) << "r = " << r;
}

}  // namespace
