#pragma once
// MechanismAdapter<Kinematics>: turns a small templated kinematics struct into a Mechanism
// with autodiff Ceres cost functions, pose Jacobians and a numerical FKM. A new mechanism
// only writes the struct:
//
//   struct MyKinematics {
//     static constexpr int kGeometric = ...;  // geometric parameter count
//     static constexpr int kJoints = ...;     // actuated joints
//     static constexpr int kPoseDof = ...;    // effector degrees of freedom
//     static constexpr MotionType kMotion = ...;
//     static constexpr Unit kJointUnit = ...;  // Radian (revolute) or Metre (prismatic)
//     std::string name() const;
//     std::vector<std::string> poseComponentNames() const;
//     std::vector<Unit> poseComponentUnits() const;
//     Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const;
//     Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const;
//     template <class T> void poseToTransform(const T* pose, T* R, T* t) const;  // R col-major
//     // IKM at bTe = (R, t); returns a bit mask of unreachable joints (0: all reachable).
//     template <class T> int inverseKinematics(const T* geometric, const T* R, const T* t,
//                                              T* joints) const;
//   };
//   auto mechanism = std::make_unique<MechanismAdapter<MyKinematics>>(MyKinematics{}, nominal);
#include <ceres/autodiff_cost_function.h>
#include <ceres/ceres.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/mechanism.hpp"

namespace mire::mechanism {

namespace detail {

// Kinematics that declare joint strokes: bool inStroke(const double* g, int joint, double q).
template <class K, class = void>
struct HasStroke : std::false_type {};
template <class K>
struct HasStroke<K, std::void_t<decltype(std::declval<const K&>().inStroke(static_cast<const double*>(nullptr), 0, 0.0))>>
    : std::true_type {};

// Kinematics with observable legs: bool legSegments(const double* g, const Eigen::Isometry3d& bTe,
// std::vector<LegSegment>* out) (false where the pose is unreachable), and kLegs.
template <class K, class = void>
struct HasLegs : std::false_type {};
template <class K>
struct HasLegs<K, std::void_t<decltype(std::declval<const K&>().legSegments(
                      static_cast<const double*>(nullptr), std::declval<const Eigen::Isometry3d&>(),
                      static_cast<std::vector<LegSegment>*>(nullptr)))>> : std::true_type {};

inline std::vector<int> unreachableList(int mask, int joints) {
  std::vector<int> list;
  for (int i = 0; i < joints; ++i)
    if (mask & (1 << i)) list.push_back(i);
  return list;
}

// Residual W·(q̄ − f(X(ξe, cTm), ξg)) of one pose (eq. 4), parameter blocks [ξg, ξe].
template <class K>
struct JointResidualFunctor {
  K kinematics;
  ExternalParameterization external;
  ExternalParameterization::PreparedPose pose;  // measured cTm, prepared once
  Eigen::Matrix<double, K::kJoints, 1> joints;
  Eigen::Matrix<double, K::kJoints, K::kJoints> whitening;

  template <class T>
  bool operator()(const T* geometric, const T* ext, T* residual) const {
    T R[9], t[3], q[K::kJoints];
    external.effectorInBase(ext, pose, R, t);
    if (kinematics.inverseKinematics(geometric, R, t, q) != 0) return false;
    T error[K::kJoints];
    for (int i = 0; i < K::kJoints; ++i) error[i] = T(joints[i]) - q[i];
    for (int r = 0; r < K::kJoints; ++r) {
      residual[r] = T(0);
      for (int c = 0; c < K::kJoints; ++c) residual[r] += whitening(r, c) * error[c];
    }
    return true;
  }
};

// f(X(ξe, cTm), ξg) as a function of cTm only, for ∂f/∂cTm.
template <class K>
struct PoseJointFunctor {
  K kinematics;
  ExternalParameterization external;
  Eigen::VectorXd geometric;
  Eigen::VectorXd ext;

  template <class T>
  bool operator()(const T* pose, T* q) const {
    T g[K::kGeometric];
    for (int k = 0; k < K::kGeometric; ++k) g[k] = T(geometric[k]);
    std::vector<T> e(static_cast<std::size_t>(ext.size()));
    for (Eigen::Index k = 0; k < ext.size(); ++k) e[static_cast<std::size_t>(k)] = T(ext[k]);
    T R[9], t[3];
    external.effectorInBase(e.data(), pose, R, t);
    return kinematics.inverseKinematics(g, R, t, q) == 0;
  }
};

// q(X) − q̄ for the FKM.
template <class K>
struct FkmFunctor {
  K kinematics;
  Eigen::Matrix<double, K::kGeometric, 1> geometric;
  Eigen::Matrix<double, K::kJoints, 1> joints;

  template <class T>
  bool operator()(const T* pose, T* residual) const {
    T g[K::kGeometric];
    for (int k = 0; k < K::kGeometric; ++k) g[k] = T(geometric[k]);
    T R[9], t[3], q[K::kJoints];
    kinematics.poseToTransform(pose, R, t);
    if (kinematics.inverseKinematics(g, R, t, q) != 0) return false;
    for (int i = 0; i < K::kJoints; ++i) residual[i] = q[i] - T(joints[i]);
    return true;
  }
};

}  // namespace detail

template <class K>
class MechanismAdapter final : public Mechanism {
 public:
  MechanismAdapter(K kinematics, ParameterSet nominal)
      : kinematics_(std::move(kinematics)), nominal_(std::move(nominal)) {
    if (static_cast<int>(nominal_.size()) != K::kGeometric)
      throw std::invalid_argument(kinematics_.name() + ": nominal parameter count " + std::to_string(nominal_.size()) +
                                  " != " + std::to_string(K::kGeometric));
  }

  const K& kinematics() const { return kinematics_; }

  std::string name() const override { return kinematics_.name(); }
  int jointCount() const override { return K::kJoints; }
  std::vector<Unit> jointUnits() const override {
    return std::vector<Unit>(static_cast<std::size_t>(K::kJoints), K::kJointUnit);
  }
  MotionType motionType() const override { return K::kMotion; }
  int poseDof() const override { return K::kPoseDof; }
  std::vector<std::string> poseComponentNames() const override { return kinematics_.poseComponentNames(); }
  std::vector<Unit> poseComponentUnits() const override { return kinematics_.poseComponentUnits(); }
  ParameterSet nominal() const override { return nominal_; }

  Eigen::Isometry3d poseToTransform(const Eigen::VectorXd& pose) const override {
    checkSize(pose, K::kPoseDof, "pose");
    double R[9], t[3];
    kinematics_.poseToTransform(pose.data(), R, t);
    Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
    bTe.linear() = Eigen::Map<const Eigen::Matrix3d>(R);
    bTe.translation() = Eigen::Map<const Eigen::Vector3d>(t);
    return bTe;
  }
  Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const override {
    return kinematics_.transformToPose(bTe);
  }
  Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const override {
    checkSize(geometric, K::kGeometric, "geometric parameter vector");
    return kinematics_.referencePose(geometric);
  }

  IkmResult inverseKinematics(const Eigen::VectorXd& geometric, const Eigen::Isometry3d& bTe) const override {
    checkSize(geometric, K::kGeometric, "geometric parameter vector");
    const Eigen::Matrix3d R = bTe.linear();
    const Eigen::Vector3d t = bTe.translation();
    IkmResult result;
    result.joints.resize(K::kJoints);
    const int mask = kinematics_.inverseKinematics(geometric.data(), R.data(), t.data(), result.joints.data());
    markUnreachable(mask, result);
    if constexpr (detail::HasStroke<K>::value)
      for (int i = 0; i < K::kJoints; ++i)
        if (!(mask & (1 << i)) && !kinematics_.inStroke(geometric.data(), i, result.joints[i]))
          result.out_of_stroke_joints.push_back(i);
    return result;
  }

  FkmResult forwardKinematics(const Eigen::VectorXd& geometric, const Eigen::VectorXd& joints,
                              const Eigen::VectorXd& initial_pose, const FkmOptions& options) const override {
    checkSize(geometric, K::kGeometric, "geometric parameter vector");
    checkSize(joints, K::kJoints, "joint vector");
    checkSize(initial_pose, K::kPoseDof, "initial pose");
    FkmResult result;
    result.pose = initial_pose;
    auto functor = std::make_unique<detail::FkmFunctor<K>>();
    functor->kinematics = kinematics_;
    functor->geometric = geometric;
    functor->joints = joints;
    {
      double residual[K::kJoints];
      if (!(*functor)(result.pose.data(), residual)) {
        result.message = "the IKM is unreachable at the initial pose";
        result.max_joint_error = std::numeric_limits<double>::infinity();
        return result;
      }
    }
    ceres::Problem problem;
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<detail::FkmFunctor<K>, K::kJoints, K::kPoseDof>(functor.release()), nullptr,
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
      result.message = "the IKM is unreachable at the final pose";
      result.max_joint_error = std::numeric_limits<double>::infinity();
      return result;
    }
    result.max_joint_error = (check.joints - joints).cwiseAbs().maxCoeff();
    result.bTe = poseToTransform(result.pose);
    result.converged = result.max_joint_error < options.joint_tolerance;
    if (!result.converged)
      result.message = "no pose reproduces the joints (max joint error " + std::to_string(result.max_joint_error) +
                       " " + unitName(K::kJointUnit) + " after " + std::to_string(result.iterations) + " iterations)";
    return result;
  }

  IkmResult predictJoints(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                          const Eigen::VectorXd& external_values, const PoseVector& cTm) const override {
    checkSize(external_values, external.size(), "external parameter vector");
    return inverseKinematics(geometric, external.effectorInBase(external_values, cTm));
  }

  Eigen::MatrixXd jointJacobianWrtPose(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                                       const Eigen::VectorXd& external_values, const PoseVector& cTm) const override {
    checkSize(geometric, K::kGeometric, "geometric parameter vector");
    checkSize(external_values, external.size(), "external parameter vector");
    auto functor = std::make_unique<detail::PoseJointFunctor<K>>(
        detail::PoseJointFunctor<K>{kinematics_, external, geometric, external_values});
    ceres::AutoDiffCostFunction<detail::PoseJointFunctor<K>, K::kJoints, 6> cost(functor.release());
    double q[K::kJoints];
    Eigen::Matrix<double, K::kJoints, 6, Eigen::RowMajor> jacobian;
    double* jacobians[1] = {jacobian.data()};
    const double* parameters[1] = {cTm.data()};
    if (!cost.Evaluate(parameters, q, jacobians))
      throw std::runtime_error(name() + ": pose unreachable while propagating its covariance");
    return jacobian;
  }

  std::unique_ptr<ceres::CostFunction> makeJointResidual(const ExternalParameterization& external,
                                                         const PoseVector& cTm, const Eigen::VectorXd& measured_joints,
                                                         const Eigen::MatrixXd& whitening) const override {
    checkSize(measured_joints, K::kJoints, "joint vector");
    if (whitening.rows() != K::kJoints || whitening.cols() != K::kJoints)
      throw std::invalid_argument(name() + ": whitening matrix must be " + std::to_string(K::kJoints) + "x" +
                                  std::to_string(K::kJoints));
    auto functor = std::make_unique<detail::JointResidualFunctor<K>>(
        detail::JointResidualFunctor<K>{kinematics_, external, external.prepare(cTm), measured_joints, whitening});
    switch (external.form()) {
      case ExternalForm::AxisAligned:
        return make<8>(std::move(functor));
      case ExternalForm::Full:
      case ExternalForm::CameraOnEffector:
        return make<12>(std::move(functor));
      case ExternalForm::CameraFrame:
        return make<4>(std::move(functor));
    }
    throw std::logic_error("unknown external form");
  }

  int legCount() const override {
    if constexpr (detail::HasLegs<K>::value)
      return K::kJoints;
    else
      return 0;
  }
  std::vector<LegSegment> legSegments(const Eigen::VectorXd& geometric, const Eigen::Isometry3d& bTe) const override {
    std::vector<LegSegment> out;
    if constexpr (detail::HasLegs<K>::value) {
      checkSize(geometric, K::kGeometric, "geometric parameter vector");
      if (!kinematics_.legSegments(geometric.data(), bTe, &out)) out.clear();
    }
    return out;
  }

  std::unique_ptr<Mechanism> clone() const override { return std::make_unique<MechanismAdapter<K>>(*this); }

 private:
  template <int kExternal>
  static std::unique_ptr<ceres::CostFunction> make(std::unique_ptr<detail::JointResidualFunctor<K>> functor) {
    return std::make_unique<ceres::AutoDiffCostFunction<detail::JointResidualFunctor<K>, K::kJoints, K::kGeometric, kExternal>>(
        functor.release());
  }

  void checkSize(const Eigen::VectorXd& v, int expected, const char* what) const {
    if (v.size() != expected)
      throw std::invalid_argument(name() + ": " + what + " has " + std::to_string(v.size()) + " values, expected " +
                                  std::to_string(expected));
    if (!v.allFinite()) throw std::invalid_argument(name() + ": " + what + " has a non-finite value");
  }

  static void markUnreachable(int mask, IkmResult& result) {
    result.unreachable_joints = detail::unreachableList(mask, K::kJoints);
    for (int i : result.unreachable_joints) result.joints[i] = std::numeric_limits<double>::quiet_NaN();
  }

  K kinematics_;
  ParameterSet nominal_;
};

}  // namespace mire::mechanism
