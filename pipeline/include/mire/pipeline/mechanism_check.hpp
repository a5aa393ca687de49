#pragma once
// `mire check-mechanism` (doc/mechanisms.md, "Checking a description"): what is wrong with a
// mechanism before a campaign is recorded: a home pose that does not assemble, a leg whose
// branch has no solution there, a home on or near a singularity, protocol poses out of reach;
// and what a campaign on it can identify: the parameter count, the expected rank and the gauge,
// from the identifiability analysis of a noise-free campaign at the nominal geometry over the
// protocol poses (no list of
// gauges is written anywhere: the analysis finds them).
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/gauge.hpp"
#include "mire/pipeline/identify.hpp"

namespace mire::pipeline {

struct MechanismCheckOptions {
  // ∂q/∂X at home (columns scaled to unit norm) with a condition number above these is on a
  // singularity (an error) or near one (a warning: the FKM and the identification degrade).
  double singular_condition = 1e8;
  double near_singular_condition = 1e3;
};

struct MechanismCheck {
  std::string label;
  int joints = 0, pose_dof = 0;
  int geometric_free = 0, external_free = 0;  // before the gauge is held
  Eigen::VectorXd home;                       // the model's reference pose (FKM start)
  Eigen::VectorXd home_joints;                // IKM there (NaN for a leg that does not assemble)
  double home_condition = 0.0;                // of the column-scaled ∂q/∂X at home
  int protocol_poses = 0, protocol_reachable = 0;
  double protocol_scale = 0.0;                    // datasets::protocolScale(): the built-in robot's protocol times this
  std::optional<mechanism::GaugeAnalysis> gauge;  // from the exact-model campaign
  std::vector<std::string> errors;                // the description cannot be used as it is
  std::vector<std::string> warnings;              // it can, with the stated consequence
  bool ok() const { return errors.empty(); }
  int expectedRank() const { return gauge ? gauge->report.rank : 0; }
};

// Never throws for a defect of the mechanism (it is reported); throws what modelInfo() throws
// for a description file it cannot read (file:line: key: what is wrong).
MechanismCheck checkMechanism(const ModelChoice& choice, const MechanismCheckOptions& options = {});

}  // namespace mire::pipeline
