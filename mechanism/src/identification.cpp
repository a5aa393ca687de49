// Identification with Ceres (paper eq. 2/4; doc/mechanisms.md): weighted IKM residuals, priors,
// robust loss, covariance of the estimate and the identifiability report at the solution.
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/identification_covariance.hpp"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "mire/support/yaml.hpp"

#include "free_parameter_cost.hpp"
#include "large_problem.hpp"
#include "pose_chunk_cost.hpp"

namespace mire::mechanism {

namespace {

// Gaussian prior on one entry of a parameter block: r = (x_k − μ)/σ.
class PriorCost final : public ceres::CostFunction {
 public:
  PriorCost(int block_size, int index, double mean, double sigma) : index_(index), mean_(mean), sigma_(sigma) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(block_size);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    residuals[0] = (parameters[0][index_] - mean_) / sigma_;
    if (jacobians && jacobians[0]) {
      for (int k = 0; k < parameter_block_sizes()[0]; ++k) jacobians[0][k] = 0.0;
      jacobians[0][index_] = 1.0 / sigma_;
    }
    return true;
  }

 private:
  int index_;
  double mean_, sigma_;
};

std::string joinIds(const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) out += (out.empty() ? "" : ", ") + id;
  return out;
}

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Evaluates whitened residuals and their Jacobian w.r.t. the ambient parameters [ξg | ξe]
// for poses [first, first + count) (rows 4(j − first)..4(j − first)+3); appends the ids of
// the poses the IKM cannot reach.
void evaluateRange(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                   const std::vector<Eigen::MatrixXd>& whitening, std::size_t first, std::size_t count,
                   Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian, std::vector<std::string>* unreachable) {
  const int J = model.mechanism->jointCount();
  const int G = model.geometricCount();
  const int E = model.external.size();
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  residuals->resize(static_cast<Eigen::Index>(count) * J);
  if (jacobian) jacobian->resize(residuals->size(), G + E);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t j = first + k;
    const auto cost = model.mechanism->makeJointResidual(model.external, poses[j].cTm, poses[j].joints, whitening[j]);
    const double* parameters[2] = {g.data(), e.data()};
    RowMatrix jg(J, G), je(J, E);
    double* jacobians[2] = {jg.data(), je.data()};
    Eigen::VectorXd r(J);
    if (!cost->Evaluate(parameters, r.data(), jacobian ? jacobians : nullptr)) {
      unreachable->push_back(poses[j].id);
      continue;
    }
    const Eigen::Index row = static_cast<Eigen::Index>(k) * J;
    residuals->segment(row, J) = r;
    if (jacobian) {
      jacobian->block(row, 0, J, G) = jg;
      jacobian->block(row, G, J, E) = je;
    }
  }
}

void throwIfUnreachable(const std::vector<std::string>& unreachable) {
  if (!unreachable.empty())
    throw std::runtime_error("the IKM has no solution (a leg cannot reach the pose) for pose(s) " + joinIds(unreachable));
}

// The same for every pose.
void evaluateAll(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                 const std::vector<Eigen::MatrixXd>& whitening, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian) {
  std::vector<std::string> unreachable;
  evaluateRange(model, poses, whitening, 0, poses.size(), residuals, jacobian, &unreachable);
  throwIfUnreachable(unreachable);
}

std::vector<Eigen::MatrixXd> identityWhitening(const IdentificationModel& model, std::size_t n, double scale) {
  const int J = model.mechanism->jointCount();
  return std::vector<Eigen::MatrixXd>(n, Eigen::MatrixXd::Identity(J, J) * scale);
}

// W_j = L⁻¹ with Σq = J Σ_X Jᵀ = L Lᵀ (pose covariance propagated through the IKM).
std::vector<Eigen::MatrixXd> poseWhitening(const IdentificationModel& model, const std::vector<PoseObservation>& poses) {
  std::vector<Eigen::MatrixXd> out;
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  for (const PoseObservation& p : poses) {
    const Eigen::MatrixXd Jp = model.mechanism->jointJacobianWrtPose(model.external, g, e, p.cTm);
    const Eigen::MatrixXd sigma_q = Jp * (*p.covariance) * Jp.transpose();
    const Eigen::LLT<Eigen::MatrixXd> llt(sigma_q);
    if (llt.info() != Eigen::Success)
      throw std::runtime_error("pose '" + p.id + "': the propagated joint covariance is singular");
    out.emplace_back(llt.matrixL().solve(Eigen::MatrixXd::Identity(sigma_q.rows(), sigma_q.cols())));
  }
  return out;
}

}  // namespace

Eigen::VectorXd IdentificationModel::geometricValues() const { return parameters.values().head(geometricCount()); }
Eigen::VectorXd IdentificationModel::externalValues() const { return parameters.values().tail(external.size()); }
IkmResult IdentificationModel::predictJoints(const PoseVector& cTm) const {
  return mechanism->predictJoints(external, geometricValues(), externalValues(), cTm);
}

IdentificationModel makeIdentificationModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                            const ExternalParameterization& external,
                                            const ParameterSet& external_values) {
  if (!mechanism) throw std::invalid_argument("no mechanism given");
  if (geometric.names() != mechanism->nominal().names())
    throw std::invalid_argument("geometric parameters do not match mechanism " + mechanism->name());
  if (external_values.names() != external.parameters().names())
    throw std::invalid_argument("external parameters do not match the " + externalFormName(external.form()) + " form");
  IdentificationModel model{std::move(mechanism), external, geometric};
  model.parameters.append(external_values);
  return model;
}

IdentificationModel makeInitialModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                     const std::vector<PoseObservation>& poses, ExternalForm form, double z_ME) {
  if (!mechanism) throw std::invalid_argument("no mechanism given");
  ExternalParameterization parameterization(form);
  const ParameterSet external = estimateExternal(*mechanism, geometric.values(), poses, form, parameterization, z_ME);
  return makeIdentificationModel(std::move(mechanism), geometric, parameterization, external);
}

std::vector<std::string> unreachablePoses(const IdentificationModel& model, const std::vector<PoseObservation>& poses) {
  std::vector<std::string> ids;
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  for (const PoseObservation& p : poses)
    if (!model.mechanism->predictJoints(model.external, g, e, p.cTm).reachable()) ids.push_back(p.id);
  return ids;
}

double IdentificationResult::sigmaOf(const std::string& name) const {
  return sigma[static_cast<Eigen::Index>(model.parameters.index(name))];
}

Eigen::MatrixXd identificationJacobian(const IdentificationModel& model, const std::vector<PoseObservation>& poses) {
  validatePoses(poses, model.mechanism->jointCount());
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  evaluateAll(model, poses, identityWhitening(model, poses.size(), 1.0), &r, &J);
  // lazyProduct: no OpenMP-parallel GEMM for these small products (it only spins).
  return J.lazyProduct(model.parameters.expansion());
}

IdentifiabilityReport analyzeIdentifiability(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                                             const IdentifiabilityOptions& options) {
  return analyzeJacobian(identificationJacobian(model, poses), model.parameters.freeNames(), options);
}

namespace {

// ---- Stage 1: input checks and the free parameter set ----

void checkIdentificationInput(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                              const IdentificationOptions& options) {
  if (!initial.mechanism) throw std::invalid_argument("identification: no mechanism");
  const int G = initial.geometricCount();
  const int E = initial.external.size();
  if (static_cast<int>(initial.parameters.size()) != G + E)
    throw std::invalid_argument("identification: the parameter set does not match the model");
  validatePoses(poses, initial.mechanism->jointCount());
  if (!(options.joint_sigma > 0.0 && std::isfinite(options.joint_sigma)))
    throw std::invalid_argument("identification: joint_sigma must be positive and finite");
  if (!(options.loss_scale > 0.0 && std::isfinite(options.loss_scale)))
    throw std::invalid_argument("identification: loss_scale must be positive and finite");
}

// Applies the options' fix/release, checks ties and priors, and that the residuals can
// determine the free parameters at reachable initial values.
void prepareFreeParameters(IdentificationModel& model, const std::vector<PoseObservation>& poses,
                           const IdentificationOptions& options) {
  ParameterSet& params = model.parameters;
  const int G = model.geometricCount();
  const int J = model.mechanism->jointCount();
  params.fix(options.fix);
  for (const std::string& name : options.release) params.setFixed(name, false);
  for (std::size_t i = 0; i < params.size(); ++i)
    if ((params.tieLeader(i) < static_cast<std::size_t>(G)) != (i < static_cast<std::size_t>(G)))
      throw std::invalid_argument("identification: parameter '" + params[i].name +
                                  "' is tied across the geometric and external blocks");
  for (const GaussianPrior& prior : options.priors) {
    params.index(prior.name);
    if (!(std::isfinite(prior.mean) && std::isfinite(prior.sigma) && prior.sigma > 0.0))
      throw std::invalid_argument("prior on '" + prior.name + "': mean and sigma must be finite, sigma > 0");
  }
  const std::size_t free_count = params.freeCount();
  if (free_count == 0) throw std::invalid_argument("identification: no free parameter left (every one is fixed)");
  if (static_cast<std::size_t>(J) * poses.size() + options.priors.size() <= free_count)
    throw std::invalid_argument("identification: " + std::to_string(poses.size()) + " poses give " +
                                std::to_string(J * poses.size()) + " residuals for " + std::to_string(free_count) +
                                " unknowns");
  if (const auto ids = unreachablePoses(model, poses); !ids.empty())
    throw std::runtime_error(
        "the IKM has no solution (a leg cannot reach the pose) at the initial parameters for pose(s) " + joinIds(ids));
}

bool everyPoseHasCovariance(const std::vector<PoseObservation>& poses) {
  bool has_covariances = !poses.empty();
  for (const PoseObservation& p : poses) has_covariances = has_covariances && p.covariance.has_value();
  return has_covariances;
}

// ---- Stage 2: the Ceres solve ----

// The expansion matrix (ambient × free) split into the geometric and external blocks.
struct BlockExpansions {
  Eigen::MatrixXd all, geometric, external;
};

BlockExpansions blockExpansions(const ParameterSet& params, int G, int E) {
  BlockExpansions out;
  out.all = params.expansion();
  std::vector<Eigen::Index> geometric_columns, external_columns;
  for (Eigen::Index k = 0; k < out.all.cols(); ++k) {
    Eigen::Index row = 0;
    out.all.col(k).maxCoeff(&row);
    (row < G ? geometric_columns : external_columns).push_back(k);
  }
  const auto block = [&](const std::vector<Eigen::Index>& columns, Eigen::Index offset, Eigen::Index size) {
    Eigen::MatrixXd b(size, static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < columns.size(); ++k)
      b.col(static_cast<Eigen::Index>(k)) = out.all.col(columns[k]).segment(offset, size);
    return b;
  };
  out.geometric = block(geometric_columns, 0, G);
  out.external = block(external_columns, G, E);
  return out;
}

std::unique_ptr<ceres::LossFunction> makeLoss(const IdentificationOptions& options) {
  if (options.loss == RobustLoss::Huber) return std::make_unique<ceres::HuberLoss>(options.loss_scale);
  if (options.loss == RobustLoss::Cauchy) return std::make_unique<ceres::CauchyLoss>(options.loss_scale);
  return nullptr;
}

std::unique_ptr<ceres::CostFunction> poseCost(const IdentificationModel& model, const PoseObservation& pose,
                                              const Eigen::MatrixXd& whitening) {
  return model.mechanism->makeJointResidual(model.external, pose.cTm, pose.joints, whitening);
}

// The residual blocks over the ambient blocks [ξg, ξe], each with its loss (may be null).
struct AmbientResidual {
  std::unique_ptr<ceres::CostFunction> cost;
  std::unique_ptr<ceres::LossFunction> loss;
  bool geometric = true, external = true;  // the blocks it reads, in that order
};

// Large problems: chunks of poses, each one compressed block (pose_chunk_cost.hpp). A chunk
// of 512 H4 poses is a 2048-row QR in the L2 cache.
void addPoseChunks(std::vector<AmbientResidual>& out, const IdentificationModel& model,
                   const std::vector<PoseObservation>& poses, const std::vector<Eigen::MatrixXd>& whitening,
                   const IdentificationOptions& options) {
  const int J = model.mechanism->jointCount();
  const std::size_t chunk = std::max<std::size_t>(1, detail::RowCompressor::kBlock / static_cast<std::size_t>(J));
  const std::shared_ptr<const ceres::LossFunction> loss = makeLoss(options);
  for (std::size_t first = 0; first < poses.size(); first += chunk) {
    std::vector<std::unique_ptr<ceres::CostFunction>> costs;
    for (std::size_t j = first; j < std::min(poses.size(), first + chunk); ++j)
      costs.push_back(poseCost(model, poses[j], whitening[j]));
    out.push_back({std::make_unique<detail::PoseChunkCost>(std::move(costs), loss, J, model.geometricCount(),
                                                           model.external.size()),
                   nullptr});
  }
}

std::vector<AmbientResidual> poseResiduals(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                                           const std::vector<Eigen::MatrixXd>& whitening,
                                           const IdentificationOptions& options) {
  std::vector<AmbientResidual> out;
  const auto rows = static_cast<Eigen::Index>(poses.size()) * model.mechanism->jointCount();
  if (rows > detail::kLargeProblemRows) {
    addPoseChunks(out, model, poses, whitening, options);
    return out;
  }
  for (std::size_t j = 0; j < poses.size(); ++j)
    out.push_back({poseCost(model, poses[j], whitening[j]), makeLoss(options)});
  return out;
}

void addPriorResiduals(std::vector<AmbientResidual>& out, const ParameterSet& params, int G, int E,
                       const std::vector<GaussianPrior>& priors) {
  for (const GaussianPrior& prior : priors) {
    const int index = static_cast<int>(params.index(prior.name));
    if (index < G)
      out.push_back({std::make_unique<PriorCost>(G, index, prior.mean, prior.sigma), nullptr, true, false});
    else
      out.push_back({std::make_unique<PriorCost>(E, index - G, prior.mean, prior.sigma), nullptr, false, true});
  }
}

// Every parameter free: the ambient blocks as they are; one block entirely fixed: constant.
bool everyBlockFreeOrFixed(const BlockExpansions& expansions) {
  const auto plain = [](const Eigen::MatrixXd& e) { return e.cols() == 0 || e.isIdentity(); };
  return plain(expansions.geometric) && plain(expansions.external);
}

void addAmbientProblem(ceres::Problem& problem, std::vector<AmbientResidual> residuals,
                       const BlockExpansions& expansions, double* g, double* e) {
  for (AmbientResidual& r : residuals) {
    std::vector<double*> blocks;
    if (r.geometric) blocks.push_back(g);
    if (r.external) blocks.push_back(e);
    problem.AddResidualBlock(r.cost.release(), r.loss.release(), blocks);
  }
  if (expansions.geometric.cols() == 0) problem.SetParameterBlockConstant(g);
  if (expansions.external.cols() == 0) problem.SetParameterBlockConstant(e);
}

// Fixed or tied parameters otherwise: one block of the free values (free_parameter_cost.hpp).
void addFreeProblem(ceres::Problem& problem, std::vector<AmbientResidual> residuals,
                    const std::shared_ptr<const detail::FreeParameterMap>& map, int G, double* free) {
  for (AmbientResidual& r : residuals) {
    std::vector<int> offsets;
    if (r.geometric) offsets.push_back(0);
    if (r.external) offsets.push_back(G);
    problem.AddResidualBlock(
        std::make_unique<detail::FreeParameterCost>(std::move(r.cost), map, std::move(offsets)).release(),
        r.loss.release(), free);
  }
}

// One Ceres solve from the result's current values with the given weights.
void solveOnce(IdentificationResult& result, const std::vector<PoseObservation>& poses,
               const std::vector<Eigen::MatrixXd>& whitening, const BlockExpansions& expansions,
               const IdentificationOptions& options) {
  const int G = result.model.geometricCount();
  const int E = result.model.external.size();
  Eigen::VectorXd all = result.model.parameters.values();
  Eigen::VectorXd g = all.head(G), e = all.tail(E), free;
  std::vector<AmbientResidual> residuals = poseResiduals(result.model, poses, whitening, options);
  addPriorResiduals(residuals, result.model.parameters, G, E, options.priors);
  const bool ambient = everyBlockFreeOrFixed(expansions);
  const auto map = std::make_shared<const detail::FreeParameterMap>(expansions.all, all);
  ceres::Problem problem;
  if (ambient) {
    addAmbientProblem(problem, std::move(residuals), expansions, g.data(), e.data());
  } else {
    free = map->freeValues(all);
    addFreeProblem(problem, std::move(residuals), map, G, free.data());
  }

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-10;
  solver.parameter_tolerance = 1e-10;
  solver.gradient_tolerance = 1e-12;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  if (ambient)
    all << g, e;
  else
    map->expand(free.data(), all.data());
  result.model.parameters.setValues(all);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.iterations += static_cast<int>(summary.iterations.size());
  result.solver_report = summary.BriefReport();
}

// Weighted: Σq depends (weakly) on the parameters, so propagate at the start, solve, then
// propagate again at the solution and refine. Returns the weights of the last solve.
std::vector<Eigen::MatrixXd> solveWeighted(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                                           const BlockExpansions& expansions, const IdentificationOptions& options) {
  if (!result.weighted) {
    std::vector<Eigen::MatrixXd> whitening = identityWhitening(result.model, poses.size(), 1.0 / options.joint_sigma);
    solveOnce(result, poses, whitening, expansions, options);
    return whitening;
  }
  std::vector<Eigen::MatrixXd> whitening = poseWhitening(result.model, poses);
  solveOnce(result, poses, whitening, expansions, options);
  std::vector<Eigen::MatrixXd> updated = poseWhitening(result.model, poses);
  double change = 0.0;
  for (std::size_t j = 0; j < poses.size(); ++j)
    change = std::max(change, (updated[j] - whitening[j]).norm() / whitening[j].norm());
  whitening = std::move(updated);
  if (change > 1e-2)
    solveOnce(result, poses, whitening, expansions, options);  // a 1 % weight change moves the solution ≪ σ
  return whitening;
}

// ---- Stage 3: residuals, outliers and covariance at the solution ----

// Whitened residuals r and Jacobian over the free parameters at the solution; fills the
// per-pose residuals (rad) and returns the unwhitened Jacobian for the identifiability report.
struct SolutionJacobian {
  Eigen::VectorXd r;
  Eigen::MatrixXd whitened;  // Jw · expansion
  Eigen::MatrixXd radians;   // W⁻¹ · Jw · expansion
};

// Per-pose residuals (rad, and their χ²) and the RMS joint residual from the whitened r.
void fillPoseResiduals(IdentificationResult& result, const std::vector<PoseObservation>& poses, const Eigen::VectorXd& r) {
  const int J = result.model.mechanism->jointCount();
  result.poses.resize(poses.size());
  double sum_sq_rad = 0.0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Index row = static_cast<Eigen::Index>(j) * J;
    const Eigen::MatrixXd& W = result.whitening[j];
    PoseResidual& pr = result.poses[j];
    pr.id = poses[j].id;
    pr.residual = W.triangularView<Eigen::Lower>().solve(r.segment(row, J));
    pr.chi2 = r.segment(row, J).squaredNorm();
    sum_sq_rad += pr.residual.squaredNorm();
  }
  result.rms_joint_residual = std::sqrt(sum_sq_rad / static_cast<double>(r.size()));
}

SolutionJacobian residualsAtSolution(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                                     const Eigen::MatrixXd& expansion) {
  const int J = result.model.mechanism->jointCount();
  SolutionJacobian out;
  Eigen::MatrixXd Jw;
  evaluateAll(result.model, poses, result.whitening, &out.r, &Jw);
  out.whitened = Jw.lazyProduct(expansion);
  out.radians.resize(out.whitened.rows(), out.whitened.cols());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Index row = static_cast<Eigen::Index>(j) * J;
    out.radians.middleRows(row, J) =
        result.whitening[j].triangularView<Eigen::Lower>().solve(out.whitened.middleRows(row, J));
  }
  fillPoseResiduals(result, poses, out.r);
  return out;
}

// Prior rows (1/σ on the prior's tie leader) join the information matrix.
struct PriorRows {
  Eigen::MatrixXd rows;
  double chi2 = 0.0;
};

PriorRows priorRows(const ParameterSet& params, const std::vector<GaussianPrior>& priors) {
  const std::vector<std::size_t> free_indices = params.freeIndices();
  PriorRows out;
  out.rows =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(priors.size()), static_cast<Eigen::Index>(free_indices.size()));
  for (std::size_t k = 0; k < priors.size(); ++k) {
    const GaussianPrior& prior = priors[k];
    const std::size_t leader = params.tieLeader(params.index(prior.name));
    for (std::size_t f = 0; f < free_indices.size(); ++f)
      if (free_indices[f] == leader)
        out.rows(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(f)) = 1.0 / prior.sigma;
    out.chi2 += std::pow((params.value(prior.name) - prior.mean) / prior.sigma, 2);
  }
  return out;
}

// χ², dof and the outlier test; returns which poses stay in the covariance (under a robust
// loss the outliers' rows are left out).
std::vector<bool> flagOutliers(IdentificationResult& result, const Eigen::VectorXd& r, const PriorRows& prior,
                               const IdentificationOptions& options) {
  const int J = result.model.mechanism->jointCount();
  const auto free_count = static_cast<int>(result.model.parameters.freeCount());
  const double threshold = chi2Quantile(J, options.outlier_probability);
  result.dof = static_cast<int>(r.size() + prior.rows.rows()) - free_count;
  result.chi2 = r.squaredNorm();
  const double scale2_all = (result.chi2 + prior.chi2) / std::max(1, result.dof);
  std::vector<bool> keep(result.poses.size(), true);
  std::vector<double> pose_chi2;
  for (PoseResidual& pr : result.poses) pose_chi2.push_back(pr.chi2);
  // Test each pose at the residual scale achieved (robust), so model misfit is not "outliers".
  result.outlier_scale2 = result.weighted ? robustPoseScale2(pose_chi2, J) : 1.0;
  for (std::size_t j = 0; j < result.poses.size(); ++j) {
    PoseResidual& pr = result.poses[j];
    if (!result.weighted) pr.chi2 /= scale2_all;
    pr.outlier = pr.chi2 / result.outlier_scale2 > threshold;
    if (pr.outlier) {
      result.outliers.push_back(pr.id);
      if (options.loss != RobustLoss::None) keep[j] = pr.used = false;
    }
  }
  return keep;
}

// The whitened system A of the poses kept, priors below, and its χ². Without outliers left
// out or priors, A is the whitened Jacobian itself (no copy of an N×P matrix).
struct KeptSystem {
  bool whole = false;   // A = SolutionJacobian::whitened
  Eigen::MatrixXd own;  // else A
  double chi2 = 0.0;
  const Eigen::MatrixXd& A(const SolutionJacobian& solution) const { return whole ? solution.whitened : own; }
};

// Rows of the kept poses (the priors' not counted) and their χ² with the priors'.
struct KeptRows {
  Eigen::Index rows = 0;
  double chi2 = 0.0;
};

KeptRows keptRows(const Eigen::VectorXd& r, const std::vector<bool>& keep, const PriorRows& prior, int J,
                  std::size_t free_count, std::size_t outlier_count) {
  KeptRows out;
  for (bool k : keep) out.rows += k ? J : 0;
  if (out.rows + prior.rows.rows() <= static_cast<Eigen::Index>(free_count))
    throw std::runtime_error("identification: " + std::to_string(outlier_count) + " of " + std::to_string(keep.size()) +
                             " poses are outliers; the others cannot determine the " + std::to_string(free_count) +
                             " free parameters (check the poses file)");
  out.chi2 = prior.chi2;
  for (std::size_t j = 0; j < keep.size(); ++j)
    if (keep[j]) out.chi2 += r.segment(static_cast<Eigen::Index>(j) * J, J).squaredNorm();
  return out;
}

KeptSystem keptSystem(const SolutionJacobian& solution, const std::vector<bool>& keep, const PriorRows& prior, int J,
                      std::size_t free_count, std::size_t outlier_count) {
  const KeptRows kept = keptRows(solution.r, keep, prior, J, free_count, outlier_count);
  KeptSystem out;
  out.whole = kept.rows == solution.whitened.rows() && prior.rows.rows() == 0;
  out.chi2 = kept.chi2;
  if (out.whole) return out;
  out.own.resize(kept.rows + prior.rows.rows(), solution.whitened.cols());
  Eigen::Index row = 0;
  for (std::size_t j = 0; j < keep.size(); ++j) {
    if (!keep[j]) continue;
    out.own.middleRows(row, J) = solution.whitened.middleRows(static_cast<Eigen::Index>(j) * J, J);
    row += J;
  }
  out.own.bottomRows(prior.rows.rows()) = prior.rows;
  return out;
}

// (AᵀA)⁻¹ (pseudo-inverse when deficient) from the SVD of A (or of R with RᵀR = AᵀA), and the
// factor the fit puts on it: 1 (weighted, absolute) or σ̂²; `rows` = A's row count.
// Returns whether AᵀA is rank deficient.
bool covarianceFromSvd(IdentificationResult& result, const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, Eigen::Index rows,
                       double chi2_kept, const IdentificationOptions& options) {
  const int dof_kept = static_cast<int>(rows) - static_cast<int>(result.model.parameters.freeCount());
  const double scale2 = chi2_kept / std::max(1, dof_kept);
  result.residual_scale = result.weighted ? std::sqrt(scale2) : std::sqrt(scale2) * options.joint_sigma;
  const Eigen::VectorXd& s = svd.singularValues();
  const double cutoff = s.size() ? s[0] * 1e-10 : 0.0;
  Eigen::VectorXd inv_s2 = Eigen::VectorXd::Zero(s.size());
  bool deficient = false;
  for (Eigen::Index k = 0; k < s.size(); ++k) {
    if (s[k] > cutoff)
      inv_s2[k] = 1.0 / (s[k] * s[k]);
    else
      deficient = true;
  }
  const Eigen::MatrixXd scaled_v = svd.matrixV() * inv_s2.asDiagonal();
  result.information_inverse = scaled_v.lazyProduct(svd.matrixV().transpose());
  result.misfit_scale2 = !result.weighted          ? scale2
                         : options.scale_on_misfit ? misfitScale2(chi2_kept, dof_kept, options.outlier_probability)
                                                   : 1.0;
  return deficient;
}

bool covarianceOfKept(IdentificationResult& result, const Eigen::MatrixXd& A, double chi2_kept,
                      const IdentificationOptions& options) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd =
      A.rows() > detail::kLargeProblemRows
          ? Eigen::JacobiSVD<Eigen::MatrixXd>(detail::compressRows(A), Eigen::ComputeThinV)
          : Eigen::JacobiSVD<Eigen::MatrixXd>(A, Eigen::ComputeThinV);
  return covarianceFromSvd(result, svd, A.rows(), chi2_kept, options);
}

// The axis alignment was estimated from the same orientations: its uncertainty enters through
// S = ∂ξ̂/∂δ = −(AᵀA)⁻¹Aᵀ·∂r/∂δ (central differences on the tilts; the alignment term S·Σδ·Sᵀ).
// ∂r/∂δ of the kept rows (`rows`: the kept poses' rows, then zero rows for the priors); an
// empty matrix when the alignment is not estimated (Full form) or exact.
Eigen::MatrixXd alignmentResidualSensitivity(const IdentificationResult& result,
                                             const std::vector<PoseObservation>& poses, const std::vector<bool>& keep,
                                             Eigen::Index rows) {
  const AxisAlignment& alignment = result.model.external.alignment();
  if (result.model.external.form() == ExternalForm::Full || alignment.covariance.isZero()) return {};
  const int J = result.model.mechanism->jointCount();
  constexpr double kStep = 1e-6;  // rad
  Eigen::MatrixXd dr = Eigen::MatrixXd::Zero(rows, 4);
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd rp, rm;
    IdentificationModel shifted = result.model;
    shifted.external = ExternalParameterization(result.model.external.form(),
                                                tiltAlignment(alignment, kStep * Eigen::Vector4d::Unit(k)));
    evaluateAll(shifted, poses, result.whitening, &rp, nullptr);
    shifted.external = ExternalParameterization(result.model.external.form(),
                                                tiltAlignment(alignment, -kStep * Eigen::Vector4d::Unit(k)));
    evaluateAll(shifted, poses, result.whitening, &rm, nullptr);
    Eigen::Index out_row = 0;
    for (std::size_t j = 0; j < poses.size(); ++j) {
      if (!keep[j]) continue;
      dr.block(out_row, k, J, 1) =
          (rp.segment(static_cast<Eigen::Index>(j) * J, J) - rm.segment(static_cast<Eigen::Index>(j) * J, J)) /
          (2.0 * kStep);
      out_row += J;
    }
  }
  return dr;
}

// S = ∂ξ̂/∂δ = −(AᵀA)⁻¹·Aᵀ·∂r/∂δ, from Aᵀ·∂r/∂δ (empty: no alignment term).
void setAlignmentSensitivity(IdentificationResult& result, const Eigen::MatrixXd& At_dr) {
  if (At_dr.size() > 0) result.alignment_sensitivity = -result.information_inverse.lazyProduct(At_dr);
}

// The same from the kept system A (central differences on the tilts).
void setAlignmentSensitivity(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                             const std::vector<bool>& keep, const Eigen::MatrixXd& A) {
  const Eigen::MatrixXd dr = alignmentResidualSensitivity(result, poses, keep, A.rows());
  if (dr.size() > 0) setAlignmentSensitivity(result, Eigen::MatrixXd(A.transpose().lazyProduct(dr)));
}

// Large problems (large_problem.hpp): the Jacobian at the solution is never stored N×P. A pass
// over the residuals gives the per-pose residuals and the outliers, then one pass over the
// Jacobian in 2 048-row blocks feeds the row compressions of the kept whitened system and of
// the unwhitened Jacobian (the same blocks as compressRows of the whole matrices: the same
// R, bit for bit) and accumulates Aᵀ·∂r/∂δ.
struct StreamedSystem {
  detail::RowCompressor information;  // of A (kept poses' whitened rows, then the priors')
  detail::RowCompressor radians;      // of the unwhitened Jacobian, every pose
  Eigen::MatrixXd At_dr;
};

void streamJacobian(StreamedSystem& out, const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                    const Eigen::MatrixXd& expansion, const std::vector<bool>& keep, const Eigen::MatrixXd& dr,
                    bool with_radians) {
  const int J = result.model.mechanism->jointCount();
  const std::size_t block = std::max<std::size_t>(1, detail::RowCompressor::kBlock / J);
  Eigen::Index kept_row = 0;
  for (std::size_t first = 0; first < poses.size(); first += block) {
    const std::size_t count = std::min(block, poses.size() - first);
    Eigen::VectorXd r;
    Eigen::MatrixXd Jw;
    std::vector<std::string> unreachable;
    evaluateRange(result.model, poses, result.whitening, first, count, &r, &Jw, &unreachable);
    throwIfUnreachable(unreachable);
    const Eigen::MatrixXd whitened = Jw.lazyProduct(expansion);
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t j = first + k;
      const auto rows = whitened.middleRows(static_cast<Eigen::Index>(k) * J, J);
      if (with_radians) {
        const Eigen::MatrixXd radians = result.whitening[j].triangularView<Eigen::Lower>().solve(rows);
        out.radians.add(radians);
      }
      if (!keep[j]) continue;
      out.information.add(rows);
      if (dr.size() > 0) out.At_dr += rows.transpose().lazyProduct(dr.middleRows(kept_row, J));
      kept_row += J;
    }
  }
}

// Outliers, (AᵀA)⁻¹, the alignment sensitivity and identifiability; returns whether the system
// is rank deficient.
bool postprocessStreamed(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                         const Eigen::MatrixXd& expansion, const PriorRows& prior, const IdentificationOptions& options) {
  const int J = result.model.mechanism->jointCount();
  Eigen::VectorXd r;
  evaluateAll(result.model, poses, result.whitening, &r, nullptr);
  fillPoseResiduals(result, poses, r);
  const std::vector<bool> keep = flagOutliers(result, r, prior, options);
  const KeptRows kept = keptRows(r, keep, prior, J, result.model.parameters.freeCount(), result.outliers.size());
  const Eigen::MatrixXd dr = alignmentResidualSensitivity(result, poses, keep, kept.rows);
  StreamedSystem system{detail::RowCompressor(expansion.cols()), detail::RowCompressor(expansion.cols()),
                        Eigen::MatrixXd::Zero(expansion.cols(), dr.cols())};
  streamJacobian(system, result, poses, expansion, keep, dr, options.compute_identifiability);
  system.information.add(prior.rows);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(system.information.result(), Eigen::ComputeThinV);
  bool deficient = covarianceFromSvd(result, svd, kept.rows + prior.rows.rows(), kept.chi2, options);
  setAlignmentSensitivity(result, system.At_dr);  // P×0 when there is no alignment term
  result.free_names = result.model.parameters.freeNames();
  if (options.compute_identifiability) {
    result.identifiability = analyzeJacobian(system.radians.result(), result.free_names, options.identifiability);
    deficient = deficient || !result.identifiability.fullRank();
  }
  return deficient;
}

// The same with the whole Jacobian in memory (every demo and test).
bool postprocessDirect(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                       const Eigen::MatrixXd& expansion, const PriorRows& prior, const IdentificationOptions& options) {
  const SolutionJacobian solution = residualsAtSolution(result, poses, expansion);
  const std::vector<bool> keep = flagOutliers(result, solution.r, prior, options);
  const KeptSystem kept = keptSystem(solution, keep, prior, result.model.mechanism->jointCount(),
                                     result.model.parameters.freeCount(), result.outliers.size());
  const Eigen::MatrixXd& A = kept.A(solution);
  bool deficient = covarianceOfKept(result, A, kept.chi2, options);
  setAlignmentSensitivity(result, poses, keep, A);
  result.free_names = result.model.parameters.freeNames();
  if (options.compute_identifiability) {
    result.identifiability = analyzeJacobian(solution.radians, result.free_names, options.identifiability);
    deficient = deficient || !result.identifiability.fullRank();
  }
  return deficient;
}

// A least-squares fit ends with smaller joint residuals than it started from; a robust loss may
// end with larger ones, by down-weighting poses. When, after the fit, more than half the poses
// have a larger joint residual than at the initial values and the RMS over all poses is larger,
// the loss has traded the majority for the few poses that happen to agree: the answer describes
// no robot (joints of another robot or campaign, corrupted poses), however small its σ. Compared
// in joint units (the "before/after" RMS `mire identify` prints): the fit's whitening moves with the
// parameters, and the weights of an absurd geometry are as absurd as the geometry.
double radiansSquared(const IdentificationResult& result, const Eigen::VectorXd& whitened, std::size_t pose) {
  const int J = result.model.mechanism->jointCount();
  const Eigen::VectorXd r = whitened.segment(static_cast<Eigen::Index>(pose) * J, J);
  return result.whitening[pose].triangularView<Eigen::Lower>().solve(r).squaredNorm();
}

void checkRobustFitKeptMostPoses(const IdentificationModel& initial, const IdentificationResult& result,
                                 const std::vector<PoseObservation>& poses, const IdentificationOptions& options) {
  if (options.loss == RobustLoss::None || poses.empty()) return;
  Eigen::VectorXd before, after;
  std::vector<std::string> unreachable_before;
  evaluateRange(initial, poses, result.whitening, 0, poses.size(), &before, nullptr, &unreachable_before);
  if (!unreachable_before.empty()) return;  // the start is not comparable pose by pose
  evaluateAll(result.model, poses, result.whitening, &after, nullptr);
  std::size_t worse = 0;
  double sum_before = 0.0, sum_after = 0.0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const double b = radiansSquared(result, before, j), a = radiansSquared(result, after, j);
    worse += a > b ? 1 : 0;
    sum_before += b;
    sum_after += a;
  }
  if (2 * worse <= poses.size() || sum_after <= sum_before) return;
  const double rows = static_cast<double>(before.size());
  const std::vector<Unit> units = initial.mechanism->jointUnits();
  const bool one_unit = std::all_of(units.begin(), units.end(), [&](Unit u) { return u == units.front(); });
  const std::string unit = !one_unit ? "(joint units)" : units.front() == Unit::Radian ? "rad" : "m";
  throw PosesRejectedError(
      "the robust fit gave up most poses: " + std::to_string(worse) + " of " + std::to_string(poses.size()) +
      " fit worse than with the initial parameters (more than half is refused) and the joint residual RMS rose from " +
      support::formatMessageNumber(std::sqrt(sum_before / rows)) + " to " +
      support::formatMessageNumber(std::sqrt(sum_after / rows)) + " " + unit +
      ": the poses and joints do not describe one robot of this model (joints of another robot or campaign, "
      "poses of another target or corrupted?)");
}

}  // namespace

// Preprocess (checks, free set, weights) / minimise (Ceres) / postprocess (outliers,
// covariance, alignment sensitivity, identifiability), as Ceres cuts a solve; then the fit's own
// covariance terms (the fit's, the alignment's) summed into σ.
IdentificationResult identify(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                              const IdentificationOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  checkIdentificationInput(initial, poses, options);
  IdentificationResult result;
  result.model = initial;
  prepareFreeParameters(result.model, poses, options);
  result.weighted = options.use_pose_covariances && everyPoseHasCovariance(poses);
  const BlockExpansions expansions =
      blockExpansions(result.model.parameters, initial.geometricCount(), initial.external.size());

  result.whitening = solveWeighted(result, poses, expansions, options);
  checkRobustFitKeptMostPoses(initial, result, poses, options);

  const PriorRows prior = priorRows(result.model.parameters, options.priors);
  const auto rows = static_cast<Eigen::Index>(poses.size()) * initial.mechanism->jointCount();
  result.rank_deficient = rows > detail::kLargeProblemRows
                              ? postprocessStreamed(result, poses, expansions.all, prior, options)
                              : postprocessDirect(result, poses, expansions.all, prior, options);
  setCovarianceTerms(result, fitCovarianceTerms(result));
  result.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace mire::mechanism
