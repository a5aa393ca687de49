// `mire measure`: target poses cTm with their precision, from one image folder per pose
// (doc/measurement.md; poses.csv: doc/file-formats.md). Poses are measured in parallel; a pose that fails is reported
// and left out, the others are written (exit code 3 then).
#include "commands.hpp"
#include "detections_io.hpp"
#include "measure_legs.hpp"
#include "measure_report.hpp"
#include "mire/pipeline/image_folders.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/campaign_screening.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/shared_term_csv.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/side_files.hpp"
#include "mire/support/statistics.hpp"

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
  std::string save_detections;        // CSV of every image's detections (doc/targets.md)
  std::string split_moving = "fail";  // static-pose integrity: fail | keep-largest
  std::string report;                 // folder for report.html and report.json
  std::vector<std::string> command_line;
  LegMeasureArguments legs;  // --legs: the legs' axes instead of the target (measure_legs.hpp)
};

using support::median;

void printSummary(const std::vector<metrology::MeasuredPose>& poses) {
  std::vector<std::vector<double>> total(6), noise(6);
  int ambiguous = 0;
  std::vector<double> rms, used;
  for (const auto& pose : poses) {
    const auto sigma = metrology::PoseEstimate::sigmas(pose.estimate.covariance);
    const auto sigma_noise = metrology::PoseEstimate::sigmas(pose.estimate.covariance_pixel_noise);
    for (int c = 0; c < 6; ++c) {
      const double scale = c < 3 ? 1000.0 : 180.0 / support::kPi;
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

// Campaign-level screening (campaign_screening.hpp): flags in poses.csv, reasons here.
void reportScreening(std::vector<metrology::MeasuredPose>* measured) {
  const metrology::ScreeningResult screening = metrology::screenCampaign(measured);
  int flagged = 0;
  for (std::size_t i = 0; i < measured->size(); ++i) {
    for (const auto& reason : screening.reasons[i])
      std::cerr << "mire measure: pose " << (*measured)[i].pose_id << ": FLAGGED: " << reason << "\n";
    flagged += screening.reasons[i].empty() ? 0 : 1;
  }
  if (flagged > 0)
    std::cerr << "mire measure: " << flagged << " pose(s) stand out from the campaign (column 'flags' of poses.csv)\n";
}

int runMeasure(const MeasureSettings& settings) {
  if (settings.target_path.empty()) throw UsageError("--target target.yaml is required (or --legs legs.yaml)");
  if (!settings.legs.joints.empty() || !settings.legs.save_contours.empty())
    throw UsageError("--joints and --save-leg-contours go with --legs");
  const fs::path output = settings.output_path;
  const fs::path covariance =
      settings.covariance_path.empty() ? support::covarianceSidePath(output) : fs::path(settings.covariance_path);
  CommandPaths paths{
      {{settings.camera_path, "--camera"}, {settings.target_path, "--target"}},
      {{settings.poses_dir, "--poses"}},
      {{output, "-o"}, {covariance, settings.covariance_path.empty() ? "the covariance side file" : "--covariance"}},
      {}};
  const fs::path shared = support::sharedTermSidePath(output);
  paths.output_files.push_back({shared, "the shared-term side file"});
  if (!settings.save_detections.empty()) paths.output_files.push_back({settings.save_detections, "--save-detections"});
  if (!settings.report.empty()) paths.output_folders.push_back({settings.report, "--report"});
  checkCommandPaths(paths);
  const int threads = workerThreads(settings.threads, "--threads");
  const calibration::Camera camera = calibration::readCamera(settings.camera_path);
  checkCamera(camera, settings.camera_path);
  const metrology::Target target = metrology::Target::fromFile(settings.target_path);
  checkTargetSize(target, settings.target_path);
  if (camera.covariance.size() == 0)
    std::cerr << "mire measure: warning: " << settings.camera_path
              << " has no covariance: sigmas include pixel noise only (too optimistic, see README)\n";

  metrology::MeasurementOptions options;
  options.pose.ambiguity_ratio = settings.ambiguity_ratio;
  options.averaging.rejection_confidence = settings.rejection_confidence;
  options.integrity.split =
      settings.split_moving == "keep-largest" ? metrology::SplitPolicy::KeepLargest : metrology::SplitPolicy::Fail;

  const std::vector<pipeline::PoseFolderMeasurement> jobs =
      pipeline::measurePoseFolders(camera, target, settings.poses_dir, options, threads);

  std::vector<metrology::MeasuredPose> measured;
  std::vector<FailedPose> failed_poses;
  int failed = 0;
  for (const pipeline::PoseFolderMeasurement& job : jobs) {
    for (const auto& warning : job.measurement.warnings)
      std::cerr << "mire measure: pose " << job.pose_id << ": warning: " << warning << "\n";
    for (const auto& note : job.measurement.notes)
      std::cerr << "mire measure: pose " << job.pose_id << ": note: " << note << "\n";
    if (!job.measurement.ok) {
      ++failed;
      std::cerr << "mire measure: pose " << job.pose_id << ": FAILED: " << job.measurement.error << "\n";
      failed_poses.push_back({job.pose_id, job.measurement.error});
      continue;
    }
    measured.emplace_back(job.pose_id, job.measurement.features.images_used, job.images_total, job.measurement.estimate,
                          metrology::measurementFlags(job.measurement));
  }
  reportScreening(&measured);
  if (measured.empty()) {
    std::cerr << "mire measure: error: no pose could be measured (" << failed << " failed); nothing written\n";
    return kFailure;
  }
  std::vector<double> distances;
  distances.reserve(measured.size());
  for (const auto& pose : measured) distances.push_back(pose.estimate.translation.norm());
  checkImpliedDistances(distances, settings.target_path, "pose");
  // All files or none; the side files land first, so a poses.csv never pairs with an older
  // run's side files (doc/robustness.md). Without a camera covariance there is no shared
  // term: an older run's file is removed so identify cannot pair it.
  support::OutputTransaction outputs;
  if (!settings.save_detections.empty())
    support::writeFileAtomically(outputs.stageFile(settings.save_detections),
                                 metrology::detectionsCsv(target, measureDetections(jobs), camera.width, camera.height));
  const metrology::DetectorBiasTerm bias = pipeline::sharedDetectorBias(camera, target, jobs, options);
  const std::string shared_text = metrology::sharedTermCsvString(camera, measured, bias);
  if (!shared_text.empty()) support::writeFileAtomically(outputs.stageFile(shared), shared_text);
  metrology::writePosesCovarianceCsv(outputs.stageFile(covariance), measured);
  metrology::writePosesCsv(outputs.stageFile(output), measured);
  if (!settings.report.empty()) {
    const fs::path dir = outputs.stageFolder(settings.report);
    MeasureReportData report{{settings.command_line, paths.input_files, paths.output_files},
                             measured,
                             failed_poses,
                             bias,
                             camera.covariance.size() > 0};
    report.provenance.inputs.push_back({settings.poses_dir, "--poses"});
    report.provenance.outputs.push_back({settings.report, "--report"});
    writeMeasureReportJson(dir / "report.json", report);
    writeMeasureReportHtml(dir / "report.html", report);
  }
  outputs.commit();
  if (shared_text.empty()) fs::remove(shared);
  printSummary(measured);
  std::printf("measured %zu of %zu poses -> %s (covariances: %s%s)%s\n", measured.size(), jobs.size(),
              output.string().c_str(), covariance.string().c_str(),
              shared_text.empty() ? "" : ("; shared calibration term: " + shared.string()).c_str(),
              settings.report.empty() ? "" : ("; report: " + settings.report + "/report.html").c_str());
  std::printf("detector bias shared by the poses: %s\n", bias.text().c_str());
  if (failed > 0) {
    std::cerr << "mire measure: " << failed << " pose(s) failed (listed above); the others were written\n";
    return kPartialFailure;
  }
  return kOk;
}

// --legs: the target's options do not apply; --joints is needed.
LegMeasureArguments legArguments(const MeasureSettings& settings) {
  if (!settings.target_path.empty())
    throw UsageError("--legs measures the legs only: run measure once with --target and once with --legs");
  if (settings.legs.joints.empty()) throw UsageError("--legs needs --joints joints.csv (the poses' joints)");
  LegMeasureArguments args = settings.legs;
  args.camera = settings.camera_path;
  args.poses = settings.poses_dir;
  args.output = settings.output_path;
  args.threads = settings.threads;
  return args;
}

}  // namespace

Runner addMeasureCommand(CLI::App& app) {
  auto settings = std::make_shared<MeasureSettings>();
  CLI::App* command =
      app.add_subcommand("measure", "measure target poses cTm (with their precision) from one image folder per pose");
  command
      ->add_option("--camera", settings->camera_path,
                   "camera file: camera.yaml, ROS camera_info, ViSP XML or Kalibr camchain (detected from the content)")
      ->required();
  command->add_option("--target", settings->target_path, "target.yaml (the target poses; or --legs)");
  command
      ->add_option("--poses", settings->poses_dir, "folder holding one subfolder of images per pose (named by pose id)")
      ->required();
  command->add_option("-o,--output", settings->output_path, "poses.csv to write (legs.csv with --legs)")->required();
  command->add_option("--covariance", settings->covariance_path,
                      "6x6 covariances side file (default: <output stem>_covariance.csv)");
  command->add_option("--threads", settings->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  command
      ->add_option("--ambiguity-ratio", settings->ambiguity_ratio,
                   "flag a pose ambiguous when cost(planar flip) < ratio x cost(best)")
      ->check(finiteNumber())
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      ->add_option("--rejection-confidence", settings->rejection_confidence,
                   "chi-square confidence of the outlier-observation test (a moved image is the static-pose test's "
                   "business, see --split-moving)")
      ->check(finiteNumber())
      ->check(CLI::Range(0.5, 0.999999999))
      ->capture_default_str();
  command->add_option("--save-detections", settings->save_detections,
                      "write every image's detections (CSV, doc/targets.md)");
  command
      ->add_option("--split-moving", settings->split_moving,
                   "when a pose's images do not show one static pose: fail it, or keep the largest consistent "
                   "group (more than half of the images) and list the rest")
      ->check(CLI::IsMember({"fail", "keep-largest"}))
      ->capture_default_str();
  command->add_option("--report", settings->report,
                      "report folder (report.html: the precision of every pose; report.json)");
  command->add_option("--legs", settings->legs.legs,
                      "legs.yaml: measure the legs' axes (legs.csv) instead of the target (doc/legs.md)");
  command->add_option("--joints", settings->legs.joints, "joints.csv of the poses (with --legs)");
  command->add_option("--save-leg-contours", settings->legs.save_contours,
                      "with --legs: a folder for each pose's first image with the fitted contours drawn");
  return [settings, command] {
    settings->command_line = commandLineOf(*command);
    return settings->legs.legs.empty() ? runMeasure(*settings) : runLegMeasure(legArguments(*settings));
  };
}

}  // namespace mire::app
