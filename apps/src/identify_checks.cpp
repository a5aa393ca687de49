#include "identify_checks.hpp"

#include "validate.hpp"

#include <cmath>
#include <cstdio>

namespace mire::app {

void checkIdentifyPoses(const std::vector<mechanism::PoseObservation>& poses, const std::filesystem::path& poses_file,
                        bool unweighted) {
  if (poses.size() > kMaxPoses)
    throw std::runtime_error(poses_file.string() + ": " + std::to_string(poses.size()) +
                             " poses; identify handles at most " + std::to_string(kMaxPoses));
  constexpr double kTwoPi = 6.283185307179586;
  std::size_t with_covariance = 0;
  const mechanism::PoseObservation* without = nullptr;
  for (const auto& pose : poses) {
    const double angle = pose.cTm.tail<3>().norm();
    // The same rotation as a vector of norm angle - 2π·k, but its covariance (given for the
    // written vector) would not describe it: refuse rather than weight it wrongly.
    if (angle > kTwoPi)
      throw std::runtime_error(poses_file.string() + ": pose " + pose.id + ": rotation vector of norm " +
                               std::to_string(angle) + " rad > 2π (write the equivalent vector of norm <= π)");
    if (pose.covariance)
      ++with_covariance;
    else if (!without)
      without = &pose;
  }
  if (!unweighted && with_covariance > 0 && without)
    throw std::runtime_error(
        poses_file.string() + ": pose " + without->id + " has no usable covariance (a sigma is 0 or missing) while " +
        std::to_string(with_covariance) + " poses have one: fix it, or pass --unweighted to ignore every covariance");
}

void checkPriorSigma(const std::string& text, double sigma) {
  if (sigma < 1e-9)
    throw UsageError("--prior '" + text + "': sigma below 1e-9 (SI) would freeze the parameter; use --fix to hold it");
}

std::vector<int> parseSubsetSizes(const std::vector<std::string>& texts, int joints, std::size_t free_parameters,
                                  std::size_t pose_count) {
  // Split here, not by CLI11 (which drops empty items: "6,,15" must be an error).
  std::vector<std::string> items;
  for (const auto& text : texts) {
    std::size_t start = 0;
    for (std::size_t comma = text.find(',');; comma = text.find(',', start)) {
      items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  std::vector<int> sizes;
  for (const auto& text : items) {
    std::size_t used = 0;
    long value = 0;
    try {
      value = std::stol(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (text.empty() || used != text.size() || value < 1)
      throw UsageError("--mc '" + text + "': expected positive subset sizes like 6,15,71");
    if (static_cast<std::size_t>(value) * static_cast<std::size_t>(joints) <= free_parameters)
      throw UsageError("--mc " + text + ": a subset of " + text + " poses gives " + std::to_string(value * joints) +
                       " equations for " + std::to_string(free_parameters) + " free parameters; use a larger size");
    if (static_cast<std::size_t>(value) >= pose_count)
      throw UsageError("--mc " + text + ": subsets must be smaller than the " + std::to_string(pose_count) +
                       " poses (the other poses validate)");
    sizes.push_back(static_cast<int>(value));
  }
  return sizes;
}

}  // namespace mire::app
