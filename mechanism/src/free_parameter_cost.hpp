#pragma once
// A residual over the free parameters only. The identification's cost functions are written over
// the ambient blocks [ξg | ξe]; with fixed or tied parameters, a manifold on those blocks would make
// Ceres multiply every residual block's ambient Jacobian by the dense ambient × free expansion E
// (doc/mechanisms.md, "Fixed and tied parameters"). Here the free vector is expanded to the ambient
// one directly (a fixed value, or its group's free value) and the ambient Jacobian's columns are
// gathered onto the free ones: the same values and the same J·E, each entry of E being 0 or 1.
#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace mire::mechanism::detail {

// Where each ambient value comes from.
class FreeParameterMap {
 public:
  // `expansion`: ambient × free, at most one 1 per row (ParameterSet::expansion()); `ambient`:
  // the current values, those of the fixed parameters kept.
  FreeParameterMap(const Eigen::MatrixXd& expansion, Eigen::VectorXd ambient);

  int ambientCount() const { return static_cast<int>(source_.size()); }
  int freeCount() const { return free_count_; }
  // The free values of `ambient` (each group's first member).
  Eigen::VectorXd freeValues(const Eigen::VectorXd& ambient) const;
  void expand(const double* free, double* ambient) const;
  // free_jacobian (rows × free, row-major) = Σ over the ambient columns [first, first + count)
  // of `ambient_jacobian` (rows × count, row-major), each added to its free column.
  void gather(const double* ambient_jacobian, int rows, int first, int count, double* free_jacobian) const;

 private:
  std::vector<int> source_;  // free index of each ambient value; −1: fixed
  Eigen::VectorXd fixed_;
  int free_count_ = 0;
};

class FreeParameterCost final : public ceres::CostFunction {
 public:
  // `inner`'s parameter blocks are the ambient vector's segments starting at `block_offsets`.
  FreeParameterCost(std::unique_ptr<ceres::CostFunction> inner, std::shared_ptr<const FreeParameterMap> map,
                    std::vector<int> block_offsets);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  std::shared_ptr<const FreeParameterMap> map_;
  std::vector<int> offsets_;
};

}  // namespace mire::mechanism::detail
