// Experiment design, part 2: the D/A/E criteria on the Schur complement of the Fisher
// information, the DETMAX exchange (Mitchell 1974, one-point excursions), and the report
// comparing the plan with random designs of the same size (doc/plan-and-select.md).
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "mire/mechanism/experiment_design.hpp"

namespace mire::mechanism {
namespace {

constexpr double kRidge = 1e-6;  // in the scaled space (one average candidate has unit diagonal)
constexpr double kNegInf = -std::numeric_limits<double>::infinity();

// The candidates' whitened rows with every column scaled by its RMS over the candidates, so
// that one average candidate has unit information per parameter (the A/E criteria need a
// common scale for parameters in m and rad; D does not depend on it).
struct ScaledCandidates {
  std::vector<Eigen::MatrixXd> rows;
  Eigen::VectorXd scale;  // physical σ = scaled σ / scale
  int p = 0, G = 0, m = 0;
};

ScaledCandidates scaleCandidates(const CandidateInformation& info) {
  ScaledCandidates s;
  s.p = static_cast<int>(info.free_names.size());
  s.G = info.geometric_free;
  s.m = info.rows.empty() ? 0 : static_cast<int>(info.rows[0].rows());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(s.p);
  for (const Eigen::MatrixXd& A : info.rows) sum += A.colwise().squaredNorm().transpose();
  s.scale = (sum / static_cast<double>(std::max<std::size_t>(1, info.rows.size()))).cwiseMax(1e-300).cwiseSqrt();
  const Eigen::VectorXd inv = s.scale.cwiseInverse();
  s.rows.reserve(info.rows.size());
  for (const Eigen::MatrixXd& A : info.rows) s.rows.emplace_back(A * inv.asDiagonal());
  return s;
}

double logDet(const Eigen::MatrixXd& M) {
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return kNegInf;
  return 2.0 * llt.matrixLLT().diagonal().array().log().sum();
}

Eigen::MatrixXd schurComplement(const Eigen::MatrixXd& M, int G) {
  const int E = static_cast<int>(M.rows()) - G;
  if (E == 0) return M;
  const Eigen::MatrixXd Mee = M.bottomRightCorner(E, E);
  return M.topLeftCorner(G, G) - M.topRightCorner(G, E) * Mee.ldlt().solve(M.bottomLeftCorner(E, G));
}

// The criterion value, larger is better.
double criterionValue(const Eigen::MatrixXd& M, int G, DesignCriterion c) {
  const int E = static_cast<int>(M.rows()) - G;
  switch (c) {
    case DesignCriterion::D:
      return logDet(M) - (E > 0 ? logDet(M.bottomRightCorner(E, E)) : 0.0);
    case DesignCriterion::A: {
      const Eigen::LLT<Eigen::MatrixXd> llt(M);
      if (llt.info() != Eigen::Success) return kNegInf;
      const Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
      return -inv.topLeftCorner(G, G).trace();
    }
    case DesignCriterion::E: {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(schurComplement(M, G), Eigen::EigenvaluesOnly);
      return eig.eigenvalues()[0];
    }
  }
  return kNegInf;
}

// Criterion gain of adding each candidate (rank-m updates: determinant lemma for D,
// Sherman–Morrison–Woodbury for A). E has no cheap update: the D gain preselects.
std::vector<double> additionGains(const ScaledCandidates& s, const Eigen::MatrixXd& M, DesignCriterion c) {
  const int E = s.p - s.G;
  const Eigen::MatrixXd Minv = M.llt().solve(Eigen::MatrixXd::Identity(s.p, s.p));
  Eigen::MatrixXd Meinv;
  if (E > 0) Meinv = M.bottomRightCorner(E, E).llt().solve(Eigen::MatrixXd::Identity(E, E));
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(s.m, s.m);
  std::vector<double> gains(s.rows.size());
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    const Eigen::MatrixXd& B = s.rows[j];
    const Eigen::MatrixXd T = B * Minv;
    const Eigen::MatrixXd S = I + T * B.transpose();
    if (c == DesignCriterion::A) {
      const Eigen::MatrixXd U = S.llt().solve(T.leftCols(s.G));
      gains[j] = U.cwiseProduct(T.leftCols(s.G)).sum();
      continue;
    }
    double g = std::log(S.determinant());
    if (E > 0) {
      const Eigen::MatrixXd Be = B.rightCols(E);
      g -= std::log((I + Be * Meinv * Be.transpose()).determinant());
    }
    gains[j] = g;
  }
  return gains;
}

int bestAddition(const ScaledCandidates& s, const Eigen::MatrixXd& M, DesignCriterion c,
                 const std::vector<char>& in_design) {
  const std::vector<double> gains = additionGains(s, M, c);
  std::vector<int> order;
  for (int j = 0; j < static_cast<int>(gains.size()); ++j)
    if (!in_design[static_cast<std::size_t>(j)] && std::isfinite(gains[static_cast<std::size_t>(j)]))
      order.push_back(j);
  if (order.empty()) return -1;
  if (c != DesignCriterion::E)
    return *std::max_element(order.begin(), order.end(), [&](int a, int b) { return gains[a] < gains[b]; });
  const std::size_t keep = std::min<std::size_t>(48, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(keep), order.end(),
                    [&](int a, int b) { return gains[a] > gains[b]; });
  int best = order[0];
  double best_value = kNegInf;
  for (std::size_t k = 0; k < keep; ++k) {
    const Eigen::MatrixXd& B = s.rows[static_cast<std::size_t>(order[k])];
    const double v = criterionValue(M + B.transpose() * B, s.G, c);
    if (v > best_value) best_value = v, best = order[k];
  }
  return best;
}

Eigen::MatrixXd information(const ScaledCandidates& s, const std::vector<int>& design) {
  Eigen::MatrixXd M = kRidge * Eigen::MatrixXd::Identity(s.p, s.p);
  for (int j : design)
    M.noalias() += s.rows[static_cast<std::size_t>(j)].transpose() * s.rows[static_cast<std::size_t>(j)];
  return M;
}

std::vector<int> greedyDesign(const ScaledCandidates& s, int count, DesignCriterion c) {
  std::vector<int> design;
  std::vector<char> in(s.rows.size(), 0);
  Eigen::MatrixXd M = information(s, design);
  while (static_cast<int>(design.size()) < count) {
    // D gains drive the start (A/E are poor guides while the information is still singular).
    const int j = bestAddition(s, M, static_cast<int>(design.size()) * s.m < s.p ? DesignCriterion::D : c, in);
    if (j < 0) break;
    design.push_back(j);
    in[static_cast<std::size_t>(j)] = 1;
    M.noalias() += s.rows[static_cast<std::size_t>(j)].transpose() * s.rows[static_cast<std::size_t>(j)];
  }
  return design;
}

// One DETMAX excursion: add the best candidate, remove the point that costs least. Returns
// false when that brings no strict improvement (the design is then unchanged).
bool exchangeOnce(const ScaledCandidates& s, std::vector<int>& design, std::vector<char>& in, Eigen::MatrixXd& M,
                  DesignCriterion c) {
  const double before = criterionValue(M, s.G, c);
  const int add = bestAddition(s, M, c, in);
  if (add < 0) return false;
  const Eigen::MatrixXd& Ba = s.rows[static_cast<std::size_t>(add)];
  const Eigen::MatrixXd Mplus = M + Ba.transpose() * Ba;
  int remove = -1;
  double best = kNegInf;
  for (std::size_t k = 0; k < design.size(); ++k) {
    const Eigen::MatrixXd& B = s.rows[static_cast<std::size_t>(design[k])];
    const double v = criterionValue(Mplus - B.transpose() * B, s.G, c);
    if (v > best) best = v, remove = static_cast<int>(k);
  }
  if (remove < 0 || !(best > before + 1e-10 * std::max(1.0, std::abs(before)))) return false;
  const Eigen::MatrixXd& Br = s.rows[static_cast<std::size_t>(design[static_cast<std::size_t>(remove)])];
  M = Mplus - Br.transpose() * Br;
  in[static_cast<std::size_t>(design[static_cast<std::size_t>(remove)])] = 0;
  in[static_cast<std::size_t>(add)] = 1;
  design[static_cast<std::size_t>(remove)] = add;
  return true;
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::infinity();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double rms(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

std::vector<int> randomDesign(int n, int count, std::mt19937& rng) {
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  for (int k = 0; k < count; ++k) {
    std::uniform_int_distribution<int> pick(k, n - 1);
    std::swap(all[static_cast<std::size_t>(k)], all[static_cast<std::size_t>(pick(rng))]);
  }
  all.resize(static_cast<std::size_t>(count));
  return all;
}

// How much of the plan's geometric variance is the calibration error shared by every pose:
// that part does not shrink with more poses, only with a better camera calibration.
std::string sharedTermText(const DesignReport& r) {
  std::vector<double> shares;
  int largest = 0;
  for (int i = 0; i < r.geometric_free; ++i) {
    shares.push_back(std::pow(r.sigma_plan_shared[i] / r.sigma_plan[i], 2));
    if (shares.back() > shares[static_cast<std::size_t>(largest)]) largest = i;
  }
  if (shares.empty()) return {};
  char line[320];
  std::snprintf(line, sizeof line,
                "the camera calibration's error, shared by every pose, is in the predicted sigma: %.0f %% of the "
                "geometric variance (median; largest %s %.0f %%); more poses do not lower that part, a better "
                "camera calibration does\n",
                100.0 * median(shares), r.names[static_cast<std::size_t>(largest)].c_str(),
                100.0 * shares[static_cast<std::size_t>(largest)]);
  return line;
}

}  // namespace

std::vector<int> chooseDesign(const CandidateInformation& info, const DesignOptions& options) {
  const int n = static_cast<int>(info.rows.size());
  const int p = static_cast<int>(info.free_names.size());
  const int m = n > 0 ? static_cast<int>(info.rows[0].rows()) : 0;
  if (options.count > n)
    throw std::invalid_argument("--count " + std::to_string(options.count) + " exceeds the " + std::to_string(n) +
                                " candidate poses");
  if (options.count * m < p)
    throw std::invalid_argument("--count " + std::to_string(options.count) + ": " + std::to_string(options.count) +
                                " poses give " + std::to_string(options.count * m) + " joint readings for " +
                                std::to_string(p) + " free parameters; at least " + std::to_string((p + m - 1) / m) +
                                " poses are needed");
  const ScaledCandidates s = scaleCandidates(info);
  std::vector<int> design = greedyDesign(s, options.count, options.criterion);
  std::vector<char> in(s.rows.size(), 0);
  for (int j : design) in[static_cast<std::size_t>(j)] = 1;
  Eigen::MatrixXd M = information(s, design);
  for (int it = 0; it < options.max_exchanges; ++it)
    if (!exchangeOnce(s, design, in, M, options.criterion)) break;
  return design;
}

DesignReport planExperiment(const CandidateInformation& info, const DesignOptions& options) {
  DesignReport r;
  r.criterion = options.criterion;
  const auto start = std::chrono::steady_clock::now();
  r.design = chooseDesign(info, options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.names = info.free_names;
  for (std::size_t i : info.model.parameters.freeIndices()) r.units.push_back(info.model.parameters[i].unit);
  r.geometric_free = info.geometric_free;
  const Eigen::MatrixXd Cplan = designCovariance(info, r.design);
  r.sigma_plan = designSigma(info, r.design);
  if (info.hasSharedTerm()) r.sigma_plan_shared = designSharedCovariance(info, r.design).diagonal().cwiseSqrt();
  std::vector<int> all(info.rows.size());
  std::iota(all.begin(), all.end(), 0);
  r.sigma_all = designSigma(info, all);

  // Evaluation poses for the positioning accuracy: up to 100 spread over the candidates.
  std::vector<int> evaluation;
  const std::size_t stride = std::max<std::size_t>(1, info.rows.size() / 100);
  for (std::size_t j = 0; j < info.rows.size(); j += stride) evaluation.push_back(static_cast<int>(j));
  const std::vector<double> plan_position = predictedPositionSigma(info, Cplan, evaluation);
  r.position_sigma_plan_rms = rms(plan_position);
  r.position_sigma_plan_max = plan_position.empty() ? 0.0 : *std::max_element(plan_position.begin(), plan_position.end());

  std::mt19937 rng(options.seed + 17);
  const int p = static_cast<int>(r.names.size());
  std::vector<std::vector<double>> per_parameter(static_cast<std::size_t>(p));
  std::vector<double> random_position;
  for (int k = 0; k < options.random_designs; ++k) {
    const std::vector<int> d = randomDesign(static_cast<int>(info.rows.size()), options.count, rng);
    const Eigen::MatrixXd C = designCovariance(info, d);
    if (!std::isfinite(C(0, 0))) continue;  // singular random draw: not counted
    ++r.random_designs_used;
    for (int i = 0; i < p; ++i) per_parameter[static_cast<std::size_t>(i)].push_back(std::sqrt(std::max(0.0, C(i, i))));
    if (k < 10) random_position.push_back(rms(predictedPositionSigma(info, C, evaluation)));
  }
  r.sigma_random.resize(p);
  std::vector<double> ratios;
  for (int i = 0; i < p; ++i) {
    r.sigma_random[i] = median(per_parameter[static_cast<std::size_t>(i)]);
    if (i < r.geometric_free) ratios.push_back(r.sigma_plan[i] / r.sigma_random[i]);
  }
  r.median_ratio_plan_random = median(ratios);
  r.position_sigma_random_rms = median(random_position);
  return r;
}

std::string designReportText(const DesignReport& r) {
  std::ostringstream out;
  char line[256];
  out << "criterion: " << designCriterionName(r.criterion)
      << (r.criterion == DesignCriterion::D ? " (Ds-optimal: log det of the Schur complement, mounting as nuisance)\n"
          : r.criterion == DesignCriterion::A
              ? " (A-optimal on the Schur complement, variances relative to one average pose)\n"
              : " (E-optimal: smallest eigenvalue of the scaled Schur complement)\n");
  out << "poses chosen: " << r.design.size() << " in " << std::to_string(r.seconds) << " s\n";
  out << "predicted sigma (plan | median of " << r.random_designs_used
      << " random sets of the same size | all candidates):\n";
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    std::snprintf(line, sizeof line, "  %-8s %-3s %12.5g %12.5g %12.5g %s\n", r.names[i].c_str(),
                  displayUnitName(r.units[i]).c_str(), toDisplay(r.units[i], r.sigma_plan[k]),
                  toDisplay(r.units[i], r.sigma_random[k]), toDisplay(r.units[i], r.sigma_all[k]),
                  static_cast<int>(i) < r.geometric_free ? "" : "(mounting, nuisance)");
    out << line;
  }
  std::snprintf(line, sizeof line, "median sigma ratio plan/random over the geometric parameters: %.3f\n",
                r.median_ratio_plan_random);
  out << line;
  if (r.sigma_plan_shared.size() > 0) out << sharedTermText(r);
  std::snprintf(line, sizeof line,
                "predicted positioning accuracy after identification (effector position sigma, common rigid "
                "motion removed, RMS over the workspace): plan %.4f mm (max %.4f mm), random sets %.4f mm\n",
                r.position_sigma_plan_rms * 1e3, r.position_sigma_plan_max * 1e3, r.position_sigma_random_rms * 1e3);
  out << line;
  return out.str();
}

}  // namespace mire::mechanism
