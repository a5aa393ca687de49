#pragma once
// Model selection (doc/plan-and-select.md; the paper's §7 asks for "tools that choose the
// optimal model for the identification"): on one campaign, every candidate model/variant is
// identified, scored by k-fold cross-validation of the joint residual (poses held out, their
// joints predicted by the model fitted on the others), with AIC/BIC and nested F-tests beside
// it; the recommendation is the simplest model whose cross-validated score is within one
// standard error of the best (the one-SE rule).
#include <Eigen/Core>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/io.hpp"

namespace mire::mechanism {

struct SelectionCandidate {
  std::string label;  // a variant letter (D) or a model name (`delta-legs`)
  DesignModel model;  // registry entry + nominal geometry
  char variant = 0;   // H4 variant A–H, 0 for a plain registry model
};

// `h4-12:A,B,C,D,h4-31c:E,F,G,H` (a model name, then its variant letters) or plain model
// names (`delta,delta-legs`). `make` builds the model of a name (its nominal geometry).
// Throws std::invalid_argument naming the bad item.
std::vector<SelectionCandidate> parseSelectionCandidates(const std::string& text,
                                                         const std::function<DesignModel(const std::string&)>& make);
// The model names of a family's `selection` (registry.hpp) in its order, each once, its variant
// letters dropped; a described robot's family, which has no selection: its model.
std::vector<std::string> selectionModelNames(const MechanismFamily& family);
// The default list for a mechanism with `joint_count` joints of `unit`: the selection of the
// table's family whose simplest model has such joints (registry.hpp).
std::string defaultSelectionModels(int joint_count, Unit unit);

struct SelectionOptions {
  int folds = 10;
  unsigned seed = 1;
};

struct ModelScore {
  std::string label;
  bool ok = false;
  std::string message;  // why it failed, when it did
  int parameters = 0;   // free parameters (geometric + mounting)
  double cv_mse =
      std::numeric_limits<double>::quiet_NaN();  // mean over folds of the held-out mean squared joint residual
  double cv_se = std::numeric_limits<double>::quiet_NaN();  // its standard error over the folds
  double cv_rms() const;                                    // √cv_mse [rad or m]
  double cv_rms_se() const;                                 // SE of √cv_mse (first order)
  double fit_rms = 0.0;                                     // joint residual RMS of the fit on all poses
  double chi2 = 0.0;                                        // weighted χ² (or RSS when unweighted)
  bool weighted = false;
  int residuals = 0;
  double aic = 0.0, bic = 0.0;
  double condition = 0.0;  // scaled Jacobian (doc/mechanisms.md)
  int rank = 0;
  double v3 = std::numeric_limits<double>::quiet_NaN();  // [m], when lines are given
  std::string model_name;                                // registry name
  std::vector<std::string> free_names;                   // for the nesting of the F-tests
};

struct NestedTest {
  int simpler = 0, richer = 0;  // indices into scores
  double F = 0.0, p_value = 1.0;
  int df1 = 0, df2 = 0;
};

struct SelectionResult {
  std::vector<ModelScore> scores;  // candidate order
  std::vector<NestedTest> tests;
  int best = -1;         // lowest CV score
  int recommended = -1;  // one-SE rule
  double seconds = 0.0;
  std::string recommendedLabel() const;
};

SelectionResult selectModel(const std::vector<SelectionCandidate>& candidates, const std::vector<PoseObservation>& poses,
                            const std::vector<LineRecord>& lines = {}, const SelectionOptions& options = {});

// The table `mire select` prints (without the final "recommended:" line).
std::string selectionTable(const SelectionResult& result, Unit joint_unit);

}  // namespace mire::mechanism
