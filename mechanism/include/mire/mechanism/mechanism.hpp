#pragma once
// The mechanism interface (paper §2.1; doc/mechanisms.md): a closed-form inverse kinematic model
// (IKM) q = f(X, ξg) (eq. 1), a numerical forward model (FKM) built on it, and a factory of
// Ceres cost functions for the identification residual ε = q̄ − f(X(ξe), ξg) (eq. 4).
//
// A new mechanism (Delta, Gough–Stewart, ...) does not implement this class by hand: it
// writes a small "kinematics" struct with a templated IKM and wraps it in
// MechanismAdapter<Kinematics> (mechanism_adapter.hpp), which provides autodiff cost
// functions, pose Jacobians and the FKM. The identification core only sees Mechanism.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"

namespace ceres {
class CostFunction;
}

namespace mire::mechanism {

// How the effector moves (doc/mechanisms.md, "Mounting"). It chooses the external
// parametrisation and its data-driven initialisation (external.hpp):
//  - Schoenflies: 3 translations + rotation about one fixed axis (H4): axis alignment;
//  - Translation: the plate keeps the base orientation (Delta): rotation fit from the
//    displacements (Kabsch/Umeyama);
//  - Spatial: full 6 DoF (Gough–Stewart): robot-world hand-eye solve.
enum class MotionType { Schoenflies, Translation, Spatial };
std::string motionTypeName(MotionType type);  // "schoenflies", "translation", "spatial"

// Result of an IKM evaluation. An unreachable pose (no real solution for a leg) lists the
// failing joints: their entries in `joints` are NaN and must never be used silently.
struct IkmResult {
  Eigen::VectorXd joints;               // q [rad or m], size jointCount()
  std::vector<int> unreachable_joints;  // 0-based joint indices
  bool reachable() const { return unreachable_joints.empty(); }
  // Reachable, but outside the joint's stroke (mechanisms that declare one: the
  // Gough–Stewart leg lengths, doc/mechanisms.md); `joints` keeps the value. The
  // identification ignores it (a measured pose was reached); commands must not.
  std::vector<int> out_of_stroke_joints;
  bool withinStroke() const { return out_of_stroke_joints.empty(); }
};

// One leg the camera can see as a rod (doc/legs.md): the axis segment of the cylinder, in the base
// frame [m]. Hexapod (extensible legs): base joint → platform joint; Delta and H4: forearm, elbow →
// effector attachment; described legs: the rod's joint on the actuator side → platform joint.
struct LegSegment {
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
};

struct FkmOptions {
  int max_iterations = 50;
  double joint_tolerance = 1e-10;  // converged when every |q(X) − q̄| is below this [rad or m]
};

// Numerical FKM (Levenberg–Marquardt on the IKM, Ceres): the pose X whose IKM gives q̄.
struct FkmResult {
  Eigen::VectorXd pose;  // X, size poseDof(), mechanism's pose components
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
  bool converged = false;
  int iterations = 0;
  double max_joint_error = 0.0;  // max |q(X) − q̄| at the returned pose
  std::string message;           // why it did not converge, when it did not
};

class Mechanism {
 public:
  virtual ~Mechanism() = default;

  virtual std::string name() const = 0;
  virtual int jointCount() const = 0;
  // Unit of each actuated joint: Radian (revolute) or Metre (prismatic), jointCount() entries.
  virtual std::vector<Unit> jointUnits() const = 0;
  // joints.csv column names q<i>_rad / q<i>_m (doc/file-formats.md, "Joint columns").
  std::vector<std::string> jointColumnNames() const;
  virtual MotionType motionType() const = 0;
  // Number of effector degrees of freedom and their names/units (H4: x, y, z [m], theta [rad]).
  virtual int poseDof() const = 0;
  virtual std::vector<std::string> poseComponentNames() const = 0;
  virtual std::vector<Unit> poseComponentUnits() const = 0;

  // Geometric parameters ξg with nominal values, units and default fixed flags
  // (e.g. d is fixed in H4 model 12 because it has no influence).
  virtual ParameterSet nominal() const = 0;
  int geometricCount() const { return static_cast<int>(nominal().size()); }

  // Pose components <-> effector transform bTe in the base frame.
  virtual Eigen::Isometry3d poseToTransform(const Eigen::VectorXd& pose) const = 0;
  virtual Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const = 0;

  // A pose inside the workspace for these parameters: the FKM's default starting point.
  virtual Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const = 0;

  // IKM (eq. 1) at the effector transform bTe; `geometric` in nominal()'s order.
  virtual IkmResult inverseKinematics(const Eigen::VectorXd& geometric, const Eigen::Isometry3d& bTe) const = 0;

  // FKM by Levenberg–Marquardt on the IKM from `initial_pose` (poseDof() values).
  // Non-convergence (or an unreachable start) is reported in the result, never thrown.
  virtual FkmResult forwardKinematics(const Eigen::VectorXd& geometric, const Eigen::VectorXd& joints,
                                      const Eigen::VectorXd& initial_pose, const FkmOptions& options = {}) const = 0;

  // IKM from a measured target pose through the external parameters (eq. 3 then eq. 1).
  virtual IkmResult predictJoints(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                                  const Eigen::VectorXd& external_values, const PoseVector& cTm) const = 0;

  // ∂f/∂cTm (jointCount() x 6), to propagate a pose covariance: Σq = J Σ_X Jᵀ.
  virtual Eigen::MatrixXd jointJacobianWrtPose(const ExternalParameterization& external, const Eigen::VectorXd& geometric,
                                               const Eigen::VectorXd& external_values, const PoseVector& cTm) const = 0;

  // Ceres cost for one pose: residual W·(q̄ − f(X(ξe, cTm), ξg)) (jointCount() values) over two
  // parameter blocks [ξg (geometricCount()), ξe (ExternalParameterization::size())].
  // `whitening` W is jointCount() x jointCount() (identity, 1/σ, or L⁻¹ with Σq = L Lᵀ).
  // The cost returns false (Ceres rejects the step) where the pose is unreachable.
  virtual std::unique_ptr<ceres::CostFunction> makeJointResidual(const ExternalParameterization& external,
                                                                 const PoseVector& cTm,
                                                                 const Eigen::VectorXd& measured_joints,
                                                                 const Eigen::MatrixXd& whitening) const = 0;

  // The legs whose axes a camera can observe (doc/legs.md), and their segments at the effector
  // transform bTe for these parameters, legCount() entries in joint order. A mechanism without
  // observable legs has none; an unreachable pose returns an empty list.
  virtual int legCount() const { return 0; }
  virtual std::vector<LegSegment> legSegments(const Eigen::VectorXd& /*geometric*/,
                                              const Eigen::Isometry3d& /*bTe*/) const {
    return {};
  }

  virtual std::unique_ptr<Mechanism> clone() const = 0;
};

}  // namespace mire::mechanism
