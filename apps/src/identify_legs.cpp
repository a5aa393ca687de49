// `mire identify --observations legs|both` (identify_legs.hpp).
#include "identify_legs.hpp"

#include "commands.hpp"
#include "model_choice.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify_legs.hpp"
#include "mire/pipeline/pose_set.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

// The table's models whose legs the camera can observe, for messages.
std::string modelsWithLegs() {
  std::string list;
  for (const mech::ModelInfo& info : mech::registeredModels())
    if (mech::makeRegisteredModel(info.name).mechanism->legCount() > 0) list += (list.empty() ? "" : ", ") + info.name;
  return list;
}

// Legs only: the poses are the joints' rows (no target measurement).
std::vector<mech::PoseObservation> posesFromJoints(const LegIdentifyArguments& args,
                                                   const std::vector<std::string>& columns) {
  std::vector<mech::PoseObservation> out;
  for (const mech::JointRow& row : mech::readJointsCsv(args.joints, columns)) {
    mech::PoseObservation p;
    p.id = row.pose_id;
    p.joints = row.joints;
    out.push_back(p);
  }
  return out;
}

std::string summaryOf(const pipeline::LegIdentification& run, mech::Observations observations) {
  const mech::LegIdentificationResult& r = run.result;
  std::ostringstream out;
  char line[256];
  out << "parameter        unit        initial     identified          sigma\n";
  for (std::size_t i = 0; i < r.model.parameters.size(); ++i) {
    const mech::Parameter& p = r.model.parameters[i];
    const double sigma = r.sigma[static_cast<Eigen::Index>(i)];
    std::snprintf(line, sizeof line, "%-16s %-6s %12.4f %14.4f %14s\n", p.name.c_str(),
                  mech::displayUnitName(p.unit).c_str(), mech::toDisplay(p.unit, run.initial.parameters[i].value),
                  mech::toDisplay(p.unit, p.value),
                  p.fixed ? "held" : std::to_string(mech::toDisplay(p.unit, sigma)).c_str());
    out << line;
  }
  std::snprintf(line, sizeof line, "observations %s: %zu poses, %d leg rows, %d target rows; chi2/dof %.3f (dof %d)%s\n",
                mech::observationsName(observations).c_str(), r.bTe.size(), r.leg_rows, r.target_rows,
                r.chi2 / std::max(1, r.dof), r.dof, r.converged ? "" : "; the solver did not report convergence");
  out << line;
  if (r.covariance_scale2 != 1.0) {
    std::snprintf(line, sizeof line,
                  "warning: the observations' covariances do not explain the residuals (chi2/dof %.3f outside its "
                  "0.999 band): sigma scaled by %.3g (doc/legs.md)\n",
                  r.chi2 / std::max(1, r.dof), std::sqrt(r.covariance_scale2));
    out << line;
  }
  std::snprintf(line, sizeof line, "identifiability: rank %d of %zu free parameters, condition number %.4g\n",
                r.identifiability.rank, r.free_names.size(), r.identifiability.condition_number);
  out << line;
  return out.str();
}

}  // namespace

int runLegIdentify(const LegIdentifyArguments& args) {
  const mech::Observations observations = [&] {
    try {
      return mech::parseObservations(args.observations);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--observations: ") + e.what());
    }
  }();
  if (args.legs.empty()) throw UsageError("--observations " + args.observations + " needs --legs legs.csv");
  if (observations == mech::Observations::Both && args.poses.empty())
    throw UsageError("--observations both needs --poses poses.csv");
  CommandPaths paths;
  paths.input_files = {{args.legs, "--legs"}, {args.joints, "--joints"}};
  if (!args.poses.empty()) paths.input_files.push_back({args.poses, "--poses"});
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  paths.output_files = {{args.output, "-o"}};
  checkCommandPaths(paths);
  const pipeline::ModelChoice choice = chooseCommandModel(args.model, "", "", args.nominal);
  const mech::RegisteredModel model = choice.registered();
  if (model.mechanism->legCount() == 0)
    throw UsageError("--observations " + args.observations + ": model " + choice.label() + " has no observable legs (" +
                     modelsWithLegs() + ")");
  const std::vector<mech::LegObservation> legs = mech::readLegsCsv(args.legs, model.mechanism->legCount());
  std::vector<mech::PoseObservation> poses;
  if (observations == mech::Observations::Legs) {
    poses = posesFromJoints(args, model.mechanism->jointColumnNames());
  } else {
    pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(args.poses, args.joints);
    if (!args.covariances.empty()) files.covariances = fs::path(args.covariances);
    files.shared.reset();
    poses = pipeline::readPoseSet(files, model.mechanism->jointColumnNames()).observations.poses;
  }
  for (const mech::LegObservation& o : legs) {
    bool known = false;
    for (const mech::PoseObservation& p : poses) known = known || p.id == o.pose_id;
    if (!known)
      throw std::runtime_error(args.legs + ": pose '" + o.pose_id + "' (leg " + std::to_string(o.leg + 1) +
                               ") has no row in " +
                               (args.poses.empty() ? args.joints : args.poses + " with " + args.joints));
  }
  const pipeline::LegIdentification run = pipeline::identifyWithLegs(choice, poses, legs, observations, args.fix);
  const std::string summary = summaryOf(run, observations);
  mech::writeParameterFile(args.output, run.result.model.parameters, run.result.sigma,
                           {{"model", choice.model},
                            {"observations", mech::observationsName(observations)},
                            {"external_form", mech::externalFormName(run.result.model.external.form())},
                            {"created_by", "mire identify"}},
                           "Identified by mire identify (" + choice.label() + ", observations " +
                               mech::observationsName(observations) + ") from " + args.legs + " and " + args.joints +
                               "\nsigma_<name>: standard deviation of the estimate (same unit as <name>)");
  std::cout << summary << "wrote " << args.output << "\n";
  return kOk;
}

}  // namespace mire::app
