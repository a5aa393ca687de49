#pragma once
// The residuals of the hand-eye least squares (mechanism/hand_eye.hpp; doc/mechanisms.md,
// "Hand-eye calibration"), shared by the solve and the experiment design.
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>
#include <stdexcept>

#include "mire/mechanism/hand_eye.hpp"

namespace mire::mechanism::detail {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// Left Jacobian of SO(3): exp(r + δ) ≈ exp(Jl(r)·δ)·exp(r).
inline Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& r) {
  const double theta = r.norm();
  const Eigen::Matrix3d S = skew(r);
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * S;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / (theta * theta) * S +
         (theta - std::sin(theta)) / (theta * theta * theta) * S * S;
}

// Whitening of the camera residual [t_pred − t_meas; log(R_pred·R_measᵀ)]: the measured
// covariance is over (t, r) with r the rotation vector; a small change δr turns R by the
// left increment Jl(r)·δr, so the residual's covariance is T·Σ·Tᵀ with T = diag(I, Jl(r)).
inline Matrix6 cameraWhitening(const HandEyeObservation& pose) {
  if (!pose.cTm_covariance) {
    Matrix6 W = Matrix6::Zero();
    W.diagonal() << Eigen::Vector3d::Constant(1.0 / pose.robot_sigma.translation_m),
        Eigen::Vector3d::Constant(1.0 / pose.robot_sigma.rotation_rad);
    return W;
  }
  Matrix6 T = Matrix6::Identity();
  T.bottomRightCorner<3, 3>() = leftJacobian(pose.cTm.tail<3>());
  const Matrix6 sigma = T * *pose.cTm_covariance * T.transpose();
  const Eigen::LLT<Matrix6> llt(sigma);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("hand-eye: pose '" + pose.id + "': its covariance is not positive definite");
  return llt.matrixL().solve(Matrix6::Identity());
}

// The measured cTm against the chain through the robot's true pose, bTe = (exp(d_ω)·R̄, t̄ + d_t):
//   camera on the effector: cTm = X⁻¹ · bTe⁻¹ · Z;  camera fixed: cTm = X · bTe · Z.
struct CameraCost {
  HandEyeMounting mounting;
  Eigen::Matrix3d robot_R, measured_R;
  Eigen::Vector3d robot_t, measured_t;
  Matrix6 whitening;

  template <class T>
  bool operator()(const T* x, const T* z, const T* d, T* residual) const {
    using M3 = Eigen::Matrix<T, 3, 3>;
    using V3 = Eigen::Matrix<T, 3, 1>;
    M3 Rx, Rz, Rd;
    ceres::AngleAxisToRotationMatrix(x + 3, ceres::ColumnMajorAdapter3x3(Rx.data()));
    ceres::AngleAxisToRotationMatrix(z + 3, ceres::ColumnMajorAdapter3x3(Rz.data()));
    ceres::AngleAxisToRotationMatrix(d + 3, ceres::ColumnMajorAdapter3x3(Rd.data()));
    const V3 tx(x[0], x[1], x[2]), tz(z[0], z[1], z[2]);
    const M3 Re = Rd * robot_R.cast<T>();
    const V3 te = robot_t.cast<T>() + V3(d[0], d[1], d[2]);
    M3 R;
    V3 t;
    if (mounting == HandEyeMounting::CameraOnEffector) {
      R = Rx.transpose() * Re.transpose() * Rz;
      t = Rx.transpose() * (Re.transpose() * (tz - te) - tx);
    } else {
      R = Rx * Re * Rz;
      t = Rx * (Re * tz + te) + tx;
    }
    const M3 dR = R * measured_R.transpose().cast<T>();
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = t - measured_t.cast<T>();
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(dR.data()), e.data() + 3);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residual);
    whitened = whitening.cast<T>() * e;
    return true;
  }
};

// The robot's pose error d against its stated σ.
struct RobotPrior {
  double sigma_t, sigma_r;
  template <class T>
  bool operator()(const T* d, T* residual) const {
    for (int k = 0; k < 3; ++k) {
      residual[k] = d[k] / sigma_t;
      residual[k + 3] = d[k + 3] / sigma_r;
    }
    return true;
  }
};

}  // namespace mire::mechanism::detail
