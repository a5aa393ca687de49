// Model selection (doc/plan-and-select.md): k-fold cross-validation of the joint residual,
// AIC/BIC, nested F-tests and the one-SE rule over candidate models/variants.
#include "mire/mechanism/model_selection.hpp"

#include <boost/math/distributions/fisher_f.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/variants.hpp"

namespace mire::mechanism {
namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

IdentificationModel initialModel(const SelectionCandidate& c, const std::vector<PoseObservation>& poses) {
  if (c.variant) return makeH4VariantModel(c.variant, c.model.h4, poses);
  return initialModelFor(c.model, poses);
}

// Mean squared held-out joint residual of each fold, the fit on the other folds warm-started
// at the all-pose solution (its optimum depends on the training poses only).
std::vector<double> foldScores(const IdentificationModel& fitted, const std::vector<PoseObservation>& poses, int folds,
                               unsigned seed) {
  std::vector<std::size_t> order(poses.size());
  std::iota(order.begin(), order.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  IdentificationOptions options;
  options.compute_identifiability = false;
  std::vector<double> scores;
  for (int k = 0; k < folds; ++k) {
    std::vector<PoseObservation> train, test;
    for (std::size_t i = 0; i < order.size(); ++i)
      (static_cast<int>(i % static_cast<std::size_t>(folds)) == k ? test : train).push_back(poses[order[i]]);
    if (test.empty()) continue;
    const IdentificationResult r = identify(fitted, train, options);
    double sum = 0.0;
    long n = 0;
    for (const PoseObservation& p : test) {
      const IkmResult q = r.model.predictJoints(p.cTm);
      if (!q.reachable()) throw std::runtime_error("held-out pose '" + p.id + "' is unreachable for the model");
      sum += (p.joints - q.joints).squaredNorm();
      n += p.joints.size();
    }
    scores.push_back(sum / static_cast<double>(n));
  }
  return scores;
}

ModelScore scoreModel(const SelectionCandidate& c, const std::vector<PoseObservation>& poses,
                      const std::vector<LineRecord>& lines, const SelectionOptions& options) {
  ModelScore s;
  s.label = c.label;
  s.model_name = c.model.registered.name;
  try {
    const IdentificationModel initial = initialModel(c, poses);
    const IdentificationResult fit = identify(initial, poses);
    s.free_names = fit.free_names;
    s.parameters = static_cast<int>(fit.free_names.size());
    s.weighted = fit.weighted;
    s.residuals = static_cast<int>(poses.size()) * initial.mechanism->jointCount();
    s.fit_rms = fit.rms_joint_residual;
    s.chi2 = fit.weighted ? fit.chi2 : fit.rms_joint_residual * fit.rms_joint_residual * s.residuals;
    const double n = s.residuals, p = s.parameters;
    // Gaussian log-likelihood: known variances (weighted) or profiled σ² (unweighted).
    const double deviance = fit.weighted ? s.chi2 : n * std::log(s.chi2 / n);
    s.aic = deviance + 2.0 * p;
    s.bic = deviance + p * std::log(n);
    s.condition = fit.identifiability.condition_number;
    s.rank = fit.identifiability.rank;
    const std::vector<double> folds = foldScores(fit.model, poses, options.folds, options.seed);
    double mean = 0.0, var = 0.0;
    for (double f : folds) mean += f / static_cast<double>(folds.size());
    for (double f : folds)
      var += (f - mean) * (f - mean) / std::max<double>(1.0, static_cast<double>(folds.size()) - 1);
    s.cv_mse = mean;
    s.cv_se = std::sqrt(var / static_cast<double>(folds.size()));
    if (!lines.empty()) {
      std::vector<std::vector<Eigen::VectorXd>> joints;
      joints.reserve(lines.size());
      for (const LineRecord& l : lines) joints.push_back(l.joints);
      const StraightnessResult v3 = straightnessCriterion(*fit.model.mechanism, fit.model.geometricValues(), joints);
      if (v3.ok) s.v3 = v3.v3_m;
    }
    s.ok = std::isfinite(s.cv_mse);
  } catch (const std::exception& e) {
    s.ok = false;
    s.message = e.what();
  }
  return s;
}

bool nested(const ModelScore& a, const ModelScore& b) {
  if (!(a.ok && b.ok) || a.parameters >= b.parameters) return false;
  if (a.model_name == b.model_name) {
    for (const std::string& n : a.free_names)
      if (std::find(b.free_names.begin(), b.free_names.end(), n) == b.free_names.end()) return false;
    return true;
  }
  // The table's containments (registry.hpp): model 12 is model 31 at ψ_i = α_i + π, β_i = π/2,
  // the Delta its per-leg model with equal legs, the hexapod its gains model at s_i = 1
  // (doc/mechanisms.md); a model-31 variant nests model 12 only when it frees h and the forearms.
  const ModelInfo& richer = modelInfo(b.model_name);
  const auto contained = std::find(richer.contains.begin(), richer.contains.end(), a.model_name);
  const auto frees = [&b](const std::string& n) {
    return std::find(b.free_names.begin(), b.free_names.end(), n) != b.free_names.end();
  };
  return contained != richer.contains.end() &&
         std::all_of(richer.contains_when_free.begin(), richer.contains_when_free.end(), frees);
}

// F-tests between nested pairs, each model against the smallest richer model nesting it.
std::vector<NestedTest> nestedTests(const std::vector<ModelScore>& scores) {
  std::vector<NestedTest> out;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    int best = -1;
    for (std::size_t j = 0; j < scores.size(); ++j)
      if (nested(scores[i], scores[j]) &&
          (best < 0 || scores[j].parameters < scores[static_cast<std::size_t>(best)].parameters))
        best = static_cast<int>(j);
    if (best < 0) continue;
    const ModelScore& a = scores[i];
    const ModelScore& b = scores[static_cast<std::size_t>(best)];
    NestedTest t;
    t.simpler = static_cast<int>(i);
    t.richer = best;
    t.df1 = b.parameters - a.parameters;
    t.df2 = b.residuals - b.parameters;
    if (t.df2 <= 0) continue;
    t.F = std::max(0.0, (a.chi2 - b.chi2) / t.df1) / (b.chi2 / t.df2);
    const boost::math::fisher_f_distribution<double> dist(t.df1, t.df2);
    t.p_value = boost::math::cdf(boost::math::complement(dist, t.F));
    out.push_back(t);
  }
  return out;
}

}  // namespace

double ModelScore::cv_rms() const { return std::sqrt(cv_mse); }
double ModelScore::cv_rms_se() const { return cv_mse > 0 ? cv_se / (2.0 * std::sqrt(cv_mse)) : 0.0; }

std::string SelectionResult::recommendedLabel() const {
  return recommended >= 0 ? scores[static_cast<std::size_t>(recommended)].label : std::string();
}

std::vector<SelectionCandidate> parseSelectionCandidates(const std::string& text,
                                                         const std::function<DesignModel(const std::string&)>& make) {
  std::vector<SelectionCandidate> out;
  std::string current;  // the model the variant letters belong to
  for (std::string item : split(text)) {
    if (item.empty()) throw std::invalid_argument("--models '" + text + "': empty item");
    const auto colon = item.find(':');
    if (colon != std::string::npos) {
      current = item.substr(0, colon);
      item = item.substr(colon + 1);
      if (modelInfo(current).variants.empty())
        throw std::invalid_argument("--models: variants (letters) belong to " + variantOwnerList() + ", not to '" +
                                    current + "'");
    } else if (item.size() != 1) {
      current.clear();
      SelectionCandidate c;
      c.label = item;
      c.model = make(item);  // throws "unknown model"
      out.push_back(c);
      continue;
    }
    if (current.empty() || item.size() != 1)
      throw std::invalid_argument("--models: '" + item + "' is neither a model name nor a variant letter after model:");
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(item[0])));
    h4Variant(letter);  // throws outside A–H
    if (modelInfo(current).variants.find(letter) == std::string::npos)
      throw std::invalid_argument(std::string("--models: variant ") + letter + " does not belong to " + current + " (" +
                                  variantOwnerList() + ")");
    SelectionCandidate c;
    c.label = std::string(1, letter);
    c.model = make(current);
    c.variant = letter;
    out.push_back(c);
  }
  if (out.empty()) throw std::invalid_argument("--models: no model given");
  return out;
}

std::vector<std::string> selectionModelNames(const MechanismFamily& family) {
  if (family.selection.empty()) return family.models;
  std::vector<std::string> names;
  for (const std::string& item : split(family.selection)) {
    const std::string name = item.substr(0, item.find(':'));  // `model:letter` or `model`
    if (name.size() != 1 && (names.empty() || names.back() != name)) names.push_back(name);
  }
  return names;
}

std::string defaultSelectionModels(int joint_count, Unit unit) {
  for (const MechanismFamily& family : mechanismFamilies()) {
    const RegisteredModel simplest = makeRegisteredModel(family.models.front());
    if (simplest.mechanism->jointCount() == joint_count && simplest.mechanism->jointUnits().front() == unit)
      return family.selection;
  }
  throw std::invalid_argument("no registered mechanism has " + std::to_string(joint_count) + " joints in " +
                              unitName(unit) + ": give --models");
}

SelectionResult selectModel(const std::vector<SelectionCandidate>& candidates, const std::vector<PoseObservation>& poses,
                            const std::vector<LineRecord>& lines, const SelectionOptions& options) {
  if (candidates.empty()) throw std::invalid_argument("no candidate model to select from");
  if (options.folds < 2) throw std::invalid_argument("--folds must be >= 2");
  if (static_cast<int>(poses.size()) < options.folds)
    throw std::invalid_argument(std::to_string(poses.size()) + " poses for " + std::to_string(options.folds) + " folds");
  const auto start = std::chrono::steady_clock::now();
  SelectionResult r;
  for (const SelectionCandidate& c : candidates) r.scores.push_back(scoreModel(c, poses, lines, options));
  for (std::size_t i = 0; i < r.scores.size(); ++i)
    if (r.scores[i].ok && (r.best < 0 || r.scores[i].cv_mse < r.scores[static_cast<std::size_t>(r.best)].cv_mse))
      r.best = static_cast<int>(i);
  if (r.best >= 0) {
    // One-SE rule: the fewest parameters among the models within one SE of the best score.
    const ModelScore& b = r.scores[static_cast<std::size_t>(r.best)];
    const double limit = b.cv_mse + b.cv_se;
    for (std::size_t i = 0; i < r.scores.size(); ++i) {
      const ModelScore& s = r.scores[i];
      if (!s.ok || s.cv_mse > limit) continue;
      if (r.recommended < 0 || s.parameters < r.scores[static_cast<std::size_t>(r.recommended)].parameters)
        r.recommended = static_cast<int>(i);
    }
  }
  r.tests = nestedTests(r.scores);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string selectionTable(const SelectionResult& r, Unit unit) {
  std::ostringstream out;
  char line[320];
  const std::string u = displayUnitName(unit);
  const double k = toDisplay(unit, 1.0);
  std::snprintf(line, sizeof line, "%-12s %6s %22s %12s %12s %12s %10s %5s %10s\n", "model", "params",
                ("CV rms +- SE [" + u + "]").c_str(), ("fit rms [" + u + "]").c_str(), "AIC", "BIC", "cond", "rank",
                "V3 [mm]");
  out << line;
  for (std::size_t i = 0; i < r.scores.size(); ++i) {
    const ModelScore& s = r.scores[i];
    if (!s.ok) {
      out << s.label << ": failed: " << s.message << "\n";
      continue;
    }
    char cv[64];
    std::snprintf(cv, sizeof cv, "%.5f +- %.5f", s.cv_rms() * k, s.cv_rms_se() * k);
    std::snprintf(line, sizeof line, "%-12s %6d %22s %12.5f %12.1f %12.1f %10.1f %5d %10s%s\n", s.label.c_str(),
                  s.parameters, cv, s.fit_rms * k, s.aic, s.bic, s.condition, s.rank,
                  std::isfinite(s.v3) ? std::to_string(s.v3 * 1e3).substr(0, 7).c_str() : "-",
                  static_cast<int>(i) == r.best ? "  (best CV)" : "");
    out << line;
  }
  for (const NestedTest& t : r.tests) {
    std::snprintf(line, sizeof line, "F-test %s within %s: F(%d, %d) = %.3f, p = %.3g%s\n",
                  r.scores[static_cast<std::size_t>(t.simpler)].label.c_str(),
                  r.scores[static_cast<std::size_t>(t.richer)].label.c_str(), t.df1, t.df2, t.F, t.p_value,
                  t.p_value < 0.05 ? " (the richer model fits significantly better)" : "");
    out << line;
  }
  out << "rule: the fewest parameters whose CV score is within one standard error of the best\n";
  return out.str();
}

}  // namespace mire::mechanism
