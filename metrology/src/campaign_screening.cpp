#include "mire/metrology/campaign_screening.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace mire::metrology {
namespace {

using support::median;

struct Quantity {
  const char* code;
  const char* description;
  const char* unit;
  bool low_is_bad;
  std::function<double(const MeasuredPose&)> value;
};

double blockSigma(const Matrix6d& covariance, int start) {
  return std::sqrt(std::max(0.0, covariance.block<3, 3>(start, start).trace()));
}

std::vector<Quantity> quantities() {
  return {
      {"rms_high", "reprojection rms", "px", false, [](const MeasuredPose& p) { return p.estimate.rms_px; }},
      {"few_images", "images used", "", true, [](const MeasuredPose& p) { return double(p.images_used); }},
      {"sigma_t_high", "translation sigma", "mm", false,
       [](const MeasuredPose& p) { return 1e3 * blockSigma(p.estimate.covariance_noise, 0); }},
      {"sigma_r_high", "rotation sigma", "deg", false,
       [](const MeasuredPose& p) { return 180.0 / support::kPi * blockSigma(p.estimate.covariance_noise, 3); }},
  };
}

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

// Screens one quantity over the campaign; appends codes and reasons.
void screenQuantity(const Quantity& quantity, const ScreeningOptions& options, std::vector<MeasuredPose>* poses,
                    ScreeningResult* result) {
  std::vector<double> logs;
  for (const MeasuredPose& pose : *poses) logs.push_back(std::log(std::max(quantity.value(pose), 1e-300)));
  const double centre = median(logs);
  const double scale = support::madSigma(logs);
  const double limit = std::max(options.k * scale, std::log(options.min_ratio));
  for (std::size_t i = 0; i < poses->size(); ++i) {
    const double z = (logs[i] - centre) * (quantity.low_is_bad ? -1.0 : 1.0);
    if (!(z > limit)) continue;
    const double ratio = std::exp(z);
    (*poses)[i].flags.push_back(std::string(quantity.code) + ":" + format("%.3gx", ratio));
    result->reasons[i].push_back(
        std::string(quantity.description) + " " + format("%.4g", quantity.value((*poses)[i])) + " " + quantity.unit +
        " is " + format("%.3g", ratio) + (quantity.low_is_bad ? "x below" : "x above") + " the campaign median " +
        format("%.4g", std::exp(centre)) + " " + quantity.unit + " (limit: factor " + format("%.3g", std::exp(limit)) +
        ", max(" + format("%g", options.k) + " x 1.4826 MAD, ln " + format("%g", options.min_ratio) + ") on log scale)");
  }
}

}  // namespace

ScreeningResult screenCampaign(std::vector<MeasuredPose>* poses, const ScreeningOptions& options) {
  ScreeningResult result;
  result.reasons.resize(poses->size());
  if (static_cast<int>(poses->size()) < options.min_poses) return result;
  result.applied = true;
  for (const Quantity& quantity : quantities()) screenQuantity(quantity, options, poses, &result);
  return result;
}

std::vector<std::string> measurementFlags(const PoseMeasurement& measurement) {
  std::vector<std::string> flags;
  const auto& duplicates = measurement.integrity.duplicate_of;
  const auto copies = std::count_if(duplicates.begin(), duplicates.end(), [](int d) { return d >= 0; });
  if (copies > 0) flags.push_back("duplicates:" + std::to_string(copies));
  if (!measurement.integrity.moved.empty() && measurement.integrity.consistent)
    flags.push_back("moved_left_out:" + std::to_string(measurement.integrity.moved.size()));
  if (measurement.estimate.scatter_from_residuals) flags.emplace_back("sigma_from_residuals");
  return flags;
}

}  // namespace mire::metrology
