// Static-pose integrity and campaign screening on the demo's campaign
// (doc/measurement.md, "Imperfect campaigns"), run by hand:
//   bench_integrity [campaign_dir]   (default /tmp/mire-bench-integrity; generated if absent)
//  1. false alarms: the 81 genuinely static poses × 10 images of the H4 reference campaign
//     (MechanismImageCampaignSpec::reference("h4"): defocus 0.6 px, read + shot noise), measured with the true
//     camera; how many fail the integrity test, the largest pairwise χ² / threshold, the
//     screening flags, and the time with and without the test (same run);
//  2. sensitivity: for 10 of those poses, 6 + 4 images of two views 1 mm or 0.1° apart
//     (rendered with the campaign's optics and noise): caught, and the image displacement;
//  3. screening: the campaign with one pose downscaled (×¼ and back) and one blurred (σ 3 px).
#include "feature_displacement.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/campaign_screening.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using mire::metrology::PoseMeasurement;

double seconds(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::vector<cv::Mat> readGrey(const std::vector<fs::path>& files) {
  std::vector<cv::Mat> images;
  for (const auto& file : files) images.push_back(cv::imread(file.string(), cv::IMREAD_GRAYSCALE));
  return images;
}

std::vector<std::string> names(const std::vector<fs::path>& files) {
  std::vector<std::string> result;
  for (const auto& file : files) result.push_back(file.filename().string());
  return result;
}

// Rotation by `degrees` about `axis` (target frame) through the target's centre.
Eigen::Isometry3d rotatedAboutCentre(const Eigen::Isometry3d& pose, const mire::metrology::Target& target,
                                     const Eigen::Vector3d& axis, double degrees) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : target.points()) centre += p;
  centre /= static_cast<double>(target.points().size());
  Eigen::Isometry3d rotation = Eigen::Isometry3d::Identity();
  rotation.linear() = Eigen::AngleAxisd(degrees * M_PI / 180, axis).toRotationMatrix();
  rotation.translation() = centre - rotation.linear() * centre;
  return pose * rotation;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path directory = argc > 1 ? fs::path(argv[1]) : fs::path("/tmp/mire-bench-integrity");
  const auto spec = mire::datasets::MechanismImageCampaignSpec::reference("h4");
  if (!fs::exists(directory / "poses")) {
    const auto start = Clock::now();
    mire::datasets::generateMechanismImageCampaign(spec, directory);
    std::printf("generated the campaign in %.0f s\n", seconds(start));
  }
  const auto camera = mire::calibration::readCameraYaml(spec.camera_file);
  const auto target = mire::metrology::Target::fromFile(directory / "target.yaml");

  // 1. False alarms on 81 static poses, and the cost of the test.
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(directory / "poses"))
    if (entry.is_directory()) folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  mire::metrology::MeasurementOptions without;
  without.integrity.enabled = false;
  std::vector<mire::metrology::MeasuredPose> poses;
  std::vector<std::vector<cv::Mat>> pose_images;
  int failed = 0;
  double worst_ratio = 0.0, time_with = 0.0, time_without = 0.0;
  std::vector<double> ratios, q_ratios;
  double q_sum = 0.0, q_dof = 0.0;
  for (const auto& folder : folders) {
    const auto files = mire::metrology::listPoseImages(folder);
    const auto images = readGrey(files);
    auto start = Clock::now();
    const PoseMeasurement with_test = mire::metrology::measurePose(camera, target, images, names(files));
    time_with += seconds(start);
    start = Clock::now();
    const PoseMeasurement plain = mire::metrology::measurePose(camera, target, images, names(files), without);
    time_without += seconds(start);
    if (!with_test.ok) {
      ++failed;
      std::printf("pose %s FAILED: %s\n", folder.filename().c_str(), with_test.error.c_str());
      continue;
    }
    const double ratio = with_test.integrity.max_statistic / with_test.integrity.threshold;
    ratios.push_back(ratio);
    q_ratios.push_back(with_test.integrity.global_statistic / with_test.integrity.global_threshold);
    q_sum += with_test.integrity.global_statistic;
    q_dof += 6.0 * (with_test.integrity.tested_images - 1);
    worst_ratio = std::max(worst_ratio, ratio);
    poses.emplace_back(folder.filename().string(), with_test.features.images_used, static_cast<int>(files.size()),
                       with_test.estimate, mire::metrology::measurementFlags(with_test));
    pose_images.push_back(images);
    (void)plain;
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf(
      "static poses: %zu, failed by the integrity test: %d; max pairwise chi2 / threshold: median %.2f, "
      "worst %.2f\n",
      folders.size(), failed, ratios.empty() ? 0.0 : ratios[ratios.size() / 2], worst_ratio);
  std::sort(q_ratios.begin(), q_ratios.end());
  std::printf(
      "homogeneity Q / threshold: median %.2f, worst %.2f; sum Q / sum dof %.3f (1 when the noise model "
      "holds)\n",
      q_ratios.empty() ? 0.0 : q_ratios[q_ratios.size() / 2], q_ratios.empty() ? 0.0 : q_ratios.back(), q_sum / q_dof);
  std::printf("time for %zu poses: %.1f s with the test, %.1f s without (ratio %.2f)\n", folders.size(), time_with,
              time_without, time_with / time_without);
  auto screened = poses;
  const auto screening = mire::metrology::screenCampaign(&screened);
  int flagged = 0;
  for (std::size_t i = 0; i < screened.size(); ++i)
    if (!screening.reasons[i].empty()) {
      ++flagged;
      std::printf("  flagged %s: %s\n", screened[i].pose_id.c_str(), screening.reasons[i].front().c_str());
    }
  std::printf("screening of the static campaign: %d of %zu poses flagged\n", flagged, screened.size());

  // 2. Sensitivity: 6 + 4 images of two views, for 10 poses.
  const mire::datasets::Renderer renderer(camera, target, spec.render);
  struct Motion {
    const char* name;
    Eigen::Vector3d shift;
    Eigen::Vector3d axis;
    double degrees;
  };
  const std::vector<Motion> motions = {
      {"1 mm x", {1e-3, 0, 0}, Eigen::Vector3d::UnitX(), 0},
      {"1 mm z", {0, 0, 1e-3}, Eigen::Vector3d::UnitX(), 0},
      {"0.1 deg about target x", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.1},
      {"0.1 deg about target y", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0.1},
      {"0.1 deg about target z", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.1}};
  for (const Motion& motion : motions) {
    int caught = 0, named = 0;
    double min_px = 1e9, max_px = 0;
    for (std::size_t p = 0; p < 10 && p < poses.size(); ++p) {
      const std::size_t index = p * (poses.size() / 10);
      const Eigen::Isometry3d pose = poses[index].estimate.cTm;
      Eigen::Isometry3d other = rotatedAboutCentre(pose, target, motion.axis, motion.degrees);
      other.translation() += motion.shift;
      const double px = mire::test::displacementPx(camera, target, pose, other);
      min_px = std::min(min_px, px);
      max_px = std::max(max_px, px);
      const auto a = renderer.render(pose), b = renderer.render(other);
      std::vector<cv::Mat> images;
      std::vector<std::string> image_names;
      for (int i = 0; i < 10; ++i) {
        const bool moved = i == 2 || i == 5 || i == 7 || i == 9;
        images.push_back(mire::datasets::addNoise(moved ? b.radiance : a.radiance, spec.noise, 777 + 10 * p + i));
        image_names.push_back("img_" + std::to_string(i));
      }
      const PoseMeasurement result = mire::metrology::measurePose(camera, target, images, image_names);
      if (!result.ok && !result.integrity.consistent) ++caught;
      if (result.integrity.moved == std::vector<int>{2, 5, 7, 9}) ++named;
    }
    std::printf("%-24s displacement %.3f-%.3f px rms: caught %d/10, moved images named exactly %d/10\n", motion.name,
                min_px, max_px, caught, named);
  }

  // 3. Screening with one downscaled and one blurred pose.
  const std::size_t downscaled = 20, blurred = 60;
  for (const std::size_t which : {downscaled, blurred}) {
    std::vector<cv::Mat> images;
    for (std::size_t i = 0; i < pose_images[which].size(); ++i) {
      cv::Mat image = pose_images[which][i].clone();
      if (which == downscaled) {
        cv::Mat small;
        cv::resize(image, small, cv::Size(), 0.25, 0.25, cv::INTER_AREA);
        cv::resize(small, image, image.size(), 0, 0, cv::INTER_LINEAR);
      } else {
        cv::GaussianBlur(image, image, cv::Size(), 3.0);
      }
      images.push_back(image);
    }
    std::vector<std::string> image_names;
    for (std::size_t i = 0; i < images.size(); ++i) image_names.push_back("img_" + std::to_string(i));
    const PoseMeasurement result = mire::metrology::measurePose(camera, target, images, image_names);
    if (!result.ok) {
      std::printf("%s pose failed: %s\n", which == downscaled ? "downscaled" : "blurred", result.error.c_str());
      continue;
    }
    const Eigen::Vector3d error = result.estimate.translation - poses[which].estimate.translation;
    std::printf("%s pose %s: rms %.3f px (was %.3f), moved %.3f mm from the sharp measurement\n",
                which == downscaled ? "downscaled" : "blurred", poses[which].pose_id.c_str(), result.estimate.rms_px,
                poses[which].estimate.rms_px, 1e3 * error.norm());
    poses[which] = mire::metrology::MeasuredPose(poses[which].pose_id, result.features.images_used,
                                                 poses[which].images_total, result.estimate);
  }
  const auto modified = mire::metrology::screenCampaign(&poses);
  for (std::size_t i = 0; i < poses.size(); ++i)
    for (const auto& reason : modified.reasons[i])
      std::printf("  flagged %s: %s\n", poses[i].pose_id.c_str(), reason.c_str());
  return 0;
}
