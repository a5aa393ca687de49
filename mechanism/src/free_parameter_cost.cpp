// A residual over the free parameters only (free_parameter_cost.hpp).
#include "free_parameter_cost.hpp"

#include <stdexcept>
#include <utility>

namespace mire::mechanism::detail {

FreeParameterMap::FreeParameterMap(const Eigen::MatrixXd& expansion, Eigen::VectorXd ambient)
    : source_(static_cast<std::size_t>(expansion.rows()), -1),
      fixed_(std::move(ambient)),
      free_count_(static_cast<int>(expansion.cols())) {
  if (fixed_.size() != expansion.rows())
    throw std::invalid_argument("free parameters: " + std::to_string(fixed_.size()) + " values for an expansion of " +
                                std::to_string(expansion.rows()) + " rows");
  for (Eigen::Index k = 0; k < expansion.rows(); ++k)
    for (Eigen::Index c = 0; c < expansion.cols(); ++c) {
      if (expansion(k, c) == 0.0) continue;
      if (expansion(k, c) != 1.0 || source_[static_cast<std::size_t>(k)] >= 0)
        throw std::invalid_argument("free parameters: the expansion is not a tie-group selection");
      source_[static_cast<std::size_t>(k)] = static_cast<int>(c);
    }
}

Eigen::VectorXd FreeParameterMap::freeValues(const Eigen::VectorXd& ambient) const {
  Eigen::VectorXd free = Eigen::VectorXd::Zero(free_count_);
  std::vector<bool> seen(static_cast<std::size_t>(free_count_), false);
  for (std::size_t k = 0; k < source_.size(); ++k) {
    const int c = source_[k];
    if (c < 0 || seen[static_cast<std::size_t>(c)]) continue;
    seen[static_cast<std::size_t>(c)] = true;
    free[c] = ambient[static_cast<Eigen::Index>(k)];
  }
  return free;
}

void FreeParameterMap::expand(const double* free, double* ambient) const {
  for (std::size_t k = 0; k < source_.size(); ++k)
    ambient[k] = source_[k] < 0 ? fixed_[static_cast<Eigen::Index>(k)] : free[source_[k]];
}

void FreeParameterMap::gather(const double* ambient_jacobian, int rows, int first, int count,
                              double* free_jacobian) const {
  for (int k = 0; k < count; ++k) {
    const int c = source_[static_cast<std::size_t>(first + k)];
    if (c < 0) continue;
    for (int r = 0; r < rows; ++r) free_jacobian[r * free_count_ + c] += ambient_jacobian[r * count + k];
  }
}

FreeParameterCost::FreeParameterCost(std::unique_ptr<ceres::CostFunction> inner,
                                     std::shared_ptr<const FreeParameterMap> map, std::vector<int> block_offsets)
    : inner_(std::move(inner)), map_(std::move(map)), offsets_(std::move(block_offsets)) {
  const std::vector<int32_t>& sizes = inner_->parameter_block_sizes();
  if (sizes.size() != offsets_.size())
    throw std::invalid_argument("free parameters: one offset per parameter block expected");
  for (std::size_t b = 0; b < sizes.size(); ++b)
    if (offsets_[b] < 0 || offsets_[b] + sizes[b] > map_->ambientCount())
      throw std::invalid_argument("free parameters: a parameter block lies outside the ambient vector");
  set_num_residuals(inner_->num_residuals());
  mutable_parameter_block_sizes()->push_back(map_->freeCount());
}

bool FreeParameterCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  Eigen::VectorXd ambient(map_->ambientCount());
  map_->expand(parameters[0], ambient.data());
  const std::vector<int32_t>& sizes = inner_->parameter_block_sizes();
  std::vector<const double*> blocks;
  for (const int offset : offsets_) blocks.push_back(ambient.data() + offset);
  if (jacobians == nullptr || jacobians[0] == nullptr) return inner_->Evaluate(blocks.data(), residuals, nullptr);

  const int rows = num_residuals();
  std::vector<Eigen::VectorXd> ambient_jacobians;
  std::vector<double*> pointers;
  ambient_jacobians.reserve(sizes.size());  // the pointers taken below stay valid
  for (const int32_t size : sizes) {
    ambient_jacobians.emplace_back(static_cast<Eigen::Index>(rows) * size);
    pointers.push_back(ambient_jacobians.back().data());
  }
  if (!inner_->Evaluate(blocks.data(), residuals, pointers.data())) return false;
  Eigen::Map<Eigen::VectorXd>(jacobians[0], static_cast<Eigen::Index>(rows) * map_->freeCount()).setZero();
  for (std::size_t b = 0; b < sizes.size(); ++b) map_->gather(pointers[b], rows, offsets_[b], sizes[b], jacobians[0]);
  return true;
}

}  // namespace mire::mechanism::detail
