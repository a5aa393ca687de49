// `mire measure --legs` (measure_legs.hpp).
#include "measure_legs.hpp"

#include "commands.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/leg_measurement.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/statistics.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

// Median σ across and along the line of sight: the smaller and larger of the two b components'
// σ, and of the two a components' σ (doc/legs.md: depth comes from the apparent width).
void printSummary(const std::vector<mechanism::LegObservation>& legs, const std::vector<double>& spread_ratios) {
  std::vector<double> a_small, a_large, b_small, b_large;
  for (const mechanism::LegObservation& leg : legs) {
    const Eigen::Vector4d sigma = leg.covariance.diagonal().cwiseSqrt();
    a_small.push_back(std::min(sigma[0], sigma[1]) * 1e3);
    a_large.push_back(std::max(sigma[0], sigma[1]) * 1e3);
    b_small.push_back(std::min(sigma[2], sigma[3]) * 1e3);
    b_large.push_back(std::max(sigma[2], sigma[3]) * 1e3);
  }
  std::printf("median leg sigma: direction %.4f / %.4f mrad, position %.4f / %.4f mm (smaller / larger component)\n",
              support::median(a_small), support::median(a_large), support::median(b_small), support::median(b_large));
  std::printf("median spread of the images against the per-image fits (1 = as predicted): %.3f\n",
              support::median(spread_ratios));
}

}  // namespace

int runLegMeasure(const LegMeasureArguments& args) {
  CommandPaths paths{{{args.camera, "--camera"}, {args.legs, "--legs"}, {args.joints, "--joints"}},
                     {{args.poses, "--poses"}},
                     {{args.output, "-o"}},
                     {}};
  if (!args.save_contours.empty()) paths.output_folders.push_back({args.save_contours, "--save-leg-contours"});
  checkCommandPaths(paths);
  const int threads = workerThreads(args.threads, "--threads");
  const calibration::Camera camera = calibration::readCamera(args.camera);
  checkCamera(camera, args.camera);
  const pipeline::LegsSpec spec = pipeline::readLegsYaml(args.legs);
  const mechanism::RegisteredModel model = pipeline::chooseModel(spec.model, "").registered();
  const auto joints = mechanism::readJointsCsv(args.joints, model.mechanism->jointColumnNames());
  if (!args.save_contours.empty()) fs::create_directories(args.save_contours);
  const std::vector<pipeline::PoseLegs> poses =
      pipeline::measureLegFolders(camera, spec, joints, args.poses, threads, args.save_contours);

  std::vector<mechanism::LegObservation> legs;
  std::vector<double> spread_ratios;
  int incomplete = 0;
  for (const pipeline::PoseLegs& pose : poses) {
    for (const std::string& problem : pose.problems)
      std::cerr << "mire measure: pose " << pose.pose_id << ": " << problem << "\n";
    incomplete += pose.problems.empty() ? 0 : 1;
    legs.insert(legs.end(), pose.legs.begin(), pose.legs.end());
    spread_ratios.insert(spread_ratios.end(), pose.spread_ratios.begin(), pose.spread_ratios.end());
  }
  if (legs.empty()) {
    std::cerr << "mire measure: error: no leg could be measured in " << args.poses << "; nothing written\n";
    return kFailure;
  }
  mechanism::writeLegsCsv(args.output, legs);
  printSummary(legs, spread_ratios);
  std::printf("measured %zu legs at %zu poses (%s, %d legs each) -> %s\n", legs.size(), poses.size(),
              spec.model.c_str(), model.mechanism->legCount(), args.output.c_str());
  if (incomplete > 0) {
    std::cerr << "mire measure: " << incomplete
              << " pose(s) with legs not measured (listed above); the others were written\n";
    return kPartialFailure;
  }
  return kOk;
}

}  // namespace mire::app
