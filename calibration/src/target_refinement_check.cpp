// A target refinement (Lavest & Dhome) compared with the rigid-target calibration of the same
// views: the rule and its warnings are stated in doc/calibration.md, "Weakly determined target
// refinement".
#include "mire/calibration/calibrate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mire::calibration {
namespace {

// Above these the warnings fire (doc/calibration.md).
constexpr double kShiftSigmas = 3.0;        // intrinsic moved by more than 3 combined σ
constexpr double kUncertaintyGrowth = 3.0;  // projection uncertainty or parameter σ grown 3×
constexpr int kPixelParameters = 4;         // fx fy cx cy

std::string number(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

// √diag of the pixel-noise covariance over the pixel σ: the parameter's σ per pixel of noise.
std::vector<double> unitSigmas(const CalibrationResult& result) {
  std::vector<double> sigmas(result.camera.params.size(), 0.0);
  const Eigen::MatrixXd& covariance = result.covariance_pixel_noise;
  for (std::size_t i = 0; i < sigmas.size() && static_cast<Eigen::Index>(i) < covariance.rows(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    sigmas[i] = result.sigma_px > 0.0 ? std::sqrt(std::max(0.0, covariance(k, k))) / result.sigma_px : 0.0;
  }
  return sigmas;
}

double ratio(double refined, double rigid) {
  return std::isfinite(refined) && std::isfinite(rigid) && rigid > 0.0 ? refined / rigid : 0.0;
}

void compareParameters(const CalibrationResult& rigid, const CalibrationResult& refined, TargetRefinementCheck* check) {
  check->rigid_params = rigid.camera.params;
  check->rigid_sigmas = rigid.camera.sigmas();
  const std::vector<double> rigid_unit = unitSigmas(rigid), refined_unit = unitSigmas(refined);
  const std::size_t count = refined.camera.params.size();
  check->shift_sigmas.assign(count, 0.0);
  check->information_loss.assign(count, 0.0);
  const std::vector<double> refined_sigmas = refined.camera.sigmas();
  for (std::size_t i = 0; i < count && i < check->rigid_sigmas.size() && i < refined_sigmas.size(); ++i) {
    // Both σ: the difference of two estimates from the same data is not as uncertain as their
    // sum (nested fits are correlated), so this is the lenient yardstick.
    const double sigma = std::hypot(check->rigid_sigmas[i], refined_sigmas[i]);
    if (sigma > 0.0) check->shift_sigmas[i] = (refined.camera.params[i] - rigid.camera.params[i]) / sigma;
    check->information_loss[i] = ratio(refined_unit[i], rigid_unit[i]);
    if (i < kPixelParameters)
      check->largest_intrinsic_shift_sigma =
          std::max(check->largest_intrinsic_shift_sigma, std::abs(check->shift_sigmas[i]));
  }
}

// "the corner from 19.67 to 761.19 px (x38.7)" for each place that grew beyond the rule.
std::string uncertaintyGrowthText(const TargetRefinementCheck& check) {
  const std::pair<const char*, std::pair<double, double>> places[] = {
      {"centre", {check.rigid_uncertainty.centre_px, check.refined_uncertainty.centre_px}},
      {"edge", {check.rigid_uncertainty.edge_px, check.refined_uncertainty.edge_px}},
      {"corner", {check.rigid_uncertainty.corner_px, check.refined_uncertainty.corner_px}}};
  std::string text;
  for (const auto& [name, values] : places) {
    const double growth = ratio(values.second, values.first);
    if (growth <= kUncertaintyGrowth) continue;
    text += std::string(text.empty() ? "" : ", ") + "at the " + name + " from " + number(values.first, 2) + " to " +
            number(values.second, 2) + " px (x" + number(growth, 1) + ")";
  }
  return text;
}

std::string informationLossText(const TargetRefinementCheck& check, const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < check.information_loss.size() && i < names.size(); ++i)
    if (check.information_loss[i] > kUncertaintyGrowth)
      text += std::string(text.empty() ? "" : ", ") + names[i] + " x" + number(check.information_loss[i], 1);
  return text;
}

std::string weakRefinementWarning(const TargetRefinementCheck& check, const std::vector<std::string>& names) {
  const std::string growth = uncertaintyGrowthText(check), loss = informationLossText(check, names);
  std::string text = "--refine-target is weakly determined by these views: its " +
                     std::to_string(check.added_unknowns) + " extra unknowns (the board's points) raise ";
  if (!growth.empty()) text += "the projection uncertainty " + growth;
  if (!growth.empty() && !loss.empty()) text += " and ";
  if (!loss.empty()) text += "the sigma of " + loss + " at equal pixel noise";
  return text +
         " against the rigid-target calibration of the same views; keep the rigid target (no --refine-target), "
         "or add views that pin the board down (tilted 30-45 deg, target in the image corners) and refine again";
}

std::string shiftWarning(const TargetRefinementCheck& check, const CalibrationResult& refined,
                         const std::vector<std::string>& names) {
  std::string moved;
  for (int i = 0; i < kPixelParameters; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (std::abs(check.shift_sigmas[k]) <= kShiftSigmas) continue;
    moved += std::string(moved.empty() ? "" : ", ") + names[k] + " " + number(check.rigid_params[k], 3) + " -> " +
             number(refined.camera.params[k], 3) + " px (" + number(check.shift_sigmas[k], 1) + " sigma)";
  }
  return "--refine-target moved " + moved +
         " against the rigid-target calibration, in the two calibrations' combined sigma: a board that is not flat "
         "does this, and so does a refinement "
         "that trades the board's points against the intrinsics; before trusting either, compare the held-out "
         "error of both (--holdout) or calibrate from more views";
}

}  // namespace

TargetRefinementCheck checkTargetRefinement(const CalibrationResult& rigid, CalibrationResult* refined) {
  TargetRefinementCheck check;
  check.added_unknowns = refined->free_parameter_count - rigid.free_parameter_count;
  compareParameters(rigid, *refined, &check);
  check.rigid_uncertainty = summarizeProjectionUncertainty(rigid);
  check.refined_uncertainty = summarizeProjectionUncertainty(*refined);
  check.largest_uncertainty_ratio =
      std::max({ratio(check.refined_uncertainty.centre_px, check.rigid_uncertainty.centre_px),
                ratio(check.refined_uncertainty.edge_px, check.rigid_uncertainty.edge_px),
                ratio(check.refined_uncertainty.corner_px, check.rigid_uncertainty.corner_px)});
  const double largest_loss = check.information_loss.empty()
                                  ? 0.0
                                  : *std::max_element(check.information_loss.begin(), check.information_loss.end());
  check.weakly_determined = check.largest_uncertainty_ratio > kUncertaintyGrowth || largest_loss > kUncertaintyGrowth;
  const std::vector<std::string> names = refined->camera.parameterNames();
  if (check.weakly_determined) refined->warnings.push_back(weakRefinementWarning(check, names));
  if (check.largest_intrinsic_shift_sigma > kShiftSigmas)
    refined->warnings.push_back(shiftWarning(check, *refined, names));
  return check;
}

}  // namespace mire::calibration
