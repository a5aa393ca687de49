#pragma once
// `mire demo --mechanism gough-stewart|delta --legs` (doc/demo-mechanisms.md, "The legs"): the campaign
// rendered with the legs as rods, and the robot identified from its legs only, its target only and
// both (identifyWithLegs), against the truth, with V3 and the positioning test before and
// after identification.
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"

namespace mire::pipeline {

struct LegsDemoRow {
  std::string observations;  // target, legs, both
  std::string error;         // why it did not run (then nothing else is set)
  int free_parameters = 0;
  double chi2_per_dof = 0.0;
  // The legs' lengths against the truth (hexapod rho01..rho06; Delta L and l against the mean of
  // the true robot's per-leg values): largest |error| [mm] and RMS of error/σ.
  double length_error_max_mm = 0.0, length_error_over_sigma_rms = 0.0;
  double v3_before_mm = 0.0, v3_after_mm = 0.0;
  double square_side_mm = 0.0, square_rms_before_mm = 0.0, square_rms_after_mm = 0.0;
};

struct LegsDemoSection {
  std::string model;  // gough-stewart, delta
  std::string legs;   // where the leg lines come from
  std::size_t leg_lines = 0;
  std::vector<std::string> unmeasured;  // per pose with a leg not measured: why
  std::vector<LegsDemoRow> rows;
};

// The demo's legs stage: the legs measured in the campaign's pose images through the calibrated
// camera as `mire measure --legs` does (`output`/legs.csv), then the campaign's truth-kind model
// identified from the legs only, the target only (`output`/poses.csv) and both, scored against the
// truth; the section is also written to `output`/legs.md.
LegsDemoSection legsDemoStage(const datasets::MechanismImageCampaign& campaign, const calibration::Camera& camera,
                              const std::filesystem::path& output);

// The section as markdown (a table), and as the demo's summary lines.
std::string legsDemoMarkdown(const LegsDemoSection& section);
std::string legsDemoSummary(const LegsDemoSection& section);

}  // namespace mire::pipeline
