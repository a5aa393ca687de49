// Gauge and minimal identifiable set from the data (doc/mechanisms.md).
#include "mire/mechanism/gauge.hpp"

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mire::mechanism {

std::vector<PoseObservation> modelConsistentPoses(const IdentificationModel& model,
                                                  const std::vector<PoseObservation>& poses) {
  const Mechanism& mechanism = *model.mechanism;
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  const std::vector<Eigen::Isometry3d> bTe = effectorPosesByFkm(mechanism, g, poses);
  std::vector<PoseObservation> out = poses;
  for (std::size_t j = 0; j < out.size(); ++j) {
    out[j].cTm = toPoseVector(model.external.targetInCamera(e, bTe[j]));
    out[j].covariance.reset();
  }
  return out;
}

namespace {
// Pivot priorities (IdentifiabilityOptions::pivot_priority): geometric 1, mounting 0.5, the full
// form's camera placement cTb 0.25 — held first among equivalent parameters.
constexpr double kMountingPivotPriority = 0.5;
constexpr double kCameraPivotPriority = 0.25;
}  // namespace

GaugeAnalysis analyzeGauge(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                           const IdentifiabilityOptions& options) {
  GaugeAnalysis analysis;
  // Between equivalent parameters, hold the mounting ones: the geometry is what the user
  // calibrates, and a gauge chosen by rounding moved from chain to chain (doc/uncertainty.md,
  // "The base offset on a few Delta chains"). Among the mounting values, cTb (the full form's
  // first six) before eTm: the `delta` model's gauge is then cTb's translation
  // (doc/mechanisms.md), which rounding swapped for eTm's on 10 of 120 rendered chains, with cTb
  // then 40–150 mm (13–45σ) from the truth.
  IdentifiabilityOptions prefer_geometry = options;
  const int G = model.geometricCount();
  // With the camera on the effector, eTc (the first six) is the camera placement.
  const bool full =
      model.external.form() == ExternalForm::Full || model.external.form() == ExternalForm::CameraOnEffector;
  if (prefer_geometry.pivot_priority.empty())
    for (const std::size_t i : model.parameters.freeIndices()) {
      const int k = static_cast<int>(i);
      prefer_geometry.pivot_priority.push_back(k < G               ? 1.0
                                               : full && k < G + 6 ? kCameraPivotPriority
                                                                   : kMountingPivotPriority);
    }
  analysis.report = analyzeIdentifiability(model, modelConsistentPoses(model, poses), prefer_geometry);
  const IdentifiabilityReport& r = analysis.report;
  std::set<std::string> dependents(r.unidentifiable.begin(), r.unidentifiable.end()), members;
  for (const UnidentifiableCombination& c : r.combinations)
    for (const auto& [name, coefficient] : c.direction) members.insert(name);
  const double largest = r.column_norms.size() ? r.column_norms.maxCoeff() : 0.0;
  for (std::size_t k = 0; k < r.parameter_names.size(); ++k) {
    const std::string& name = r.parameter_names[k];
    if (dependents.count(name)) {
      analysis.gauge.push_back(name);
      if (!(r.column_norms[static_cast<Eigen::Index>(k)] > 1e-9 * largest)) analysis.no_influence.push_back(name);
    } else if (members.count(name)) {
      analysis.combination_only.push_back(name);
    } else {
      analysis.identified.push_back(name);
    }
  }
  return analysis;
}

GaugeAnalysis fixGauge(IdentificationModel& model, const std::vector<PoseObservation>& poses,
                       const IdentifiabilityOptions& options) {
  GaugeAnalysis analysis = analyzeGauge(model, poses, options);
  model.parameters.fix(analysis.gauge);
  return analysis;
}

std::string GaugeAnalysis::text() const {
  std::ostringstream out;
  const auto list = [&out](const char* label, const std::vector<std::string>& names) {
    out << label << " (" << names.size() << "):";
    for (const std::string& n : names) out << " " << n;
    out << "\n";
  };
  out << "identifiability on model-consistent poses: rank " << report.rank << " of " << report.parameter_names.size()
      << " free parameters\n";
  list("  identified", identified);
  list("  combination-only", combination_only);
  list("  gauge (held at their current value)", gauge);
  if (!no_influence.empty()) list("  of which without any influence", no_influence);
  for (const UnidentifiableCombination& c : report.combinations) out << "  " << c.text() << "\n";
  return out.str();
}

}  // namespace mire::mechanism
