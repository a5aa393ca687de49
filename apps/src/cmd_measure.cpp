// `mire measure`: target poses cTm with their precision, from one image folder per pose
// (../shared/BRIEF.md §3, §10). Poses are measured in parallel; a pose that fails is reported
// and left out, the others are written (exit code 3 then).
#include "commands.hpp"
#include "image_folders.hpp"

#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/shared_term_csv.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

struct MeasureSettings {
  std::string camera_path;
  std::string target_path;
  std::string poses_dir;
  std::string output_path;
  std::string covariance_path;  // default: <output stem>_covariance.csv
  int threads = 0;              // 0 = all cores
  double ambiguity_ratio = 4.0;
  double rejection_confidence = 0.999;
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

void printSummary(const std::vector<metrology::MeasuredPose>& poses) {
  std::vector<std::vector<double>> total(6), noise(6);
  int ambiguous = 0;
  std::vector<double> rms, used;
  for (const auto& pose : poses) {
    const auto sigma = metrology::PoseEstimate::sigmas(pose.estimate.covariance);
    const auto sigma_noise = metrology::PoseEstimate::sigmas(pose.estimate.covariance_pixel_noise);
    for (int c = 0; c < 6; ++c) {
      const double scale = c < 3 ? 1000.0 : 180.0 / M_PI;
      total[static_cast<std::size_t>(c)].push_back(sigma[c] * scale);
      noise[static_cast<std::size_t>(c)].push_back(sigma_noise[c] * scale);
    }
    ambiguous += pose.estimate.ambiguous ? 1 : 0;
    rms.push_back(pose.estimate.rms_px);
    used.push_back(pose.images_used);
  }
  const char* names[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  std::printf("median sigma per component (reference system: 0.2 mm and 0.03 deg):\n");
  std::printf("  %-4s %12s %16s\n", "", "total", "pixel noise only");
  for (int c = 0; c < 6; ++c)
    std::printf("  %-4s %9.4f %-3s %12.4f %s\n", names[c], median(total[static_cast<std::size_t>(c)]),
                c < 3 ? "mm" : "deg", median(noise[static_cast<std::size_t>(c)]), c < 3 ? "mm" : "deg");
  std::printf("median reprojection rms %.4f px, median images used %.1f", median(rms), median(used));
  if (ambiguous > 0) std::printf(", %d ambiguous pose(s) (planar flip, see column 'ambiguous')", ambiguous);
  std::printf("\n");
}

int runMeasure(const MeasureSettings& settings) {
  const calibration::Camera camera = calibration::readCameraYaml(settings.camera_path);
  const metrology::Target target = metrology::Target::fromFile(settings.target_path);
  if (camera.covariance.size() == 0)
    std::cerr << "mire measure: warning: " << settings.camera_path
              << " has no covariance: sigmas include pixel noise only (too optimistic, see README)\n";

  metrology::MeasurementOptions options;
  options.pose.ambiguity_ratio = settings.ambiguity_ratio;
  options.averaging.rejection_confidence = settings.rejection_confidence;

  const std::vector<PoseFolderMeasurement> jobs =
      measurePoseFolders(camera, target, settings.poses_dir, options, settings.threads);

  std::vector<metrology::MeasuredPose> measured;
  int failed = 0;
  for (const PoseFolderMeasurement& job : jobs) {
    for (const auto& warning : job.measurement.warnings)
      std::cerr << "mire measure: pose " << job.pose_id << ": warning: " << warning << "\n";
    if (!job.measurement.ok) {
      ++failed;
      std::cerr << "mire measure: pose " << job.pose_id << ": FAILED: " << job.measurement.error << "\n";
      continue;
    }
    measured.push_back({job.pose_id, job.measurement.features.images_used, job.images_total, job.measurement.estimate});
  }
  if (measured.empty()) {
    std::cerr << "mire measure: error: no pose could be measured (" << failed << " failed); nothing written\n";
    return kFailure;
  }
  const fs::path output = settings.output_path;
  const fs::path covariance =
      settings.covariance_path.empty() ? metrology::covarianceSidePath(output) : fs::path(settings.covariance_path);
  metrology::writePosesCsv(output, measured);
  metrology::writePosesCovarianceCsv(covariance, measured);
  const fs::path shared = metrology::sharedTermSidePath(output);
  const bool wrote_shared = metrology::writeSharedTermCsv(shared, camera, measured);
  std::printf("measured %zu of %zu poses -> %s (covariances: %s%s)\n", measured.size(), jobs.size(),
              output.string().c_str(), covariance.string().c_str(),
              wrote_shared ? ("; shared calibration term: " + shared.string()).c_str() : "");
  printSummary(measured);
  if (failed > 0) {
    std::cerr << "mire measure: " << failed << " pose(s) failed (listed above); the others were written\n";
    return kPartialFailure;
  }
  return kOk;
}

}  // namespace

Runner addMeasureCommand(CLI::App& app) {
  auto settings = std::make_shared<MeasureSettings>();
  CLI::App* command = app.add_subcommand(
      "measure", "measure target poses cTm (with their precision) from one image folder per pose");
  command->add_option("--camera", settings->camera_path, "camera.yaml (intrinsics, distortion, covariance)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--target", settings->target_path, "target.yaml")->required()->check(CLI::ExistingFile);
  command->add_option("--poses", settings->poses_dir, "folder holding one subfolder of images per pose (named by pose id)")
      ->required()
      ->check(CLI::ExistingDirectory);
  command->add_option("-o,--output", settings->output_path, "poses.csv to write")->required();
  command->add_option("--covariance", settings->covariance_path,
                      "6x6 covariances side file (default: <output stem>_covariance.csv)");
  command->add_option("--threads", settings->threads, "worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  command->add_option("--ambiguity-ratio", settings->ambiguity_ratio,
                      "flag a pose ambiguous when cost(planar flip) < ratio x cost(best)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--rejection-confidence", settings->rejection_confidence,
                      "chi-square confidence of the outlier-image test")
      ->check(CLI::Range(0.5, 0.999999999))
      ->capture_default_str();
  return [settings] { return runMeasure(*settings); };
}

}  // namespace mire::app
