// `mire calibrate`: camera intrinsics + distortion from a folder of target images
// (doc/calibration.md; camera.yaml and target.yaml: doc/file-formats.md). Detection runs in parallel on all cores;
// images without the target are listed and skipped; bad input (empty folder, unreadable image, bad target spec,
// too few usable views) stops with a message naming the cause and writes nothing.
#include "commands.hpp"
#include "detections_io.hpp"
#include "mire/pipeline/image_folders.hpp"
#include "output_paths.hpp"
#include "report_html.hpp"
#include "report_json.hpp"
#include "validate.hpp"

#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/calibration/model_check.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/output_transaction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

struct CalibrateArguments {
  std::string target_path;
  std::string images_dir;
  std::string model = "opencv5";
  std::vector<std::string> fixed_parameters;  // --fix k3,p1,p2
  bool refine_target = false;
  std::string output_path;
  std::string report_dir;
  int threads = 0;
  int holdout_folds = 0;                  // --holdout K: k-fold held-out check over views
  std::string save_detections;            // CSV of every view's detections (doc/targets.md)
  std::string detections_path;            // calibrate from this file instead of images
  std::vector<int> image_size;            // width height, for a detections file that does not say
  std::vector<std::string> command_line;  // as parsed, for report.json
};

std::string fixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

// mire's keys beyond camera_io's (same FileStorage YAML, top level).
std::string extraYamlKeys(const calibration::CalibrationResult& result,
                          const calibration::ProjectionUncertaintySummary& uncertainty) {
  std::ostringstream out;
  out << "# mire calibrate: solution quality (see README 'mire calibrate')\n";
  out << "sigma_px: " << support::formatNumber(result.sigma_px) << "\n";
  out << "# sigma = pixel-noise sigma x sigma_inflation (>= 1, view-cluster sandwich: systematic error), per "
         "parameter\n";
  out << "sigma_inflation: [ ";
  for (std::size_t i = 0; i < result.sigma_inflation.size(); ++i)
    out << (i ? ", " : "") << support::formatNumber(result.sigma_inflation[i]);
  out << " ]\n";
  out << "views_used: " << result.used_views << "\n";
  out << "views_rejected: " << result.rejected_views << "\n";
  out << "points_used: " << result.used_points << "\n";
  out << "points_rejected: " << result.rejected_points << "\n";
  out << "target_refined: " << (result.target_refined ? 1 : 0) << "\n";
  out << "projection_uncertainty_distance_m: " << support::formatNumber(result.uncertainty_distance_m) << "\n";
  // −1 where undefined (the pixel cannot be unprojected: beyond the model's invertible field);
  // nothing non-finite is ever written.
  const auto value = [](double px) { return support::formatNumber(std::isfinite(px) ? px : -1.0); };
  out << "# projection_uncertainty_px: centre, edge, corner; -1 = undefined there (pixel outside the lens model's "
         "invertible field)\n";
  out << "projection_uncertainty_px: [ " << value(uncertainty.centre_px) << ", " << value(uncertainty.edge_px) << ", "
      << value(uncertainty.corner_px) << " ]\n";
  return out.str();
}

std::string viewsCsv(const calibration::CalibrationResult& result) {
  std::ostringstream out;
  out << "image,used,points,inliers,rms_px,tilt_deg,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,reason\n";
  for (const auto& view : result.views) {
    const int inliers = static_cast<int>(std::count(view.inlier.begin(), view.inlier.end(), true));
    out << view.name << "," << (view.used ? 1 : 0) << "," << view.ids.size() << "," << inliers << ","
        << support::formatNumber(view.rms_px, 6) << "," << support::formatNumber(view.tilt_deg, 4);
    for (int i = 0; i < 3; ++i) out << "," << support::formatNumber(view.translation[i], 10);
    for (int i = 0; i < 3; ++i) out << "," << support::formatNumber(view.rotation[i], 10);
    std::string reason = view.rejection_reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    out << "," << reason << "\n";
  }
  return out.str();
}

std::string targetCsv(const calibration::CalibrationResult& result, const std::vector<Eigen::Vector3d>& nominal) {
  std::ostringstream out;
  out << "# refined target points (Lavest & Dhome), target frame M, mm; gauge points " << result.gauge_points[0] << ", "
      << result.gauge_points[1] << " fixed, z of " << result.gauge_points[2] << " fixed\n";
  out << "id,x_mm,y_mm,z_mm,dx_mm,dy_mm,dz_mm\n";
  for (std::size_t i = 0; i < nominal.size(); ++i) {
    const Eigen::Vector3d p = result.target_points[i] * 1e3, d = (result.target_points[i] - nominal[i]) * 1e3;
    out << i << "," << support::formatNumber(p.x(), 8) << "," << support::formatNumber(p.y(), 8) << ","
        << support::formatNumber(p.z(), 8) << "," << support::formatNumber(d.x(), 6) << ","
        << support::formatNumber(d.y(), 6) << "," << support::formatNumber(d.z(), 6) << "\n";
  }
  return out.str();
}

// Everything that can be checked before the long work is checked first. Returns the paths
// (report.json's provenance).
CommandPaths checkCalibratePaths(const CalibrateArguments& args) {
  if (args.images_dir.empty() == args.detections_path.empty()) throw UsageError("give either --images or --detections");
  if (!args.image_size.empty() &&
      (args.image_size.size() != 2 || args.image_size[0] < 1 || args.image_size[1] < 1 ||
       args.image_size[0] > static_cast<int>(kMaxImageSide) || args.image_size[1] > static_cast<int>(kMaxImageSide)))
    throw UsageError("--image-size: expected WIDTH HEIGHT, each 1.." + std::to_string(kMaxImageSide) + " px");
  CommandPaths paths{{{args.target_path, "--target"}}, {}, {{args.output_path, "-o"}}, {}};
  if (!args.images_dir.empty()) paths.input_folders.push_back({args.images_dir, "--images"});
  if (!args.detections_path.empty()) paths.input_files.push_back({args.detections_path, "--detections"});
  if (!args.save_detections.empty()) paths.output_files.push_back({args.save_detections, "--save-detections"});
  if (!args.report_dir.empty()) paths.output_folders.push_back({args.report_dir, "--report"});
  checkCommandPaths(paths);
  return paths;
}

metrology::Target readTarget(const std::string& path) {
  try {
    return metrology::Target::fromFile(path);
  } catch (const std::exception& error) {
    throw std::runtime_error("target spec: " + std::string(error.what()));
  }
}

// Two views with the very same detections are one image given twice (sub-pixel corners of two
// exposures never agree to the last bit): counted as independent views they shrink every σ by
// √copies and pull the fit towards that pose.
void refuseCopiedViews(const std::vector<calibration::CalibrationView>& views, const std::string& where) {
  std::map<std::pair<std::vector<int>, std::vector<std::pair<double, double>>>, std::string> seen;
  for (const calibration::CalibrationView& view : views) {
    std::vector<std::pair<double, double>> pixels;
    pixels.reserve(view.pixels.size());
    for (const Eigen::Vector2d& p : view.pixels) pixels.emplace_back(p.x(), p.y());
    const auto [at, inserted] = seen.emplace(std::make_pair(view.ids, std::move(pixels)), view.name);
    if (!inserted)
      throw std::runtime_error("'" + where + "': " + view.name + " has exactly the detections of " + at->second +
                               ": the same image twice; each view must be an image of its own (a copy would make "
                               "every sigma too small)");
  }
}

// The views: detected in the images (in parallel) or read from a detections file; the images
// without the target are listed. At least 3 views, or an error naming the folder.
pipeline::CalibrationFolder readCalibrationViews(const CalibrateArguments& args, const metrology::Target& target,
                                                 int threads) {
  pipeline::CalibrationFolder folder =
      args.detections_path.empty() ? pipeline::detectCalibrationFolder(target, args.images_dir, threads)
                                   : calibrationFolderFromDetections(target, args.detections_path, args.image_size);
  for (const auto& [name, reason] : folder.skipped) std::cout << "skipped " << name << ": " << reason << "\n";
  for (const auto& [name, reason] : folder.notes) std::cout << "note " << name << ": " << reason << "\n";
  refuseCopiedViews(folder.views, args.detections_path.empty() ? args.images_dir : args.detections_path);
  if (folder.views.size() < 3)
    throw std::runtime_error("the target was found in " + std::to_string(folder.views.size()) + " of " +
                             std::to_string(folder.images) + " images in '" +
                             (args.detections_path.empty() ? args.images_dir : args.detections_path) +
                             "': calibration needs at least 3 (check target.yaml's cols/rows and type)");
  return folder;
}

// Outputs, all or nothing (doc/robustness.md): camera.yaml, then the report.
void writeCalibrateOutputs(const CalibrateArguments& args, const CommandPaths& paths, const metrology::Target& target,
                           const pipeline::CalibrationFolder& folder, const calibration::CalibrationResult& result,
                           const calibration::ProjectionUncertaintySummary& uncertainty,
                           const calibration::ModelCheck& check) {
  support::OutputTransaction outputs;
  support::writeFileAtomically(outputs.stageFile(args.output_path),
                               calibration::cameraYamlString(result.camera) + extraYamlKeys(result, uncertainty));
  if (!args.report_dir.empty()) {
    const fs::path dir = outputs.stageFolder(args.report_dir);
    writeSvgFiles(dir, calibrateFigures(result, check));
    support::writeFileAtomically(dir / "views.csv", viewsCsv(result));
    if (result.target_refined)
      support::writeFileAtomically(dir / "target_refined.csv", targetCsv(result, target.points()));
    ReportProvenance provenance{args.command_line, paths.input_files, paths.output_files};
    provenance.inputs.insert(provenance.inputs.end(), paths.input_folders.begin(), paths.input_folders.end());
    provenance.outputs.push_back({args.report_dir, "--report"});
    writeCalibrateReportJson(dir / "report.json", provenance, result, uncertainty, check);
    writeCalibrateReportHtml(dir / "report.html", provenance, result, uncertainty, check);
  }
  if (!args.save_detections.empty())
    support::writeFileAtomically(
        outputs.stageFile(args.save_detections),
        metrology::detectionsCsv(target, calibrationDetections(folder), folder.width, folder.height));
  outputs.commit();
}

// Each parameter ± 1 σ (px for the first four), then what the σ include.
void printParameters(const calibration::CalibrationResult& result) {
  const auto& p = result.camera.params;
  const auto sigma = result.camera.sigmas();
  const auto names = result.camera.parameterNames();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool pixel_unit = i < 4;
    const bool is_fixed = std::find(result.fixed_parameters.begin(), result.fixed_parameters.end(), names[i]) !=
                          result.fixed_parameters.end();
    std::cout << "  " << names[i] << " = " << fixed(p[i], pixel_unit ? 3 : 6)
              << (is_fixed ? " (fixed)" : " +- " + fixed(sigma.empty() ? 0.0 : sigma[i], pixel_unit ? 3 : 6))
              << (pixel_unit ? " px" : "") << "\n";
  }
  std::string inflated;
  for (std::size_t i = 0; i < result.sigma_inflation.size() && i < names.size(); ++i)
    if (result.sigma_inflation[i] > 1.05) inflated += " " + names[i] + " x" + fixed(result.sigma_inflation[i], 2);
  std::cout << (inflated.empty() ? std::string("sigma: pixel noise (no sign of systematic error across views)")
                                 : "sigma include systematic error (residuals correlated within views, view-cluster "
                                   "sandwich):" +
                                       inflated)
            << "\n";
}

// Residuals, projection uncertainty, target deformation, rejected views and warnings.
void printQuality(const calibration::CalibrationResult& result,
                  const calibration::ProjectionUncertaintySummary& uncertainty) {
  std::cout << "reprojection RMS " << fixed(result.camera.rms_px, 4) << " px (sigma " << fixed(result.sigma_px, 4)
            << " px); per view: ";
  for (const auto& view : result.views)
    if (view.used) std::cout << fixed(view.rms_px, 3) << " ";
  std::cout << "\n";
  const auto pixels = [](double px) {
    return std::isfinite(px) ? fixed(px, 4) + " px" : std::string("undefined (outside the model's invertible field)");
  };
  std::cout << "projection uncertainty (1 sigma, at " << fixed(result.uncertainty_distance_m * 1e3, 0)
            << " mm): centre " << pixels(uncertainty.centre_px) << ", edge " << pixels(uncertainty.edge_px)
            << ", corner " << pixels(uncertainty.corner_px) << "\n";
  if (result.target_refined)
    std::cout << "target deformation: out-of-plane RMS " << fixed(result.target_out_of_plane_rms_m * 1e3, 4)
              << " mm, max " << fixed(result.target_out_of_plane_max_m * 1e3, 4) << " mm; displacement RMS "
              << fixed(result.target_displacement_rms_m * 1e3, 4) << " mm\n";
  for (const auto& view : result.views)
    if (!view.used) std::cout << "rejected view " << view.name << ": " << view.rejection_reason << "\n";
  for (const auto& warning : result.warnings) std::cout << "warning: " << warning << "\n";
}

std::string pValue(double p) {
  if (p < 1e-12) return "p < 1e-12";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "p = %.2g", p);
  return buffer;
}

// The model check's tests with their numbers, then the verdict line (doc/calibration.md).
void printModelCheck(const calibration::ModelCheck& check) {
  const auto& structure = check.structure;
  std::cout << "model check (each test at " << fixed(100.0 * check.level, 0) << " %):\n";
  std::cout << "  residual structure: " << structure.tested_bins << " of " << structure.bins.size() << " bins tested ("
            << structure.rings << " rings x " << structure.sectors << " directions), " << structure.significant_bins
            << " significant (smallest " << pValue(structure.corrected_p_value) << " after Bonferroni); bin means "
            << fixed(structure.structured_rms_px, 4) << " px RMS\n";
  for (const auto& test : check.nested) {
    std::string terms;
    for (const auto& term : test.terms) terms += (terms.empty() ? "" : " ") + term;
    std::string held;
    for (const auto& name : test.fixed) held += (held.empty() ? "" : " ") + name;
    std::cout << "  + " << terms << " (" << test.model << (held.empty() ? "" : ", " + held + " held at 0")
              << "): likelihood ratio chi2(" << test.dof << ") = " << fixed(test.statistic, 1) << ", "
              << pValue(test.p_value) << "; RMS " << fixed(test.rms_px, 4) << " px; cx cy would move "
              << fixed(test.intrinsic_shift_sigma[2], 1) << ", " << fixed(test.intrinsic_shift_sigma[3], 1)
              << " sigma\n";
  }
  if (check.holdout) {
    const auto& h = *check.holdout;
    std::cout << "  held out (" << h.folds << " folds, " << h.views << " views, pose refitted): RMS "
              << fixed(h.measured_rms_px, 4) << " px measured, " << fixed(h.predicted_rms_px, 4) << " px predicted ("
              << fixed(h.noise_only_rms_px, 4) << " from pixel noise alone), ratio " << fixed(h.ratio, 3)
              << " (t = " << fixed(h.t_statistic, 1) << ", " << pValue(h.p_value) << ")\n";
    std::cout << "  held out: the calibration's own error is "
              << (std::isfinite(h.calibration_sigma_scale) ? fixed(h.calibration_sigma_scale, 2) + "x"
                                                           : std::string("not above pixel noise, i.e. <= 1x"))
              << " its predicted sigma; jackknife sigma / printed sigma:";
    for (std::size_t i = 0; i < h.names.size(); ++i)
      if (std::isfinite(h.jackknife_ratio[i])) std::cout << " " << h.names[i] << " " << fixed(h.jackknife_ratio[i], 2);
    std::cout << "\n";
  }
  std::cout << check.verdictLine() << "\n";
}

// Stages: checks, the views, the calibration, the outputs, then the summary.
int runCalibrate(const CalibrateArguments& args) {
  const CommandPaths paths = checkCalibratePaths(args);
  const int threads = workerThreads(args.threads, "--threads");
  if (args.holdout_folds == 1) throw UsageError("--holdout: K is 0 (no held-out check) or at least 2 folds");
  const calibration::DistortionModel model = calibration::parseDistortionModel(args.model);
  const metrology::Target target = readTarget(args.target_path);
  checkTargetSize(target, args.target_path);
  const pipeline::CalibrationFolder folder = readCalibrationViews(args, target, threads);

  calibration::CalibrationOptions options;
  options.model = model;
  options.fixed_parameters = args.fixed_parameters;
  options.refine_target = args.refine_target;
  // The solve stays on one thread (options.num_threads = 1): with more, Ceres sums the cost and
  // gradient per thread in an order that depends on the scheduling, and camera.yaml would change
  // in its last digits from run to run (calibrate.hpp). --threads parallelises the detection.
  const calibration::CalibrationResult result =
      calibration::calibrateCamera(target.points(), folder.views, folder.width, folder.height, options);
  const calibration::ProjectionUncertaintySummary uncertainty = calibration::summarizeProjectionUncertainty(result);
  std::vector<double> distances;
  for (const auto& view : result.views)
    if (view.used) distances.push_back(view.translation.norm());
  checkImpliedDistances(distances, args.target_path, "view");
  calibration::ModelCheckOptions check_options;
  check_options.holdout_folds = args.holdout_folds;
  const calibration::ModelCheck check = calibration::checkCalibrationModel(result, options, check_options);
  writeCalibrateOutputs(args, paths, target, folder, result, uncertainty, check);

  const int skipped = static_cast<int>(folder.skipped.size());
  std::cout << "calibrated from " << result.used_views << " views (" << skipped << (skipped == 1 ? " image" : " images")
            << " without the target, " << result.rejected_views << " views rejected), " << result.used_points
            << " points (" << result.rejected_points << " rejected as outliers beyond 5 sigma)\n";
  std::cout << "model " << calibration::distortionModelName(model) << (result.target_refined ? ", target refined" : "")
            << "; values +- 1 sigma (sigma^2 = SSR/(2N - " << result.free_parameter_count << "))\n";
  printParameters(result);
  printQuality(result, uncertainty);
  printModelCheck(check);
  std::cout << "wrote " << args.output_path << (args.report_dir.empty() ? "" : " and the report in " + args.report_dir)
            << "\n";
  return kOk;
}

}  // namespace

Runner addCalibrateCommand(CLI::App& app) {
  auto args = std::make_shared<CalibrateArguments>();
  CLI::App* command =
      app.add_subcommand("calibrate", "Calibrate the camera (intrinsics + distortion) from target images");
  command->add_option("--target", args->target_path, "target.yaml describing the board")->required();
  command->add_option("--images", args->images_dir, "folder of calibration images");
  command->add_option("--detections", args->detections_path,
                      "calibrate from a detections file instead of images (mire's CSV or mrcal's corners vnlog)");
  command->add_option("--image-size", args->image_size, "WIDTH HEIGHT of the images, for a detections file without it")
      ->expected(2);
  command->add_option("--save-detections", args->save_detections, "write every view's detections (CSV, doc/targets.md)");
  command
      ->add_option("--model", args->model,
                   "camera model: pinhole (no distortion), opencv4 (k1 k2 p1 p2), opencv5 (+k3), opencv8 (rational), "
                   "opencv12 (+ thin prism s1..s4), fisheye (OpenCV's equidistant k1..k4)")
      ->check(CLI::IsMember({"pinhole", "opencv4", "opencv5", "opencv8", "opencv12", "fisheye"}));
  command
      ->add_option("--fix", args->fixed_parameters,
                   "parameters held fixed, by name (e.g. k3,p1,p2; fx fy cx cy too): distortion terms stay 0, "
                   "cx cy stay at the image centre, fx fy at the initial estimate")
      ->delimiter(',');
  command->add_flag("--refine-target", args->refine_target,
                    "also estimate the target's 3D points (Lavest & Dhome) for an imperfect board");
  command->add_option("-o,--output", args->output_path, "camera.yaml to write")->required();
  command->add_option(
      "--report", args->report_dir,
      "folder for report.html, residuals.svg, residuals_per_view.svg, projection_uncertainty.svg, model_check.svg, "
      "views.csv, report.json");
  command
      ->add_option("--holdout", args->holdout_folds,
                   "K: k-fold held-out check over views (each fold calibrated without its views, which are then "
                   "predicted); 0 = none")
      ->check(CLI::Range(0, 1000));
  command->add_option("--threads", args->threads,
                      "detection threads (default: all cores); the result does not depend on them");
  return [args, command] {
    args->command_line = commandLineOf(*command);
    return runCalibrate(*args);
  };
}

}  // namespace mire::app
