// The Mechanism of a description file (described.hpp; doc/mechanisms.md, "Described mechanisms").
// The geometric parameter count depends on the file: the identification residual is built leg by
// leg (described_joint_cost.hpp); the FKM and ∂q/∂cTm have fixed pose sizes (3 or 6) and use
// ceres::AutoDiffCostFunction with a dynamic residual count.
#include <ceres/autodiff_cost_function.h>
#include <ceres/ceres.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "described_joint_cost.hpp"
#include "described_kinematics.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/external.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using detail::DescribedKinematics;

std::vector<int> unreachableList(int mask, std::size_t joints) {
  std::vector<int> list;
  for (std::size_t i = 0; i < joints; ++i)
    if (mask & (1 << i)) list.push_back(static_cast<int>(i));
  return list;
}

// The legs whose reading lies outside their declared stroke (a revolute reading taken in the turn
// nearest the stroke's middle: the IKM's atan2 gives it only modulo 2π).
std::vector<int> outOfStrokeList(const MechanismDescription& description, const Eigen::VectorXd& joints) {
  std::vector<int> list;
  for (std::size_t i = 0; i < description.legs.size(); ++i) {
    const LegDescription& leg = description.legs[i];
    const double q = joints[static_cast<Eigen::Index>(i)];
    if (!leg.stroke || !std::isfinite(q)) continue;
    const Eigen::Vector2d& stroke = *leg.stroke;
    const double turn = 2.0 * support::kPi;
    const double reading =
        leg.actuator == LegActuator::Revolute ? q - turn * std::round((q - 0.5 * (stroke[0] + stroke[1])) / turn) : q;
    if (reading < stroke[0] || reading > stroke[1]) list.push_back(static_cast<int>(i));
  }
  return list;
}

// f(X(ξe, cTm), ξg) as a function of cTm only, for ∂f/∂cTm.
struct PoseJoints {
  DescribedKinematics kinematics;
  ExternalParameterization external;
  Eigen::VectorXd geometric, ext;

  template <class T>
  bool operator()(const T* pose, T* q) const {
    std::vector<T> g(geometric.data(), geometric.data() + geometric.size());
    std::vector<T> e(ext.data(), ext.data() + ext.size());
    T R[9], t[3];
    external.effectorInBase(e.data(), pose, R, t);
    return kinematics.inverseKinematics(g.data(), R, t, q) == 0;
  }
};

// q(X) − q̄ for the FKM.
struct FkmResidual {
  DescribedKinematics kinematics;
  Eigen::VectorXd geometric, joints;

  template <class T>
  bool operator()(const T* pose, T* residual) const {
    std::vector<T> g(geometric.data(), geometric.data() + geometric.size());
    T R[9], t[3];
    kinematics.poseToTransform(pose, R, t);
    if (kinematics.inverseKinematics(g.data(), R, t, residual) != 0) return false;
    for (Eigen::Index i = 0; i < joints.size(); ++i) residual[i] -= T(joints[i]);
    return true;
  }
};

template <int kPoseDof>
ceres::CostFunction* fkmCost(FkmResidual functor) {
  const int joints = static_cast<int>(functor.joints.size());
  return new ceres::AutoDiffCostFunction<FkmResidual, ceres::DYNAMIC, kPoseDof>(new FkmResidual(std::move(functor)),
                                                                                joints);
}

class DescribedMechanism final : public Mechanism {
 public:
  explicit DescribedMechanism(const MechanismDescription& description)
      : description_(description),
        kinematics_(detail::describedKinematics(description)),
        nominal_(describedParameters(description)),
        geometric_count_(static_cast<int>(nominal_.size())),
        home_(description.home ? *description.home : detail::describedDefaultHome(description)) {}

  std::string name() const override { return description_.name; }
  int jointCount() const override { return static_cast<int>(description_.legs.size()); }
  std::vector<Unit> jointUnits() const override {
    std::vector<Unit> units;
    for (const LegDescription& leg : description_.legs)
      units.push_back(leg.actuator == LegActuator::Revolute ? Unit::Radian : Unit::Metre);
    return units;
  }
  MotionType motionType() const override { return full() ? MotionType::Spatial : MotionType::Translation; }
  int poseDof() const override { return kinematics_.poseDof(); }
  std::vector<std::string> poseComponentNames() const override {
    if (full()) return {"x", "y", "z", "rx", "ry", "rz"};
    return {"x", "y", "z"};
  }
  std::vector<Unit> poseComponentUnits() const override {
    std::vector<Unit> units(3, Unit::Metre);
    if (full()) units.insert(units.end(), 3, Unit::Radian);
    return units;
  }
  ParameterSet nominal() const override { return nominal_; }

  Eigen::Isometry3d poseToTransform(const Eigen::VectorXd& pose) const override {
    checkSize(pose, poseDof(), "pose");
    double R[9], t[3];
    kinematics_.poseToTransform(pose.data(), R, t);
    Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
    bTe.linear() = Eigen::Map<const Eigen::Matrix3d>(R);
    bTe.translation() = Eigen::Map<const Eigen::Vector3d>(t);
    return bTe;
  }
  Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const override {
    if (!full()) return bTe.translation();
    Eigen::VectorXd pose(6);
    pose << bTe.translation(), rotationVector(bTe.linear());
    return pose;
  }
  Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const override {
    checkSize(geometric, geometric_count_, "geometric parameter vector");
    return home_.head(poseDof());
  }

  IkmResult inverseKinematics(const Eigen::VectorXd& geometric, const Eigen::Isometry3d& bTe) const override {
    checkSize(geometric, geometric_count_, "geometric parameter vector");
    const Eigen::Matrix3d R = bTe.linear();
    const Eigen::Vector3d t = bTe.translation();
    IkmResult result;
    result.joints.resize(jointCount());
    const int mask = kinematics_.inverseKinematics(geometric.data(), R.data(), t.data(), result.joints.data());
    result.unreachable_joints = unreachableList(mask, description_.legs.size());
    for (int i : result.unreachable_joints) result.joints[i] = std::numeric_limits<double>::quiet_NaN();
    result.out_of_stroke_joints = outOfStrokeList(description_, result.joints);
    return result;
  }

  FkmResult forwardKinematics(const Eigen::VectorXd& geometric, const Eigen::VectorXd& joints,
                              const Eigen::VectorXd& initial_pose, const FkmOptions& options) const override;

  IkmResult predictJoints(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                          const Eigen::VectorXd& external_values, const PoseVector& cTm) const override {
    checkSize(external_values, external.size(), "external parameter vector");
    return inverseKinematics(geometric, external.effectorInBase(external_values, cTm));
  }

  Eigen::MatrixXd jointJacobianWrtPose(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                                       const Eigen::VectorXd& external_values, const PoseVector& cTm) const override {
    checkSize(geometric, geometric_count_, "geometric parameter vector");
    checkSize(external_values, external.size(), "external parameter vector");
    const int n = jointCount();
    ceres::AutoDiffCostFunction<PoseJoints, ceres::DYNAMIC, 6> cost(
        new PoseJoints{kinematics_, external, geometric, external_values}, n);
    Eigen::VectorXd q(n);
    Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> jacobian(n, 6);
    double* jacobians[1] = {jacobian.data()};
    const double* parameters[1] = {cTm.data()};
    if (!cost.Evaluate(parameters, q.data(), jacobians))
      throw std::runtime_error(name() + ": pose unreachable while propagating its covariance");
    return jacobian;
  }

  std::unique_ptr<ceres::CostFunction> makeJointResidual(const ExternalParameterization& external,
                                                         const PoseVector& cTm, const Eigen::VectorXd& measured_joints,
                                                         const Eigen::MatrixXd& whitening) const override {
    const int n = jointCount();
    checkSize(measured_joints, n, "joint vector");
    if (whitening.rows() != n || whitening.cols() != n)
      throw std::invalid_argument(name() + ": whitening matrix must be " + std::to_string(n) + "x" + std::to_string(n));
    return std::make_unique<detail::DescribedJointCost>(kinematics_, geometric_count_, external, cTm, measured_joints,
                                                        whitening);
  }

  std::unique_ptr<Mechanism> clone() const override { return std::make_unique<DescribedMechanism>(*this); }

 private:
  bool full() const { return kinematics_.full; }

  void checkSize(const Eigen::VectorXd& v, int expected, const char* what) const {
    if (v.size() != expected)
      throw std::invalid_argument(name() + ": " + what + " has " + std::to_string(v.size()) + " values, expected " +
                                  std::to_string(expected));
    if (!v.allFinite()) throw std::invalid_argument(name() + ": " + what + " has a non-finite value");
  }

  MechanismDescription description_;
  DescribedKinematics kinematics_;
  ParameterSet nominal_;
  int geometric_count_;  // nominal_.size(), without copying the set on every call
  PoseVector home_;
};

FkmResult DescribedMechanism::forwardKinematics(const Eigen::VectorXd& geometric, const Eigen::VectorXd& joints,
                                                const Eigen::VectorXd& initial_pose, const FkmOptions& options) const {
  checkSize(geometric, geometric_count_, "geometric parameter vector");
  checkSize(joints, jointCount(), "joint vector");
  checkSize(initial_pose, poseDof(), "initial pose");
  FkmResult result;
  result.pose = initial_pose;
  FkmResult unreachable = result;
  unreachable.max_joint_error = std::numeric_limits<double>::infinity();
  FkmResidual functor{kinematics_, geometric, joints};
  {
    Eigen::VectorXd residual(jointCount());
    if (!functor(result.pose.data(), residual.data())) {
      unreachable.message = "the IKM is unreachable at the initial pose";
      return unreachable;
    }
  }
  ceres::Problem problem;
  problem.AddResidualBlock(full() ? fkmCost<6>(std::move(functor)) : fkmCost<3>(std::move(functor)), nullptr,
                           result.pose.data());
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-16;
  solver_options.gradient_tolerance = 1e-16;
  solver_options.parameter_tolerance = 1e-14;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  const IkmResult check = inverseKinematics(geometric, poseToTransform(result.pose));
  if (!check.reachable()) {
    unreachable.pose = result.pose;
    unreachable.iterations = result.iterations;
    unreachable.message = "the IKM is unreachable at the final pose";
    return unreachable;
  }
  result.max_joint_error = (check.joints - joints).cwiseAbs().maxCoeff();
  result.bTe = poseToTransform(result.pose);
  result.converged = result.max_joint_error < options.joint_tolerance;
  if (!result.converged)
    result.message = "no pose reproduces the joints (max joint error " + std::to_string(result.max_joint_error) +
                     " after " + std::to_string(result.iterations) + " iterations)";
  return result;
}

}  // namespace

std::unique_ptr<Mechanism> makeDescribedMechanism(const MechanismDescription& description) {
  return std::make_unique<DescribedMechanism>(description);
}

RegisteredModel makeDescribedModel(const MechanismDescription& description) {
  RegisteredModel out;
  out.name = description.name;
  out.mechanism = makeDescribedMechanism(description);
  out.nominal = out.mechanism->nominal();
  out.external_form = ExternalForm::Full;
  return out;
}

RegisteredModel makeDescribedModel(const std::filesystem::path& file) {
  return makeDescribedModel(readMechanismDescription(file));
}

}  // namespace mire::mechanism
