// `mire measure` against its peers (doc/measurement.md), in one run:
//  1. pose accuracy on the SAME averaged features (feature-level campaign, 10 noisy images per
//     pose): mire (IPPE + Ceres through the full distortion, covariance-weighted) vs
//     cv::solvePnP ITERATIVE / IPPE / SQPnP (with the distortion coefficients) and ViSP vpPose
//     LAGRANGE_VIRTUAL_VS / DEMENTHON_VIRTUAL_VS (on exactly undistorted coordinates);
//  2. the whole pipeline on an 81-pose × 10-image campaign at 1024×768 (rendered once per pose,
//     noise per image): mire's detect-once-then-refine vs cv::findChessboardCornersSB on every
//     image.
// Prints RMS errors and ratios (peer / mire); run by hand.
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/vision/vpPose.h>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <random>

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Clock = std::chrono::steady_clock;

struct PoseVectors {
  Eigen::Vector3d t, r;
};

Vector6d errorOf(const PoseVectors& estimate, const Eigen::Isometry3d& truth) {
  Vector6d e;
  e.head<3>() = estimate.t - truth.translation();
  // Rotation error as the rotation vector of R_est R_trueᵀ (parameterisation-free).
  e.tail<3>() = mire::metrology::rotationVector(mire::metrology::isometryFromVectors(estimate.t, estimate.r).linear() *
                                                truth.linear().transpose());
  return e;
}

mire::metrology::Target board(int cols, int rows, double square) {
  mire::metrology::TargetSpec spec;
  spec.cols = cols;
  spec.rows = rows;
  spec.square_size_m = square;
  return mire::metrology::Target(spec);
}

cv::Mat cameraMatrix(const mire::calibration::Camera& camera) {
  return (cv::Mat_<double>(3, 3) << camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
}

std::optional<PoseVectors> openCvPose(const mire::calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                      const mire::metrology::AveragedFeatures& features, int flags) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& p = points[static_cast<std::size_t>(features.ids[i])];
    object.emplace_back(p.x(), p.y(), p.z());
    image.emplace_back(features.pixels[i].x(), features.pixels[i].y());
  }
  const std::vector<double> distortion(camera.params.begin() + 4, camera.params.end());
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(object, image, cameraMatrix(camera), distortion, rvec, tvec, false, flags)) return std::nullopt;
  return PoseVectors{{tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)},
                     {rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)}};
}

std::optional<PoseVectors> vispPose(const mire::calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                    const mire::metrology::AveragedFeatures& features, bool dementhon_init) {
  vpPose pose;
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& p = points[static_cast<std::size_t>(features.ids[i])];
    Eigen::Vector2d normalized;
    if (!camera.unproject(features.pixels[i], &normalized)) continue;
    vpPoint point(p.x(), p.y(), p.z());
    point.set_x(normalized.x());
    point.set_y(normalized.y());
    pose.addPoint(point);
  }
  vpHomogeneousMatrix cMo;
  try {
    // ViSP 3.5 has no DEMENTHON_LAGRANGE_VIRTUAL_VS: its two VVS variants with a linear init.
    pose.computePose(dementhon_init ? vpPose::DEMENTHON_VIRTUAL_VS : vpPose::LAGRANGE_VIRTUAL_VS, cMo);
  } catch (const vpException&) {
    return std::nullopt;
  }
  const vpTranslationVector t = cMo.getTranslationVector();
  const vpThetaUVector r = cMo.getThetaUVector();
  return PoseVectors{{t[0], t[1], t[2]}, {r[0], r[1], r[2]}};
}

void featureLevelComparison() {
  const auto camera = mire::datasets::referenceCamera();
  const auto target = board(11, 8, 0.025);
  mire::datasets::CampaignGeometry geometry;
  geometry.target_centre_m = Eigen::Vector3d(0.125, 0.0875, 0);
  std::mt19937_64 rng(2024);
  using Method = std::function<std::optional<PoseVectors>(const mire::metrology::AveragedFeatures&)>;
  const std::vector<std::pair<std::string, Method>> methods = {
      {"mire (IPPE + Ceres, weighted)",
       [&](const auto& f) -> std::optional<PoseVectors> {
         const auto e = mire::metrology::estimatePose(camera, target.points(), f);
         if (!e.valid) return std::nullopt;
         return PoseVectors{e.translation, e.rotation_vector};
       }},
      {"cv::solvePnP ITERATIVE",
       [&](const auto& f) { return openCvPose(camera, target.points(), f, cv::SOLVEPNP_ITERATIVE); }},
      {"cv::solvePnP IPPE", [&](const auto& f) { return openCvPose(camera, target.points(), f, cv::SOLVEPNP_IPPE); }},
      {"cv::solvePnP SQPNP", [&](const auto& f) { return openCvPose(camera, target.points(), f, cv::SOLVEPNP_SQPNP); }},
      {"ViSP vpPose LAGRANGE_VIRTUAL_VS", [&](const auto& f) { return vispPose(camera, target.points(), f, false); }},
      {"ViSP vpPose DEMENTHON_VIRTUAL_VS", [&](const auto& f) { return vispPose(camera, target.points(), f, true); }},
  };
  constexpr int kPoses = 200;
  std::vector<Vector6d> sum_squares(methods.size(), Vector6d::Zero());
  std::vector<int> failures(methods.size(), 0);
  for (int p = 0; p < kPoses; ++p) {
    const auto truth = mire::datasets::drawCampaignPose(geometry, rng);
    const auto exact = mire::datasets::exactDetection(camera, target.points(), truth);
    const auto sigmas = mire::datasets::drawFeatureSigmas(target.points().size(), 0.1, 0.5, rng);
    const auto averaged = mire::metrology::averageDetections(mire::datasets::noisyDetections(exact, sigmas, 10, rng));
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const auto estimate = methods[m].second(averaged);
      if (!estimate) {
        ++failures[m];
        continue;
      }
      sum_squares[m] += errorOf(*estimate, truth).cwiseAbs2();
    }
  }
  std::printf("1. pose accuracy on the same averaged features (%d poses, 10 images, sigma 0.1 px +-50%%)\n", kPoses);
  std::printf("   %-44s %9s %9s %9s %9s %9s %9s  %s\n", "method", "tx mm", "ty mm", "tz mm", "rx deg", "ry deg",
              "rz deg", "rms(peer)/rms(mire) worst..best");
  const Vector6d mire_rms = (sum_squares[0] / (kPoses - failures[0])).cwiseSqrt();
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const Vector6d rms = (sum_squares[m] / std::max(1, kPoses - failures[m])).cwiseSqrt();
    std::printf("   %-44s", methods[m].first.c_str());
    for (int c = 0; c < 6; ++c) std::printf(" %9.5f", rms[c] * (c < 3 ? 1000.0 : 180.0 / M_PI));
    const Vector6d ratio = rms.cwiseQuotient(mire_rms);
    std::printf("  %.3f..%.3f", ratio.minCoeff(), ratio.maxCoeff());
    if (failures[m] > 0) std::printf("  (%d failures)", failures[m]);
    std::printf("\n");
  }
}

void pipelineComparison(int kPoses) {
  const auto camera = mire::datasets::referenceCamera();
  const auto target = board(9, 6, 0.03);
  const mire::datasets::Renderer renderer(camera, target);
  mire::datasets::CampaignGeometry geometry;
  geometry.distance_m = 0.7;
  geometry.target_centre_m = Eigen::Vector3d(0.12, 0.075, 0);
  std::mt19937_64 rng(81);
  constexpr int kImages = 10;
  std::printf("2. whole pipeline, %d poses x %d images at %dx%d (rendering...)\n", kPoses, kImages, camera.width,
              camera.height);
  std::vector<std::vector<cv::Mat>> campaign;
  std::vector<Eigen::Isometry3d> truths;
  for (int p = 0; p < kPoses; ++p) {
    truths.push_back(mire::datasets::drawCampaignPose(geometry, rng));
    const auto rendering = renderer.render(truths.back());
    std::vector<cv::Mat> images;
    for (int i = 0; i < kImages; ++i)
      images.push_back(mire::datasets::addNoise(rendering.radiance, {2.0, 0.0}, static_cast<std::uint64_t>(p * 100 + i)));
    campaign.push_back(std::move(images));
  }
  // mire, one thread (the CLI runs poses in parallel on top of this).
  Vector6d mire_sq = Vector6d::Zero();
  int mire_ok = 0;
  const auto mire_start = Clock::now();
  for (int p = 0; p < kPoses; ++p) {
    const auto result = mire::metrology::measurePose(camera, target, campaign[static_cast<std::size_t>(p)], {});
    if (!result.ok) continue;
    ++mire_ok;
    mire_sq +=
        errorOf({result.estimate.translation, result.estimate.rotation_vector}, truths[static_cast<std::size_t>(p)])
            .cwiseAbs2();
  }
  const double mire_seconds = std::chrono::duration<double>(Clock::now() - mire_start).count();
  // Peer: findChessboardCornersSB on every image, averaged corners, solvePnP ITERATIVE.
  Vector6d sb_sq = Vector6d::Zero();
  int sb_ok = 0;
  const auto sb_start = Clock::now();
  for (int p = 0; p < kPoses; ++p) {
    std::vector<cv::Point2f> sum;
    int found = 0;
    for (const auto& image : campaign[static_cast<std::size_t>(p)]) {
      std::vector<cv::Point2f> corners;
      if (!cv::findChessboardCornersSB(image, cv::Size(target.spec().cols, target.spec().rows), corners,
                                       cv::CALIB_CB_ACCURACY))
        continue;
      if (sum.empty()) sum.assign(corners.size(), cv::Point2f(0, 0));
      if (corners.size() != sum.size()) continue;
      for (std::size_t i = 0; i < corners.size(); ++i) sum[i] += corners[i];
      ++found;
    }
    if (found == 0) continue;
    mire::metrology::AveragedFeatures averaged;
    for (std::size_t i = 0; i < sum.size(); ++i) {
      averaged.ids.push_back(static_cast<int>(i));
      averaged.pixels.emplace_back(sum[i].x / found, sum[i].y / found);
    }
    // SB may start its corner order at another board corner than mire's origin (doc/file-formats.md, "Target frame M"):
    // try the four grid orderings and keep the one nearest the truth (generous to the peer).
    const int cols = target.spec().cols, rows = target.spec().rows;
    std::optional<Vector6d> best;
    for (int flip = 0; flip < 4; ++flip) {
      mire::metrology::AveragedFeatures reordered = averaged;
      for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
          const int rr = (flip & 2) ? rows - 1 - r : r, cc = (flip & 1) ? cols - 1 - c : c;
          reordered.ids[static_cast<std::size_t>(r * cols + c)] = rr * cols + cc;
        }
      const auto estimate = openCvPose(camera, target.points(), reordered, cv::SOLVEPNP_ITERATIVE);
      if (!estimate) continue;
      const Vector6d e = errorOf(*estimate, truths[static_cast<std::size_t>(p)]);
      if (!best || e.head<3>().norm() < best->head<3>().norm()) best = e;
    }
    if (!best) continue;
    const Vector6d e = *best;
    if (e.head<3>().norm() > 0.05) continue;
    ++sb_ok;
    sb_sq += e.cwiseAbs2();
  }
  const double sb_seconds = std::chrono::duration<double>(Clock::now() - sb_start).count();
  const Vector6d mire_rms = (mire_sq / std::max(1, mire_ok)).cwiseSqrt();
  const Vector6d sb_rms = (sb_sq / std::max(1, sb_ok)).cwiseSqrt();
  std::printf(
      "   mire measurePose:                %7.2f s, %d/%d poses, rms err t %.4f %.4f %.4f mm, r %.5f %.5f %.5f deg\n",
      mire_seconds, mire_ok, kPoses, mire_rms[0] * 1e3, mire_rms[1] * 1e3, mire_rms[2] * 1e3, mire_rms[3] * 180 / M_PI,
      mire_rms[4] * 180 / M_PI, mire_rms[5] * 180 / M_PI);
  std::printf(
      "   findChessboardCornersSB x %d:   %7.2f s, %d/%d poses, rms err t %.4f %.4f %.4f mm, r %.5f %.5f %.5f deg\n",
      kPoses * kImages, sb_seconds, sb_ok, kPoses, sb_rms[0] * 1e3, sb_rms[1] * 1e3, sb_rms[2] * 1e3,
      sb_rms[3] * 180 / M_PI, sb_rms[4] * 180 / M_PI, sb_rms[5] * 180 / M_PI);
  std::printf("   speed ratio (SB time / mire time): %.2fx (target >= 5x)\n", sb_seconds / mire_seconds);
}

}  // namespace

// Usage: bench_measure [poses for the pipeline part, default 81]
int main(int argc, char** argv) {
  const int pipeline_poses = argc > 1 ? std::max(1, std::atoi(argv[1])) : 81;
  featureLevelComparison();
  pipelineComparison(pipeline_poses);
  return 0;
}
