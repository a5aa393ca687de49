#pragma once
// `mire demo --mechanism gough-stewart|delta --legs` (doc/demo-mechanisms.md, "The legs"): the campaign
// rendered with the legs as rods, and the robot identified from its legs only, its target only and
// both (pipeline::identifyWithLegs), against the truth, with V3 and the positioning test before and
// after identification.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/pipeline/pose_set.hpp"

namespace mire::app {

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
  std::string legs;   // where the leg lines come from (measured, or simulated: said so)
  std::size_t leg_lines = 0;
  std::vector<LegsDemoRow> rows;
};

// Until the legs are measured in the images: the campaign's truth/legs.csv with errors drawn from
// the representative leg-line covariance of doc/legs.md ("Precision and tests"), written to `out`
// as legs.csv. Labelled as simulated wherever it is used.
void writeSimulatedLegLines(const datasets::MechanismImageCampaign& campaign, std::uint64_t seed,
                            const std::filesystem::path& out);

// The three identifications of the campaign's truth-kind model with leg observations from
// `legs_csv` (read as legs.csv), `legs_source` saying where they came from.
LegsDemoSection runLegsDemo(const datasets::MechanismImageCampaign& campaign, const pipeline::PoseSet& data,
                            const std::filesystem::path& legs_csv, const std::string& legs_source);

// The section as markdown (a table), and as the demo's summary lines.
std::string legsDemoMarkdown(const LegsDemoSection& section);
std::string legsDemoSummary(const LegsDemoSection& section);

}  // namespace mire::app
