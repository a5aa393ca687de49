// The identification's covariance as the sum of its named terms (identification.hpp,
// doc/uncertainty.md "How the terms add up").
#include <cmath>
#include <limits>
#include <set>

#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {

namespace {

// σ per parameter (tied ones share their leader's); ∞ for the members of an unidentifiable
// combination when the system is deficient, 0 when fixed.
void fillSigma(IdentificationResult& result) {
  const ParameterSet& params = result.model.parameters;
  const std::vector<std::size_t> free_indices = params.freeIndices();
  std::set<std::string> undetermined;
  if (result.rank_deficient)
    for (const UnidentifiableCombination& c : result.identifiability.combinations)
      for (const auto& [name, coefficient] : c.direction) undetermined.insert(name);
  result.sigma = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(params.size()));
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::size_t leader = params.tieLeader(i);
    for (std::size_t f = 0; f < free_indices.size(); ++f)
      if (free_indices[f] == leader) {
        const auto fi = static_cast<Eigen::Index>(f);
        result.sigma[static_cast<Eigen::Index>(i)] = undetermined.count(params[leader].name)
                                                         ? std::numeric_limits<double>::infinity()
                                                         : std::sqrt(result.covariance(fi, fi));
      }
  }
}

}  // namespace

void setCovarianceTerms(IdentificationResult& result, std::vector<CovarianceTerm> terms) {
  result.covariance_terms = std::move(terms);
  const auto p = static_cast<Eigen::Index>(result.free_names.size());
  result.covariance = Eigen::MatrixXd::Zero(p, p);
  for (const CovarianceTerm& term : result.covariance_terms) result.covariance += term.covariance;
  fillSigma(result);
}

const CovarianceTerm* IdentificationResult::term(const std::string& name) const {
  for (const CovarianceTerm& t : covariance_terms)
    if (t.name == name) return &t;
  return nullptr;
}

Eigen::MatrixXd IdentificationResult::termCovariance(const std::string& name) const {
  const CovarianceTerm* t = term(name);
  const auto p = static_cast<Eigen::Index>(free_names.size());
  return t ? t->covariance : Eigen::MatrixXd::Zero(p, p);
}

std::string IdentificationResult::covarianceMethod() const {
  const CovarianceTerm* fit = term(CovarianceTerm::kFit);
  std::string method = fit ? fit->method : "";
  if (term(CovarianceTerm::kShared)) method += " + shared calibration term";
  return method;
}

double IdentificationResult::covarianceScale2() const {
  const CovarianceTerm* fit = term(CovarianceTerm::kFit);
  return fit ? fit->scale2 : 1.0;
}

}  // namespace mire::mechanism
