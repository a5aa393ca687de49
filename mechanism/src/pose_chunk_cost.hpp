#pragma once
// Large identification problems (large_problem.hpp): the poses' residual blocks grouped into
// chunks, each handed to Ceres as one block of P + 1 compressed rows instead of J·K rows.
// For the K poses of a chunk, stacked (each with its robust loss applied as Ceres applies it,
// docs "Modeling Non-linear Least Squares: LossFunction"), the Householder QR of [J̃ r̃] gives
// [R c; 0 d]: the residual (c, d) and the Jacobian (R; 0) have the same cost ½Σρ, gradient
// J̃ᵀr̃ = Rᵀc and Gauss–Newton matrix J̃ᵀJ̃ = RᵀR as the K blocks, so Ceres' Levenberg–Marquardt
// takes the same steps — but its Jacobian is 4K/(P+1) times smaller and stays in the caches,
// which the per-pose Jacobian of 10⁵ poses (60 MB) does not.
#include <ceres/ceres.h>

#include <memory>
#include <vector>

namespace mire::mechanism::detail {

class PoseChunkCost final : public ceres::CostFunction {
 public:
  // `poses`: the per-pose costs over the same two parameter blocks [ξg, ξe], each with
  // `joints` residuals; `loss` (may be null) applied to each pose's block, as Ceres would.
  PoseChunkCost(std::vector<std::unique_ptr<ceres::CostFunction>> poses,
                std::shared_ptr<const ceres::LossFunction> loss, int joints, int geometric, int external);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  // ½Σρ(‖r_j‖²) of every pose, or false where a pose cannot be evaluated (unreachable).
  bool costOnly(double const* const* parameters, double* rho_sum) const;

  std::vector<std::unique_ptr<ceres::CostFunction>> poses_;
  std::shared_ptr<const ceres::LossFunction> loss_;
  int joints_, geometric_, external_;
};

}  // namespace mire::mechanism::detail
