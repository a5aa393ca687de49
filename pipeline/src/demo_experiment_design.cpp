// The demo's planning and model-selection stage (doc/plan-and-select.md): what
// `mire plan` would have chosen instead of the paper's 81 protocol poses, and which variant
// `mire select` recommends on the measured campaign, next to the paper's Table 3.
#include <string>
#include <vector>

#include "demo_stages.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/model_selection.hpp"

namespace mire::pipeline::demo {

namespace {

namespace mech = mire::mechanism;

// 15 poses planned among the protocol volume's candidates (the truth model, D criterion) against
// random sets of 15 from the same candidates, as `mire plan --count 15` reports them.
void planStudy(const DemoOptions& options, const std::string& model_name, const mech::H4Nominal& nominal,
               DemoExperimentDesign& out) {
  const mech::DesignModel model = mech::makeDesignModel(model_name, nominal);
  const mech::Mechanism& m = *model.registered.mechanism;
  const Eigen::VectorXd geometry = model.registered.nominal.values();
  const mech::Workspace workspace = mech::protocolWorkspace(m, geometry);
  mech::DesignOptions design;
  design.count = 15;
  design.seed = static_cast<unsigned>(options.seed);
  out.plan_candidates = options.quick ? 2000 : 10000;
  const auto poses = mech::generateCandidatePoses(m, geometry, workspace, out.plan_candidates, design.seed);
  const mech::CandidateInformation info =
      mech::candidateInformation(model, mech::defaultMountingGuess(workspace), poses, design);
  const mech::DesignReport report = mech::planExperiment(info, design);
  out.plan_sigma_ratio = report.median_ratio_plan_random;
  out.plan_position_sigma_m = report.position_sigma_plan_rms;
  out.random_position_sigma_m = report.position_sigma_random_rms;
}

// The eight variants ranked by 10-fold cross-validated joint residual on the measured poses.
void selectStudy(const DemoOptions& options, const std::string& selection_models, const mech::H4Nominal& nominal,
                 const std::vector<mech::PoseObservation>& poses, DemoExperimentDesign& out) {
  const auto candidates = mech::parseSelectionCandidates(
      selection_models, [&](const std::string& name) { return mech::makeDesignModel(name, nominal); });
  mech::SelectionOptions selection;
  selection.seed = static_cast<unsigned>(options.seed);
  out.folds = selection.folds;
  const mech::SelectionResult result = mech::selectModel(candidates, poses, {}, selection);
  out.selection_table = mech::selectionTable(result, mech::Unit::Radian);
  out.recommended = result.recommended >= 0 ? result.recommendedLabel() : "none (no variant could be identified)";
}

}  // namespace

DemoExperimentDesign experimentDesignStage(const DemoOptions& options, const mech::MechanismFamily& family,
                                           const mech::H4Nominal& nominal,
                                           const std::vector<mech::PoseObservation>& poses) {
  DemoExperimentDesign out;
  planStudy(options, family.truth_model, nominal, out);
  selectStudy(options, family.selection, nominal, poses, out);
  return out;
}

}  // namespace mire::pipeline::demo
