#pragma once
// The identification residual of a described mechanism, W·(q̄ − f(X(ξe, cTm), ξg)) (eq. 4),
// with its Jacobian built leg by leg: leg i's reading depends on its own ≤ 14 values and on the
// effector pose only, so each leg is differentiated once with a Jet over those values and bTe's
// 12 entries, and bTe once over ξe; a dense autodiff over all 54–102 parameters would evaluate
// every leg once per stride of parameters (doc/mechanisms.md, "Described mechanisms").
#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <vector>

#include "described_kinematics.hpp"
#include "mire/mechanism/external.hpp"

namespace mire::mechanism::detail {

class DescribedJointCost final : public ceres::CostFunction {
 public:
  DescribedJointCost(const DescribedKinematics& kinematics, int geometric_count, ExternalParameterization external,
                     const PoseVector& cTm, Eigen::VectorXd measured_joints, Eigen::MatrixXd whitening);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  // A leg (`leg`: indices into the geometric vector) and the same leg re-indexed onto its own
  // values (`local` reads values[k] = g[global[k]]).
  struct LocalLeg {
    DescribedLeg leg, local;
    std::vector<int> global;
  };

 private:
  // ∂q_i/∂(bTe's R, t) and ∂q_i/∂(leg i's values) at (R, t); false where leg i cannot assemble.
  bool legDerivatives(const LocalLeg& leg, const double* g, const double* R, const double* t, double* q, double* d_pose,
                      double* d_local) const;
  // bTe's 12 entries (R column-major, t) and their derivatives, row-major 12 × E.
  void effectorDerivatives(const double* external, double* Rt, double* d_external) const;

  std::vector<LocalLeg> legs_;
  ExternalParameterization external_;
  ExternalParameterization::PreparedPose pose_;
  Eigen::VectorXd joints_;
  Eigen::MatrixXd whitening_;
  bool translation_ = false;  // a translation platform: R = I whatever X's rotation (described_kinematics.hpp)
};

}  // namespace mire::mechanism::detail
