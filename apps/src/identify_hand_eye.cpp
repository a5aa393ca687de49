// `mire identify --robot-poses`: see identify_hand_eye.hpp. Everything is computed before
// anything is written; the parameters and their covariance side file land together.
#include "identify_hand_eye.hpp"

#include "output_paths.hpp"
#include "validate.hpp"

#include "mire/mechanism/hand_eye.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;
using support::kDegreesPerRadian;

// A median camera residual above these (5 mm, 1 deg) means a wrong chain, not noise.
constexpr double kImplausibleResidualM = 0.005;
constexpr double kImplausibleResidualRad = 1.0 / kDegreesPerRadian;

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// --robot-sigma T_MM,R_DEG.
std::optional<mech::RobotPoseSigma> parseRobotSigma(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const auto comma = text.find(',');
  double t_mm = 0.0, r_deg = 0.0;
  try {
    if (comma == std::string::npos) throw std::invalid_argument("comma");
    std::size_t used_t = 0, used_r = 0;
    const std::string t = text.substr(0, comma), r = text.substr(comma + 1);
    t_mm = std::stod(t, &used_t);
    r_deg = std::stod(r, &used_r);
    if (used_t != t.size() || used_r != r.size()) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    throw UsageError("--robot-sigma '" + text + "': expected T_MM,R_DEG, e.g. 0.1,0.01");
  }
  if (!(t_mm > 0.0) || !(r_deg > 0.0) || !std::isfinite(t_mm) || !std::isfinite(r_deg))
    throw UsageError("--robot-sigma '" + text + "': both sigma must be finite and > 0");
  return mech::RobotPoseSigma{t_mm * 1e-3, r_deg / kDegreesPerRadian};
}

struct HandEyeInputs {
  std::vector<mech::HandEyeObservation> poses;
  std::vector<std::string> unused_robot_ids;
  std::optional<fs::path> covariance_path;
};

// Pairs each measured pose with the robot's pose of the same id.
HandEyeInputs readInputs(const HandEyeIdentifyArguments& args, const std::optional<mech::RobotPoseSigma>& sigma) {
  HandEyeInputs inputs;
  const std::vector<mech::RobotPoseRow> robot = mech::readRobotPosesCsv(args.robot_poses);
  inputs.covariance_path = args.covariances.empty() ? std::optional<fs::path>() : fs::path(args.covariances);
  const fs::path beside = support::covarianceSidePath(args.poses);
  if (!inputs.covariance_path && fs::exists(beside)) inputs.covariance_path = beside;
  const std::vector<mech::PoseRow> camera = mech::readPosesCsv(args.poses, inputs.covariance_path);
  std::map<std::string, const mech::RobotPoseRow*> by_id;
  for (const mech::RobotPoseRow& row : robot) by_id[row.id] = &row;
  std::map<std::string, bool> used;
  for (const mech::PoseRow& row : camera) {
    const auto it = by_id.find(row.observation.id);
    if (it == by_id.end())
      throw std::runtime_error(args.poses + ":" + std::to_string(row.line) + ": pose '" + row.observation.id +
                               "' has no row in " + args.robot_poses);
    const mech::RobotPoseRow& r = *it->second;
    if (!r.sigma && !sigma)
      throw UsageError(args.robot_poses + ":" + std::to_string(r.line) +
                       ": no sigma_t_mm,sigma_r_deg for this pose: give those columns or --robot-sigma T_MM,R_DEG");
    mech::HandEyeObservation o;
    o.id = row.observation.id;
    o.bTe = r.bTe;
    o.robot_sigma = r.sigma ? *r.sigma : *sigma;
    o.cTm = row.observation.cTm;
    o.cTm_covariance = row.observation.covariance;
    inputs.poses.push_back(o);
    used[o.id] = true;
  }
  for (const mech::RobotPoseRow& row : robot)
    if (!used.count(row.id)) inputs.unused_robot_ids.push_back(row.id);
  return inputs;
}

std::string fixed(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

std::string padded(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : text + std::string(width - text.size(), ' ');
}

// The human report (mm, deg).
std::string reportText(const HandEyeIdentifyArguments& args, const HandEyeInputs& inputs,
                       const mech::HandEyeResult& result) {
  std::ostringstream out;
  const bool on_effector = result.mounting == mech::HandEyeMounting::CameraOnEffector;
  out << "hand-eye (" << mech::handEyeMountingName(result.mounting) << ", "
      << (on_effector ? "AX = XB: eTc and bTm" : "AX = ZB: cTb and eTm") << "): " << result.poses.size() << " poses";
  if (!inputs.unused_robot_ids.empty())
    out << "; " << inputs.unused_robot_ids.size() << " robot poses without a measured pose (ignored)";
  out << "\n";
  out << "camera pose errors: "
      << (result.sigma_from_residuals ? "no covariance in " + args.poses + ": weighted like the robot's"
                                      : "weighted by their covariances (" + inputs.covariance_path->string() + ")")
      << "; robot pose errors: nuisance poses with the robot's sigma\n";
  out << "robot rotations (RMS over pairs, principal axes): "
      << fixed("%.2f", result.rotation_spread[0] * kDegreesPerRadian) << ", "
      << fixed("%.2f", result.rotation_spread[1] * kDegreesPerRadian) << ", "
      << fixed("%.2f", result.rotation_spread[2] * kDegreesPerRadian) << " deg\n";
  out << "fit: chi2/dof " << fixed("%.3g", result.dof > 0 ? result.chi2 / result.dof : 0.0) << " (" << result.dof
      << " dof)";
  if (result.sigma_from_residuals)
    out << ": sigma scaled by the residuals (x " << fixed("%.3g", std::sqrt(result.scale2)) << ")";
  else if (result.scale2 != 1.0)
    out << ": misfit, the stated sigma understate the scatter: sigma scaled x "
        << fixed("%.3g", std::sqrt(result.scale2));
  else
    out << ", consistent with the stated sigma";
  out << "; condition number " << fixed("%.4g", result.identifiability.condition_number) << "; start: OpenCV "
      << result.closed_form_method << (result.converged ? "" : "; warning: the solver did not report convergence")
      << "\n";
  // A camera residual of many millimetres or degrees is no measurement error: the chain is wrong.
  std::vector<double> camera_t, camera_r;
  for (const auto& score : result.poses) {
    camera_t.push_back(score.camera_t_m.norm());
    camera_r.push_back(score.camera_r_rad);
  }
  const double median_t = median(camera_t), median_r = median(camera_r);
  if (median_t > kImplausibleResidualM || median_r > kImplausibleResidualRad)
    out << "warning: the median camera residual is " << fixed("%.1f", median_t * 1e3) << " mm, "
        << fixed("%.2f", median_r * kDegreesPerRadian)
        << " deg: far beyond a pose measurement's error; is the mounting right (--mounting "
        << (on_effector ? "camera-fixed" : "camera-on-effector") << "?), and are both files in the same units?\n";
  for (const auto& outlier : result.outliers)
    out << "outlier pose removed: " << outlier.id << " (chi2 " << fixed("%.1f", outlier.chi2) << " of 6 dof; camera "
        << fixed("%.3f", outlier.camera_t_m.norm() * 1e3) << " mm, "
        << fixed("%.3f", outlier.camera_r_rad * kDegreesPerRadian) << " deg off)\n";
  out << "parameter  unit    value          sigma\n";
  for (std::size_t k = 0; k < result.parameters.size(); ++k) {
    const mech::Parameter& p = result.parameters[k];
    const double scale = p.unit == mech::Unit::Metre ? 1e3 : kDegreesPerRadian;
    out << padded(p.name, 9) << "  " << (p.unit == mech::Unit::Metre ? "mm " : "deg") << " "
        << fixed("%14.4f", p.value * scale) << " "
        << fixed("%10.4f", result.sigma[static_cast<Eigen::Index>(k)] * scale) << "\n";
  }
  const Eigen::Isometry3d change = result.X_closed_form.inverse() * result.X;
  out << (on_effector ? "eTc" : "cTb") << " moved from OpenCV's " << result.closed_form_method << " by "
      << fixed("%.4f", change.translation().norm() * 1e3) << " mm, "
      << fixed("%.4f", Eigen::AngleAxisd(change.linear()).angle() * kDegreesPerRadian) << " deg\n";
  out << "pose  chi2   camera mm  camera deg  robot mm  robot deg\n";
  for (const auto& s : result.poses)
    out << padded(s.id, 5) << " " << fixed("%5.2f", s.chi2) << " " << fixed("%10.4f", s.camera_t_m.norm() * 1e3) << " "
        << fixed("%11.4f", s.camera_r_rad * kDegreesPerRadian) << " " << fixed("%9.4f", s.robot_t_m.norm() * 1e3) << " "
        << fixed("%10.4f", s.robot_r_rad * kDegreesPerRadian) << "\n";
  return out.str();
}

void writeOutputs(const HandEyeIdentifyArguments& args, const mech::HandEyeResult& result, const std::string& report) {
  mech::PredictionModel covariance;
  covariance.model_name = "hand-eye";
  covariance.geometric = result.parameters;
  covariance.covariance_names = result.parameters.names();
  covariance.covariance = result.covariance;
  const std::vector<std::pair<std::string, std::string>> metadata{
      {"model", "hand-eye"},
      {"mounting", mech::handEyeMountingName(result.mounting)},
      {"poses", std::to_string(result.poses.size())},
      {"outliers", std::to_string(result.outliers.size())},
      {"chi2_per_dof", fixed("%.6g", result.dof > 0 ? result.chi2 / result.dof : 0.0)},
      {"created_by", "mire identify --robot-poses"}};
  const fs::path covariance_output = support::covarianceSidePath(args.output);
  support::OutputTransaction outputs;
  mech::writePredictionCovarianceCsv(outputs.stageFile(covariance_output), covariance);
  mech::writeParameterFile(outputs.stageFile(args.output), result.parameters, result.sigma, metadata,
                           "Hand-eye calibration by mire identify from " + args.robot_poses + " and " + args.poses +
                               "\nrotations: rotation vectors (rad); sigma_<name>: standard deviation (same unit)");
  outputs.commit();
  std::cout << report << "wrote " << args.output << ", " << covariance_output.string()
            << " (full covariance of the 12 values)\n";
}

}  // namespace

int runHandEyeIdentify(const HandEyeIdentifyArguments& args) {
  if (args.mounting.empty())
    throw UsageError("--robot-poses needs --mounting camera-on-effector or --mounting camera-fixed");
  mech::HandEyeMounting mounting;
  try {
    mounting = mech::parseHandEyeMounting(args.mounting);
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--mounting: ") + error.what());
  }
  const std::optional<mech::RobotPoseSigma> sigma = parseRobotSigma(args.robot_sigma);
  CommandPaths paths;
  paths.input_files = {{args.robot_poses, "--robot-poses"}, {args.poses, "--poses"}};
  if (!args.covariances.empty()) paths.input_files.push_back({args.covariances, "--pose-covariances"});
  paths.output_files = {{args.output, "-o"},
                        {support::covarianceSidePath(args.output), "the covariance side file of -o"}};
  checkCommandPaths(paths);
  const HandEyeInputs inputs = readInputs(args, sigma);
  mech::HandEyeResult result;
  try {
    result = mech::solveHandEye(inputs.poses, mounting);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.poses + " and " + args.robot_poses + ": " + error.what());
  }
  writeOutputs(args, result, reportText(args, inputs, result));
  return 0;
}

}  // namespace mire::app
