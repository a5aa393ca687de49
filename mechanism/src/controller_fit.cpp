// A controller model's parameters fitted to an identified robot (controller_fit.hpp).
#include "mire/mechanism/controller_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>

#include "mire/support/constants.hpp"

namespace mire::mechanism {
namespace {

// Robots drawn for ControllerFit's expected error (its σ is then known to about 1/√(2·100) = 7 %),
// and how many of them the controller is refitted to (the costly part: ~8 ms each for a Delta).
constexpr int kResidualDraws = 100;
constexpr int kResidualRefits = 25;

// F from (rx, ry, rz, tx, ty, tz).
Eigen::Isometry3d frameOf(const double* f) {
  PoseVector v;
  v << f[3], f[4], f[5], f[0], f[1], f[2];
  return toIsometry(v);
}

// F·X as the controller can command it: its own pose components (a Delta keeps the identity
// orientation, an H4 its rotation about z).
Eigen::Isometry3d controllerPose(const Mechanism& controller, const Eigen::Isometry3d& frame,
                                 const Eigen::Isometry3d& pose) {
  return controller.poseToTransform(controller.transformToPose(frame * pose));
}

// IKM_controller(F·X, ξc) − IKM_identified(X) at one pose, over the controller's free parameters
// and the frame F.
struct JointMismatch {
  const Mechanism* mechanism;
  ParameterSet parameters;  // the controller's, fixed values kept
  std::vector<std::size_t> free;
  Eigen::Isometry3d pose;
  Eigen::VectorXd target;
  std::vector<bool> revolute;

  bool operator()(double const* const* blocks, double* residual) const {
    const Eigen::Isometry3d frame = frameOf(blocks[1]);
    Eigen::VectorXd values = parameters.values();
    for (std::size_t k = 0; k < free.size(); ++k) values[static_cast<Eigen::Index>(free[k])] = blocks[0][k];
    ParameterSet p = parameters;
    p.setValues(values);  // re-synchronises tied parameters
    const IkmResult q = mechanism->inverseKinematics(p.values(), controllerPose(*mechanism, frame, pose));
    if (!q.reachable()) return false;
    // Revolute joints agree modulo 2π (the models may take their angles on different branches).
    for (Eigen::Index k = 0; k < target.size(); ++k) {
      const double difference = q.joints[k] - target[k];
      residual[k] = revolute[static_cast<std::size_t>(k)] ? std::remainder(difference, 2.0 * support::kPi) : difference;
    }
    return true;
  }
};

// The covariance of the identified geometry's values (zero where a value has no variance) as a
// factor L, values = ξ̂ + L·z with z standard normal; ties follow their leaders.
struct GeometryDraw {
  std::vector<Eigen::Index> index;  // into the geometric values, one per covariance row used
  std::vector<Eigen::Index> row;    // into PredictionModel::covariance
  Eigen::MatrixXd factor;           // F with F·Fᵀ the submatrix
};

GeometryDraw geometryDraw(const PredictionModel& identified) {
  GeometryDraw draw;
  for (std::size_t k = 0; k < identified.covariance_names.size(); ++k)
    if (identified.geometric.contains(identified.covariance_names[k])) {
      draw.index.push_back(static_cast<Eigen::Index>(identified.geometric.index(identified.covariance_names[k])));
      draw.row.push_back(static_cast<Eigen::Index>(k));
    }
  const auto n = static_cast<Eigen::Index>(draw.row.size());
  Eigen::MatrixXd sub(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b) sub(a, b) = identified.covariance(draw.row[a], draw.row[b]);
  // Eigen-decomposition rather than Cholesky: a gauge leaves the covariance semidefinite.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (sub + sub.transpose()));
  draw.factor = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  return draw;
}

// Frame-free RMS position error of the robot at `values` driven by `commands` towards `wanted`
// (NaN when a pose's FKM fails).
double alignedRms(const Mechanism& m, const Eigen::VectorXd& values, const std::vector<Eigen::VectorXd>& commands,
                  const std::vector<Eigen::VectorXd>& wanted) {
  Eigen::Matrix3Xd attained(3, static_cast<Eigen::Index>(wanted.size())), goal(3, attained.cols());
  for (std::size_t j = 0; j < wanted.size(); ++j) {
    const FkmResult f = m.forwardKinematics(values, commands[j], wanted[j]);
    if (!f.converged) return std::numeric_limits<double>::quiet_NaN();
    attained.col(static_cast<Eigen::Index>(j)) = f.bTe.translation();
    goal.col(static_cast<Eigen::Index>(j)) = m.poseToTransform(wanted[j]).translation();
  }
  const Eigen::Isometry3d align(Eigen::umeyama(attained, goal, false));
  return std::sqrt(((align * attained) - goal).colwise().squaredNorm().mean());
}

// The controller's free parameters and frame fitted to joint targets at `poses`, from `start`.
struct ControllerSolve {
  ParameterSet parameters;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  bool converged = false;
  double final_cost = 0.0;
};

ControllerSolve solveController(const Mechanism& c, const ParameterSet& start, const Eigen::Isometry3d& start_frame,
                                const std::vector<Eigen::Isometry3d>& poses,
                                const std::vector<Eigen::VectorXd>& targets, int max_iterations) {
  ControllerSolve out;
  out.parameters = start;
  const std::vector<std::size_t> free = start.freeIndices();
  std::vector<double> x;
  for (std::size_t k : free) x.push_back(start[k].value);
  const PoseVector f0 = toPoseVector(start_frame);
  std::array<double, 6> frame{f0[3], f0[4], f0[5], f0[0], f0[1], f0[2]};  // rx, ry, rz, tx, ty, tz
  std::vector<bool> revolute;
  for (Unit u : c.jointUnits()) revolute.push_back(u == Unit::Radian);
  ceres::Problem problem;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    auto cost = std::make_unique<ceres::DynamicNumericDiffCostFunction<JointMismatch, ceres::CENTRAL>>(
        new JointMismatch{&c, start, free, poses[j], targets[j], revolute});
    cost->AddParameterBlock(static_cast<int>(x.size()));
    cost->AddParameterBlock(6);
    cost->SetNumResiduals(c.jointCount());
    problem.AddResidualBlock(cost.release(), nullptr, x.data(), frame.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out.converged = summary.IsSolutionUsable();
  out.final_cost = summary.final_cost;
  Eigen::VectorXd values = start.values();
  for (std::size_t k = 0; k < free.size(); ++k) values[static_cast<Eigen::Index>(free[k])] = x[k];
  out.parameters.setValues(values);
  out.frame = frameOf(frame.data());
  return out;
}

// The controller's joint commands for poses X (identified frame); false when one is unreachable.
bool commandsOf(const Mechanism& c, const ParameterSet& parameters, const Eigen::Isometry3d& frame,
                const std::vector<Eigen::VectorXd>& wanted, const Mechanism& id, std::vector<Eigen::VectorXd>& commands) {
  commands.clear();
  for (const Eigen::VectorXd& X : wanted) {
    const IkmResult q = c.inverseKinematics(parameters.values(), controllerPose(c, frame, id.poseToTransform(X)));
    if (!q.reachable()) return false;
    commands.push_back(q.joints);
  }
  return true;
}

// t_s below: the controller refitted to the drawn robot's joints, run on the identified robot.
std::optional<double> refittedRms(const PredictionModel& identified, const Mechanism& c, const ControllerFit& fit,
                                  const ParameterSet& drawn, const std::vector<Eigen::Isometry3d>& poses,
                                  const std::vector<Eigen::VectorXd>& wanted) {
  const Mechanism& id = *identified.mechanism;
  std::vector<Eigen::VectorXd> targets;
  for (const Eigen::Isometry3d& T : poses) {
    const IkmResult q = id.inverseKinematics(drawn.values(), T);
    if (!q.reachable()) return std::nullopt;
    targets.push_back(q.joints);
  }
  const ControllerSolve refit = solveController(c, fit.parameters, fit.frame, poses, targets, 20);
  std::vector<Eigen::VectorXd> commands;
  if (!refit.converged || !commandsOf(c, refit.parameters, refit.frame, wanted, id, commands)) return std::nullopt;
  const double t = alignedRms(id, identified.geometric.values(), commands, wanted);
  return std::isfinite(t) ? std::optional<double>(t) : std::nullopt;
}

// ControllerFit::expected_rms_position_error and its σ (doc/accuracy.md, "Controller model"), from
// paired draws δ of the identified geometry's covariance (a fixed seed: the same files give the same
// numbers). The robot is ξ = ξ̂ − ε, ε the identification's error, and the controller was fitted
// to ξ̂. To first order, with p the error ξ̂ makes under the fitted commands, G the effect of the
// geometry on the reached positions and P the projector on what the controller cannot represent:
// the robot's error is p − G·ε, and p = a + P·G·ε, a the error the controller leaves on ξ.
//  - d_s = p + G·δ (the robot ξ̂ + δ under the fitted commands) spreads as the robot's error does,
//    but E‖d‖² exceeds E‖p − G·ε‖² by 2·tr(P·G·Gᵀ·P): p already holds P·G·ε once.
//  - t_s = p − (I − P)·G·δ (the controller refitted to ξ̂ + δ, run on ξ̂): E‖d‖² − E‖t‖² is that
//    trace, which no closed form needs (paired with the first `refits` draws: their difference
//    varies far less than either).
// The draws' ‖d_s‖² less twice the trace give the expected RMS and its spread.
void addResidualSpread(const PredictionModel& identified, const Mechanism& c,
                       const std::vector<Eigen::VectorXd>& wanted, int draws, int refits, ControllerFit& fit) {
  if (identified.covariance.size() == 0 || wanted.size() < 3) return;
  const Mechanism& id = *identified.mechanism;
  std::vector<Eigen::VectorXd> commands;
  if (!commandsOf(c, fit.parameters, fit.frame, wanted, id, commands)) return;
  std::vector<Eigen::Isometry3d> poses;
  for (const Eigen::VectorXd& X : wanted) poses.push_back(id.poseToTransform(X));
  const GeometryDraw draw = geometryDraw(identified);
  std::mt19937_64 rng(20261126);
  std::normal_distribution<double> normal;
  std::vector<double> fixed_ms, paired_difference;
  for (int s = 0; s < draws; ++s) {
    Eigen::VectorXd z(draw.factor.cols());
    for (Eigen::Index k = 0; k < z.size(); ++k) z[k] = normal(rng);
    const Eigen::VectorXd delta = draw.factor * z;
    Eigen::VectorXd values = identified.geometric.values();
    for (std::size_t k = 0; k < draw.index.size(); ++k) values[draw.index[k]] += delta[static_cast<Eigen::Index>(k)];
    ParameterSet drawn = identified.geometric;
    drawn.setValues(values);  // re-synchronises tied parameters
    const double d = alignedRms(id, drawn.values(), commands, wanted);
    if (!std::isfinite(d)) continue;
    fixed_ms.push_back(d * d);
    if (static_cast<int>(paired_difference.size()) >= refits) continue;
    const std::optional<double> t = refittedRms(identified, c, fit, drawn, poses, wanted);
    if (t) paired_difference.push_back(d * d - *t * *t);
  }
  if (fixed_ms.size() < 2 || paired_difference.empty()) return;
  const auto mean = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())).mean();
  };
  const double unrepresentable = std::max(0.0, mean(paired_difference));
  Eigen::VectorXd rms(static_cast<Eigen::Index>(fixed_ms.size()));
  for (std::size_t k = 0; k < fixed_ms.size(); ++k)
    rms[static_cast<Eigen::Index>(k)] = std::sqrt(std::max(0.0, fixed_ms[k] - 2.0 * unrepresentable));
  fit.draws = static_cast<int>(rms.size());
  fit.expected_rms_position_error = rms.mean();
  fit.sigma_rms_position_error =
      std::sqrt((rms.array() - rms.mean()).square().sum() / static_cast<double>(rms.size() - 1));
}

}  // namespace

Eigen::VectorXd controllerCommand(const Mechanism& controller, const Eigen::Isometry3d& frame,
                                  const Eigen::Isometry3d& pose) {
  return controller.transformToPose(frame * pose);
}

ControllerFit fitControllerModel(const PredictionModel& identified, const RegisteredModel& controller,
                                 const std::vector<Eigen::VectorXd>& workspace) {
  const Mechanism& id = *identified.mechanism;
  const Mechanism& c = *controller.mechanism;
  if (id.jointCount() != c.jointCount() || id.poseComponentNames() != c.poseComponentNames())
    throw std::invalid_argument("the controller model " + controller.name + " does not drive the same joints and pose " +
                                "components as the identified " + identified.model_name);
  ControllerFit fit;
  std::vector<Eigen::VectorXd> used, targets;
  std::vector<Eigen::Isometry3d> poses;
  for (const Eigen::VectorXd& pose : workspace) {
    const Eigen::Isometry3d T = id.poseToTransform(pose);
    const IkmResult target = id.inverseKinematics(identified.geometric.values(), T);
    if (!target.reachable() || !c.inverseKinematics(controller.nominal.values(), T).reachable()) continue;
    used.push_back(pose);
    poses.push_back(T);
    targets.push_back(target.joints);
  }
  if (used.empty()) throw std::invalid_argument("no workspace pose is reachable by both models");
  const ControllerSolve solve =
      solveController(c, controller.nominal, Eigen::Isometry3d::Identity(), poses, targets, 200);
  fit.converged = solve.converged;
  fit.parameters = solve.parameters;
  fit.frame = solve.frame;
  fit.poses = static_cast<int>(used.size());
  fit.rms_joint_residual = std::sqrt(2.0 * solve.final_cost / (static_cast<double>(used.size()) * c.jointCount()));
  // Where the identified robot goes with the fitted controller's commands.
  double sum_sq = 0.0;
  int counted = 0;
  std::vector<Eigen::VectorXd> reached;
  for (const Eigen::VectorXd& pose : used) {
    const IkmResult q =
        c.inverseKinematics(fit.parameters.values(), controllerPose(c, fit.frame, id.poseToTransform(pose)));
    if (!q.reachable()) continue;
    const FkmResult f = id.forwardKinematics(identified.geometric.values(), q.joints, pose);
    if (!f.converged) continue;
    reached.push_back(pose);
    const double e = (f.bTe.translation() - id.poseToTransform(pose).translation()).norm();
    sum_sq += e * e;
    ++counted;
    if (e >= fit.max_position_error) {
      fit.max_position_error = e;
      fit.worst_pose = pose;
    }
  }
  fit.rms_position_error = counted > 0 ? std::sqrt(sum_sq / counted) : 0.0;
  if (fit.converged) addResidualSpread(identified, c, reached, kResidualDraws, kResidualRefits, fit);
  return fit;
}

}  // namespace mire::mechanism
