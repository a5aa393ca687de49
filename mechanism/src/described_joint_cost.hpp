#pragma once
// The identification residual of a described mechanism, W·(q̄ − f(X(ξe, cTm), ξg)) (eq. 4),
// with its Jacobian built leg by leg: leg i's reading depends on its own ≤ 14 values and on the
// effector pose only, through w = t + R·p_i − A_i. Each leg's actuation s_i(w, tilt, arm, rod) is
// differentiated once with a Jet over those ≤ 9 inputs, the rest chained by plain products, and
// bTe once over ξe; a dense autodiff over all 54–102 parameters would evaluate every leg once per
// stride of parameters (doc/mechanisms.md, "Described mechanisms").
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

  // A leg (`leg`: indices into the geometric vector), where each of its values sits in its own
  // list (`local`, `global[local.base] = leg.base`...), and the leg re-indexed onto the inputs
  // of its actuation's Jet (`actuation`: tilt, arm, rod in fixed slots after w).
  struct LocalLeg {
    struct Slots {
      int base = -1, tilt = -1, arm = -1, rod = -1, platform = -1, offset = -1, gain = -1;
    };
    DescribedLeg leg, actuation;
    Slots local;
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
