// Identification with leg observations (leg_identification.hpp, doc/legs.md).
#include "mire/mechanism/leg_identification.hpp"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "leg_identification_cost.hpp"
#include "mire/mechanism/identification_covariance.hpp"

namespace mire::mechanism {

std::string observationsName(Observations observations) {
  switch (observations) {
    case Observations::Target:
      return "target";
    case Observations::Legs:
      return "legs";
    case Observations::Both:
      return "both";
  }
  return "?";
}

Observations parseObservations(const std::string& text) {
  for (Observations o : {Observations::Target, Observations::Legs, Observations::Both})
    if (observationsName(o) == text) return o;
  throw std::invalid_argument("observations '" + text + "': expected target, legs or both");
}

double LegIdentificationResult::sigmaOf(const std::string& name) const {
  return sigma[static_cast<Eigen::Index>(model.parameters.index(name))];
}

Eigen::Isometry3d cameraFromBaseByLegs(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                       const std::vector<LegObservation>& legs) {
  const int n = mechanism.legCount();
  const Eigen::VectorXd ref = mechanism.referencePose(geometric);
  const std::vector<LegSegment> at_ref = mechanism.legSegments(geometric, mechanism.poseToTransform(ref));
  Eigen::VectorXd moved = ref;
  moved[2] += 0.01;
  const std::vector<LegSegment> at_moved = mechanism.legSegments(geometric, mechanism.poseToTransform(moved));
  if (n < 3 || static_cast<int>(at_ref.size()) != n || static_cast<int>(at_moved.size()) != n)
    throw std::invalid_argument(mechanism.name() + ": fewer than three observable legs at the reference pose");
  for (int i = 0; i < n; ++i)
    if ((at_ref[static_cast<std::size_t>(i)].from - at_moved[static_cast<std::size_t>(i)].from).norm() > 1e-9)
      throw std::invalid_argument(mechanism.name() +
                                  ": its legs' base ends move with the pose; a legs-only start needs legs "
                                  "jointed to the base (use the target, --observations both)");
  Eigen::Matrix3Xd model_points(3, n), camera_points(3, n);
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int count = 0;
    for (const LegObservation& o : legs) {
      if (o.leg != i) continue;
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - o.line.direction * o.line.direction.transpose();
      A += P;
      b += P * o.line.closestPointToOrigin();
      ++count;
    }
    if (count < 2)
      throw std::invalid_argument("leg " + std::to_string(i + 1) + " is observed at " + std::to_string(count) +
                                  " pose(s): a legs-only start needs every leg at two poses at least");
    camera_points.col(i) = A.ldlt().solve(b);
    model_points.col(i) = at_ref[static_cast<std::size_t>(i)].from;
  }
  Eigen::Isometry3d cTb = Eigen::Isometry3d::Identity();
  cTb.matrix() = Eigen::umeyama(model_points, camera_points, false);
  return cTb;
}

IdentificationModel makeLegsInitialModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                         const std::vector<LegObservation>& legs) {
  if (!mechanism) throw std::invalid_argument("no mechanism given");
  const Eigen::Isometry3d cTb = cameraFromBaseByLegs(*mechanism, geometric.values(), legs);
  const ExternalParameterization full(ExternalForm::Full);
  ParameterSet external = full.parameters();
  external.setValues(full.valuesFrom(cTb.inverse(), Eigen::Isometry3d::Identity()));
  return makeIdentificationModel(std::move(mechanism), geometric, full, external);
}

std::vector<std::string> legsOnlyGauge(const IdentificationModel& model) {
  std::vector<std::string> names = {"rx_CB", "ry_CB", "rz_CB", "tx_CB", "ty_CB", "tz_CB",
                                    "rx_EM", "ry_EM", "rz_EM", "tx_EM", "ty_EM", "tz_EM"};
  for (const std::string& n : names) model.parameters.index(n);  // throws outside the Full form
  const ParameterSet& p = model.parameters;
  if (model.mechanism->motionType() != MotionType::Spatial || !p.contains("px3")) return names;
  // The effector frame: p1 (translation), p2's z and p3's z (the tilts), and the coordinate of p2
  // that a turn about z through p1 moves most (the other one would leave that turn free).
  const double dx = p.value("px2") - p.value("px1"), dy = p.value("py2") - p.value("py1");
  for (const char* n : {"px1", "py1", "pz1", std::abs(dx) < std::abs(dy) ? "px2" : "py2", "pz2", "pz3"})
    names.emplace_back(n);
  return names;
}

namespace {

struct PreparedPoses {
  std::vector<detail::LegPoseTerms> terms;
  std::vector<Eigen::VectorXd> start;  // X_j
  std::vector<std::string> ids;
};

PreparedPoses preparePoses(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                           const std::vector<LegObservation>& legs, const LegIdentificationOptions& options) {
  const Mechanism& m = *model.mechanism;
  const bool use_target = options.observations != Observations::Legs;
  const bool use_legs = options.observations != Observations::Target;
  std::map<std::string, std::vector<const LegObservation*>> by_pose;
  std::set<std::string> known;
  for (const PoseObservation& p : poses) known.insert(p.id);
  if (use_legs)
    for (const LegObservation& o : legs) {
      if (!known.count(o.pose_id))
        throw std::invalid_argument("leg observation of pose '" + o.pose_id + "': no joints for that pose");
      by_pose[o.pose_id].push_back(&o);
    }
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  PreparedPoses out;
  for (const PoseObservation& p : poses) {
    detail::LegPoseTerms t;
    t.joints = p.joints;
    t.joint_sigma = options.joint_sigma;
    for (const LegObservation* o : by_pose[p.id]) {
      t.legs.push_back(*o);
      const Eigen::LLT<Eigen::Matrix4d> llt(o->covariance);
      t.leg_whitening.emplace_back(llt.matrixL().solve(Eigen::Matrix4d::Identity()));
    }
    if (use_target) {
      if (!p.covariance)
        throw std::invalid_argument("pose '" + p.id + "': target observations need the pose covariance");
      t.cTm = toIsometry(p.cTm);
      t.target_whitening = detail::targetWhitening(p.cTm, *p.covariance);
    }
    if (t.legs.empty() && !t.cTm) continue;  // nothing observed at this pose
    Eigen::VectorXd X;
    if (use_target) {
      X = m.transformToPose(model.external.effectorInBase(e, p.cTm));
    } else {
      const FkmResult fkm = m.forwardKinematics(g, p.joints, m.referencePose(g));
      if (!fkm.converged) throw std::runtime_error("pose '" + p.id + "': no starting pose (" + fkm.message + ")");
      X = fkm.pose;
    }
    out.terms.push_back(std::move(t));
    out.start.push_back(X);
    out.ids.push_back(p.id);
  }
  return out;
}

// The free parameters' information with the poses marginalised (Schur complement of the X blocks).
Eigen::MatrixXd marginalInformation(const Eigen::MatrixXd& A, int P, int D, std::size_t pose_count) {
  const Eigen::MatrixXd H = A.transpose() * A;
  Eigen::MatrixXd S = H.topLeftCorner(P, P);
  for (std::size_t j = 0; j < pose_count; ++j) {
    const Eigen::Index c = P + static_cast<Eigen::Index>(j) * D;
    const Eigen::MatrixXd Hxx = H.block(c, c, D, D);
    const Eigen::MatrixXd Hpx = H.block(0, c, P, D);
    S -= Hpx * Hxx.ldlt().solve(Hpx.transpose());
  }
  return 0.5 * (S + S.transpose());
}

Eigen::MatrixXd denseJacobian(ceres::Problem& problem, const std::vector<double*>& blocks, Eigen::VectorXd* r) {
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = blocks;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  problem.Evaluate(eval, nullptr, &residuals, nullptr, &crs);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[static_cast<std::size_t>(row)]; k < crs.rows[static_cast<std::size_t>(row) + 1]; ++k)
      A(row, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
  *r = Eigen::Map<Eigen::VectorXd>(residuals.data(), static_cast<Eigen::Index>(residuals.size()));
  return A;
}

void fillSigma(LegIdentificationResult& result, const Eigen::MatrixXd& covariance) {
  const ParameterSet& params = result.model.parameters;
  const std::vector<std::size_t> free_indices = params.freeIndices();
  result.sigma = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(params.size()));
  for (std::size_t i = 0; i < params.size(); ++i)
    for (std::size_t f = 0; f < free_indices.size(); ++f)
      if (free_indices[f] == params.tieLeader(i))
        result.sigma[static_cast<Eigen::Index>(i)] =
            std::sqrt(covariance(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(f)));
}

}  // namespace

LegIdentificationResult identifyWithLegs(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                                         const std::vector<LegObservation>& legs,
                                         const LegIdentificationOptions& options) {
  if (!initial.mechanism) throw std::invalid_argument("identification: no mechanism");
  const Mechanism& m = *initial.mechanism;
  validatePoses(poses, m.jointCount());
  if (options.observations != Observations::Target) {
    if (m.legCount() == 0) throw std::invalid_argument(m.name() + ": no observable legs");
    validateLegObservations(legs, m.legCount());
  }
  if (!(options.joint_sigma > 0.0 && std::isfinite(options.joint_sigma)))
    throw std::invalid_argument("identification: joint_sigma must be positive and finite");
  LegIdentificationResult result;
  result.model = initial;
  ParameterSet& params = result.model.parameters;
  params.fix(options.fix);
  for (const std::string& name : options.release) params.setFixed(name, false);
  const int P = static_cast<int>(params.freeCount());
  const int D = m.poseDof();
  if (P == 0) throw std::invalid_argument("identification: no free parameter left (every one is fixed)");

  PreparedPoses prepared = preparePoses(result.model, poses, legs, options);
  auto map = std::make_shared<const detail::FreeParameterMap>(params.expansion(), params.values());
  Eigen::VectorXd free = map->freeValues(params.values());
  int rows = 0;
  for (const detail::LegPoseTerms& t : prepared.terms) {
    rows += t.residualCount(m.jointCount());
    result.leg_rows += 4 * static_cast<int>(t.legs.size());
    result.target_rows += t.cTm ? 6 : 0;
    result.joint_rows += m.jointCount();
  }
  result.dof = rows - P - D * static_cast<int>(prepared.terms.size());
  if (result.dof <= 0)
    throw std::invalid_argument("identification: " + std::to_string(rows) + " residuals for " +
                                std::to_string(P + D * static_cast<int>(prepared.terms.size())) +
                                " unknowns (parameters and poses)");

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<double*> blocks = {free.data()};
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  ordering->AddElementToGroup(free.data(), 1);
  for (std::size_t j = 0; j < prepared.terms.size(); ++j) {
    double* X = prepared.start[j].data();
    problem.AddResidualBlock(detail::makeLegPoseCost(result.model, map, prepared.terms[j]).release(), nullptr,
                             free.data(), X);
    ordering->AddElementToGroup(X, 0);
    blocks.push_back(X);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.linear_solver_ordering = ordering;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-12;
  solver.logging_type = ceres::SILENT;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(summary.iterations.size());

  Eigen::VectorXd ambient(map->ambientCount());
  map->expand(free.data(), ambient.data());
  params.setValues(ambient);
  for (const Eigen::VectorXd& X : prepared.start) result.bTe.push_back(m.poseToTransform(X));

  Eigen::VectorXd r;
  const Eigen::MatrixXd A = denseJacobian(problem, blocks, &r);
  result.chi2 = r.squaredNorm();
  const Eigen::MatrixXd S = marginalInformation(A, P, D, prepared.terms.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  const Eigen::VectorXd s = eig.eigenvalues().cwiseMax(0.0);
  const double cutoff = s.maxCoeff() * 1e-14;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index k = 0; k < s.size(); ++k)
    if (s[k] > cutoff) inv[k] = 1.0 / s[k];
  if (options.scale_on_misfit) result.covariance_scale2 = misfitScale2(result.chi2, result.dof, 1e-3);
  result.covariance = result.covariance_scale2 * eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
  result.free_names = params.freeNames();
  fillSigma(result, result.covariance);
  if (options.compute_identifiability) {
    // A square root of the marginal information: the same column space as the whitened Jacobian.
    const Eigen::MatrixXd root = s.cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
    result.identifiability = analyzeJacobian(root, result.free_names, options.identifiability);
  }
  return result;
}

}  // namespace mire::mechanism
