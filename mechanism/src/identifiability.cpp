// Identifiability of J_ξ (paper §2.2 eq. 5–12; doc/mechanisms.md): SVD of the column-scaled Jacobian,
// rank, QR with column pivoting (Khalil & Besnard) and named null-space combinations.
#include "mire/mechanism/identifiability.hpp"

#include <Eigen/Householder>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "large_problem.hpp"

namespace mire::mechanism {

namespace {

std::string formatCoefficient(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4f", value);
  return buffer;
}

// Two remaining column norms closer than this (relative) tie in the pivoted QR, and the column
// first in parameter order wins: equivalent parameters (an arm turned about its axis and the
// joint offset) have equal norms up to rounding, which otherwise chose which one is held and
// changed it with the last bits of the Jacobian (doc/mechanisms.md, "Identifiability").
constexpr double kPivotTieTolerance = 1e-9;

double conditionOf(const Eigen::VectorXd& singular_values) {
  if (singular_values.size() == 0) return 0.0;
  const double smallest = singular_values.minCoeff();
  if (!(smallest > 0.0)) return std::numeric_limits<double>::infinity();
  return singular_values.maxCoeff() / smallest;
}

}  // namespace

std::string UnidentifiableCombination::text() const {
  std::string out = "unidentifiable direction:";
  for (const auto& [name, coefficient] : direction)
    out += " " + (coefficient < 0 ? std::string("-") : std::string("+")) + formatCoefficient(std::abs(coefficient)) +
           "·δ" + name;
  if (identifiable_sums.empty()) {
    out += "; " + dependent + " has no influence on the residuals";
  } else {
    out += "; only";
    for (std::size_t i = 0; i < identifiable_sums.size(); ++i) out += (i ? ", " : " ") + identifiable_sums[i];
    out += " identifiable";
  }
  return out;
}

std::string IdentifiabilityReport::text() const {
  std::ostringstream out;
  out << "Identifiability of " << parameter_names.size() << " parameters (" << scaling << ")\n";
  out << "  rank " << rank << " of " << parameter_names.size() << "; condition number " << condition_number
      << " (unscaled SI: " << condition_number_unscaled << ")";
  if (!fullRank()) out << "; identifiable subset: " << condition_number_identifiable;
  out << "\n  singular values:";
  for (Eigen::Index i = 0; i < singular_values.size(); ++i) out << " " << singular_values[i];
  out << "\n";
  if (!unidentifiable.empty()) {
    out << "  not identifiable (pivoted QR): ";
    for (std::size_t i = 0; i < unidentifiable.size(); ++i) out << (i ? ", " : "") << unidentifiable[i];
    out << "\n";
  }
  for (const UnidentifiableCombination& c : combinations) out << "  " << c.text() << "\n";
  return out.str();
}

namespace {

// Singular values of the column-scaled Jacobian (zeros when fewer rows than columns), the
// condition numbers (scaled and unscaled SI) and the rank.
void singularValueStage(IdentifiabilityReport& report, const Eigen::MatrixXd& J,
                        const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, const IdentifiabilityOptions& options) {
  const Eigen::Index n = J.cols();
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  s.head(svd.singularValues().size()) = svd.singularValues();
  report.singular_values = s;
  report.condition_number = conditionOf(s);
  report.condition_number_unscaled = conditionOf([&] {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    const Eigen::JacobiSVD<Eigen::MatrixXd> raw(J);
    u.head(raw.singularValues().size()) = raw.singularValues();
    return u;
  }());
  const double threshold = options.rank_tolerance * s[0];
  report.rank = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (s[k] > threshold) ++report.rank;
}

// Column order of a Householder QR with column pivoting: at each step the column of largest
// remaining norm, ties (kPivotTieTolerance) to the first in parameter order. The remaining norms
// are recomputed at each step rather than downdated, so that equal ones stay equal.
std::vector<Eigen::Index> pivotOrder(Eigen::MatrixXd A) {
  const Eigen::Index m = A.rows(), n = A.cols();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) order[static_cast<std::size_t>(k)] = k;
  Eigen::VectorXd workspace(n);
  for (Eigen::Index k = 0; k < std::min(m, n); ++k) {
    const Eigen::VectorXd norms = A.bottomRightCorner(m - k, n - k).colwise().norm().transpose();
    const double floor = (1.0 - kPivotTieTolerance) * norms.maxCoeff();
    Eigen::Index best = 0;
    for (Eigen::Index j = 1; j < n - k; ++j)
      if (norms[j] >= floor &&
          (norms[best] < floor || order[static_cast<std::size_t>(k + j)] < order[static_cast<std::size_t>(k + best)]))
        best = j;
    A.col(k).swap(A.col(k + best));
    std::swap(order[static_cast<std::size_t>(k)], order[static_cast<std::size_t>(k + best)]);
    Eigen::VectorXd essential(m - k - 1);
    double tau = 0.0, beta = 0.0;
    A.col(k).tail(m - k).makeHouseholder(essential, tau, beta);
    A.bottomRightCorner(m - k, n - k - 1).applyHouseholderOnTheLeft(essential, tau, workspace.data());
  }
  return order;
}

// Khalil & Besnard: the first `rank` pivoted-QR columns form a minimal identifiable set;
// returns the other (dependent) columns and sets the identifiable subset's condition number.
std::vector<Eigen::Index> pivotedQrStage(IdentifiabilityReport& report, const Eigen::MatrixXd& Js,
                                         const std::vector<std::string>& names, const std::vector<double>& priority) {
  Eigen::MatrixXd weighted = Js;
  if (priority.size() == static_cast<std::size_t>(Js.cols()))
    for (Eigen::Index k = 0; k < Js.cols(); ++k) weighted.col(k) *= priority[static_cast<std::size_t>(k)];
  const std::vector<Eigen::Index> permutation = pivotOrder(weighted);
  std::vector<Eigen::Index> identifiable_columns, dependent_columns;
  for (Eigen::Index k = 0; k < Js.cols(); ++k) {
    const Eigen::Index column = permutation[static_cast<std::size_t>(k)];
    (k < report.rank ? identifiable_columns : dependent_columns).push_back(column);
    (k < report.rank ? report.identifiable : report.unidentifiable).push_back(names[static_cast<std::size_t>(column)]);
  }
  if (!identifiable_columns.empty()) {
    Eigen::MatrixXd sub(Js.rows(), static_cast<Eigen::Index>(identifiable_columns.size()));
    for (std::size_t k = 0; k < identifiable_columns.size(); ++k)
      sub.col(static_cast<Eigen::Index>(k)) = Js.col(identifiable_columns[k]);
    Eigen::VectorXd ss = Eigen::VectorXd::Zero(sub.cols());
    const Eigen::JacobiSVD<Eigen::MatrixXd> subsvd(sub);
    ss.head(subsvd.singularValues().size()) = subsvd.singularValues();
    report.condition_number_identifiable = conditionOf(ss);
  }
  return dependent_columns;
}

// Null space in parameter units (δξ = D·v), re-based so that each direction has coefficient
// 1 on its own dependent parameter and 0 on the other dependents; named combinations.
void nullSpaceStage(IdentifiabilityReport& report, const Eigen::MatrixXd& V, const Eigen::VectorXd& scale,
                    const std::vector<Eigen::Index>& dependent_columns, const std::vector<std::string>& names,
                    const IdentifiabilityOptions& options) {
  const Eigen::Index n = V.cols();
  const Eigen::Index nullity = n - report.rank;
  const Eigen::MatrixXd null_params = scale.asDiagonal() * V.rightCols(nullity);
  Eigen::MatrixXd dependent_block(nullity, nullity);
  for (Eigen::Index j = 0; j < nullity; ++j)
    dependent_block.row(j) = null_params.row(dependent_columns[static_cast<std::size_t>(j)]);
  const Eigen::MatrixXd basis = null_params * dependent_block.fullPivLu().inverse();
  for (Eigen::Index j = 0; j < nullity; ++j) {
    const Eigen::Index dep = dependent_columns[static_cast<std::size_t>(j)];
    UnidentifiableCombination combination;
    combination.dependent = names[static_cast<std::size_t>(dep)];
    combination.singular_value = report.singular_values[report.rank + j];
    combination.direction.emplace_back(combination.dependent, 1.0);
    for (Eigen::Index k = 0; k < n; ++k) {
      if (k == dep) continue;
      const double coefficient = basis(k, j);
      // Significance: the coefficient's effect in unit-norm column space vs the dependent's.
      const double effect = std::abs(coefficient) * report.column_norms[k] /
                            std::max(report.column_norms[dep], std::numeric_limits<double>::min());
      if (!(effect > options.coefficient_tolerance)) continue;
      const std::string& name = names[static_cast<std::size_t>(k)];
      combination.direction.emplace_back(name, coefficient);
      // Invariant along the direction: ξ_k − c_k·ξ_dep.
      combination.identifiable_sums.push_back(name + (coefficient > 0 ? " - " : " + ") +
                                              formatCoefficient(std::abs(coefficient)) + "·" + combination.dependent);
    }
    report.combinations.push_back(std::move(combination));
  }
}

}  // namespace

IdentifiabilityReport analyzeJacobian(const Eigen::MatrixXd& J, const std::vector<std::string>& names,
                                      const IdentifiabilityOptions& options) {
  const Eigen::Index n = J.cols();
  if (static_cast<std::size_t>(n) != names.size())
    throw std::invalid_argument("identifiability: " + std::to_string(n) + " Jacobian columns but " +
                                std::to_string(names.size()) + " parameter names");
  if (!J.allFinite()) throw std::invalid_argument("identifiability: the Jacobian has non-finite entries");
  // Every quantity below depends on J through JᵀJ only (column norms, SVD, pivoted QR).
  if (J.rows() > detail::kLargeProblemRows) return analyzeJacobian(detail::compressRows(J), names, options);
  IdentifiabilityReport report;
  report.parameter_names = names;
  if (n == 0) return report;

  report.column_norms = J.colwise().norm().transpose();
  Eigen::VectorXd scale(n);  // D = diag(1/‖J_k‖); an all-zero column keeps scale 1
  for (Eigen::Index k = 0; k < n; ++k) scale[k] = report.column_norms[k] > 0.0 ? 1.0 / report.column_norms[k] : 1.0;
  const Eigen::MatrixXd Js = J * scale.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeFullV);
  singularValueStage(report, J, svd, options);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index largest = 0;
    svd.matrixV().col(k).cwiseAbs().maxCoeff(&largest);
    report.dominant_parameters.push_back(names[static_cast<std::size_t>(largest)]);
  }
  const std::vector<Eigen::Index> dependent_columns = pivotedQrStage(report, Js, names, options.pivot_priority);
  if (report.rank < n) nullSpaceStage(report, svd.matrixV(), scale, dependent_columns, names, options);
  return report;
}

}  // namespace mire::mechanism
