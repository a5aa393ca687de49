#pragma once
// Identifiability analysis of the identification Jacobian J_ξ = ∂ε/∂ξ (paper §2.2, eq. 5–12,
// doc/mechanisms.md, "Identifiability"): SVD and condition number of the column-scaled Jacobian,
// rank, QR with column pivoting (Khalil & Besnard) for a minimal identifiable set, and the unidentifiable
// combinations written with parameter names (from the null space).
//
// Scaling: the primary condition number uses J·D with D = diag(1/‖J_k‖), i.e. every column
// scaled to unit Euclidean norm (invariant to each parameter's unit). The report also gives
// the condition number of the unscaled SI Jacobian (m, rad) for reference.
#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

struct IdentifiabilityOptions {
  // A singular value σ_k of the unit-norm scaled Jacobian counts as zero when
  // σ_k < rank_tolerance · σ_max.
  double rank_tolerance = 1e-7;
  // Null-vector coefficients below this (relative to the largest) are dropped from names.
  double coefficient_tolerance = 1e-4;
  // Per column (empty: all 1): the pivoted QR picks a column while its remaining norm × priority
  // is the largest, so lower-priority columns are the ones named dependent when columns tie.
  // The unit-norm scaling makes every first pivot a tie, so without it rounding decides which of
  // two equivalent parameters is held (the Delta's base offsets or its legs' positions).
  std::vector<double> pivot_priority;
};

// One unidentifiable direction δξ (a null vector of J, in SI parameter units), normalised
// so that the `dependent` parameter (chosen by the pivoted QR) has coefficient 1.
// Moving all parameters along it leaves every residual unchanged; what the data determine
// are the invariant sums, e.g. for eq. 24 with dependent tz_EM and members tx_CB..tz_CB:
// "tx_CB + 0.0123·tz_EM", "ty_CB − 0.0456·tz_EM", "tz_CB + 0.9988·tz_EM".
struct UnidentifiableCombination {
  std::string dependent;
  std::vector<std::pair<std::string, double>> direction;  // (name, coefficient), dependent first
  std::vector<std::string> identifiable_sums;             // k − c_k·dependent, per other member
  double singular_value = 0.0;                            // of the scaled Jacobian
  std::string text() const;  // "unidentifiable: z_ME; only z_BC + 1.0000·z_ME is identifiable"
};

struct IdentifiabilityReport {
  std::vector<std::string> parameter_names;  // the Jacobian's columns (free parameters)
  std::string scaling = "columns scaled to unit Euclidean norm";
  Eigen::VectorXd column_norms;     // ‖J_k‖ in SI (rad per m or rad per rad)
  Eigen::VectorXd singular_values;  // of the scaled Jacobian, descending
  // Per singular value: the parameter with the largest weight in its right singular vector (the
  // scaled parameter direction it measures), e.g. to name the bars of a singular-value plot.
  std::vector<std::string> dominant_parameters;
  double condition_number = 0.0;               // σ_max/σ_min of the scaled Jacobian (inf if σ_min = 0)
  double condition_number_unscaled = 0.0;      // same for the SI Jacobian
  double condition_number_identifiable = 0.0;  // scaled, restricted to `identifiable`
  int rank = 0;
  std::vector<std::string> identifiable;                // pivoted-QR order, first `rank` columns
  std::vector<std::string> unidentifiable;              // the other columns (dependents)
  std::vector<UnidentifiableCombination> combinations;  // one per null direction
  bool fullRank() const { return rank == static_cast<int>(parameter_names.size()); }
  std::string text() const;  // multi-line human summary
};

// Analyses a Jacobian (rows: residuals, columns: parameters named `names`).
// Throws std::invalid_argument on a size mismatch or non-finite entries.
IdentifiabilityReport analyzeJacobian(const Eigen::MatrixXd& jacobian, const std::vector<std::string>& names,
                                      const IdentifiabilityOptions& options = {});

}  // namespace mire::mechanism
