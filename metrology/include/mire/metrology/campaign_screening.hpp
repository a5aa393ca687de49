#pragma once
// Campaign-level screening of measured poses (doc/measurement.md, "Imperfect campaigns"): a pose whose
// reprojection RMS, image count or σ stands far from the rest of its campaign (a blurred or
// downscaled pose, a folder with a few images left) is flagged, with the reason.
//
// Rule, per quantity q (rms_px, σ_t, σ_r: high is bad; images_used: low is bad), on log scale
// over the campaign's measured poses:
//   z = ln q − median(ln q),  s = 1.4826 · MAD(ln q),
//   flagged when z (or −z for images_used) > max(k · s, ln min_ratio),
// i.e. more than k robust σ AND more than a factor min_ratio from the campaign's median.
// σ_t = √tr(translation block), σ_r = √tr(rotation block) of the features' covariance
// (covariance_noise: pixel noise × max(1, reduced χ²)); the intrinsics part, common to all
// poses, is left out. Needs at least min_poses poses.
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"

#include <string>
#include <vector>

namespace mire::metrology {

struct ScreeningOptions {
  double k = 5.0;
  double min_ratio = 2.0;
  int min_poses = 5;
};

struct ScreeningResult {
  bool applied = false;                           // false: fewer than min_poses poses
  std::vector<std::vector<std::string>> reasons;  // per pose, human-readable (empty: not flagged)
};

// Appends flag codes (e.g. "rms_high:10.2x") to each pose's `flags` and returns the reasons.
ScreeningResult screenCampaign(std::vector<MeasuredPose>* poses, const ScreeningOptions& options = {});

// Flag codes of one measurement: "duplicates:N" (identical frames counted once),
// "moved_left_out:N" (split kept the largest consistent group), "sigma_from_residuals" (one
// image or zero scatter: σ from the fit residuals).
std::vector<std::string> measurementFlags(const PoseMeasurement& measurement);

}  // namespace mire::metrology
