#include "silhouette_edge.hpp"

#include "mire/support/constants.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace mire::metrology {
namespace {

// The shading h blurred by g_σ on a grid of kStep px from `low` (x = u − u0), by a discrete
// convolution over ±4σ.
class BlurredShading {
 public:
  BlurredShading(double low, double high, double sigma, double radius) : low_(low) {
    const int size = static_cast<int>((high - low) / kStep) + 2;
    const int reach = static_cast<int>(4.0 * sigma / kStep) + 1;
    std::vector<double> raw(static_cast<std::size_t>(size + 2 * reach));
    for (std::size_t j = 0; j < raw.size(); ++j) {
      const double x = std::clamp(low + (static_cast<double>(j) - reach) * kStep, 0.0, radius) / radius;
      raw[j] = std::sqrt(std::max(0.0, 2.0 * x - x * x));
    }
    std::vector<double> kernel(static_cast<std::size_t>(2 * reach + 1));
    double total = 0.0;
    for (int k = -reach; k <= reach; ++k) {
      const double x = k * kStep / sigma;
      total += kernel[static_cast<std::size_t>(k + reach)] = std::exp(-0.5 * x * x);
    }
    blurred_.assign(static_cast<std::size_t>(size), 0.0);
    for (int i = 0; i < size; ++i)
      for (int k = 0; k <= 2 * reach; ++k)
        blurred_[static_cast<std::size_t>(i)] +=
            kernel[static_cast<std::size_t>(k)] * raw[static_cast<std::size_t>(i + 2 * reach - k)] / total;
  }
  double operator()(double x) const {
    const double f = std::clamp((x - low_) / kStep, 0.0, static_cast<double>(blurred_.size()) - 1.001);
    const auto i = static_cast<std::size_t>(f);
    return blurred_[i] + (f - static_cast<double>(i)) * (blurred_[i + 1] - blurred_[i]);
  }

 private:
  static constexpr double kStep = 0.05;
  double low_;
  std::vector<double> blurred_;
};

// The residuals of the best levels (B, A − B, C) of each profile for this edge and blur (`shading`
// made for σ and a range of x that covers the samples).
Eigen::VectorXd residuals(const std::vector<std::vector<double>>& u, const std::vector<std::vector<double>>& values,
                          double u0, double sigma, const BlurredShading& shading) {
  std::vector<double> out;
  for (std::size_t g = 0; g < u.size(); ++g) {
    const auto n = static_cast<Eigen::Index>(u[g].size());
    Eigen::MatrixXd basis(n, 3);
    Eigen::VectorXd y(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = u[g][static_cast<std::size_t>(i)] - u0;
      basis(i, 0) = 1.0;
      basis(i, 1) = 0.5 * std::erfc(-x / (sigma * std::sqrt(2.0)));
      basis(i, 2) = shading(x);
      y[i] = values[g][static_cast<std::size_t>(i)];
    }
    const Eigen::Vector3d levels = (basis.transpose() * basis).ldlt().solve(basis.transpose() * y);
    const Eigen::VectorXd r = basis * levels - y;
    out.insert(out.end(), r.data(), r.data() + r.size());
  }
  return Eigen::Map<const Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace

std::optional<SilhouetteEdge> silhouetteEdge(const std::vector<std::vector<double>>& positions,
                                             const std::vector<std::vector<double>>& values, double start,
                                             double radius_px) {
  double low = 0.0, high = 0.0;
  for (const auto& group : positions)
    for (const double u : group) low = std::min(low, u), high = std::max(high, u);
  // One blurred shading per σ tried; u0 moves within ±2 px of the start (checked below).
  const auto shading = [&](double sigma) {
    return BlurredShading(low - start - 3.0, high - start + 3.0, sigma, radius_px);
  };
  Eigen::Vector2d p(start, 1.0);  // (u0, σ)
  BlurredShading current = shading(p[1]);
  Eigen::VectorXd r = residuals(positions, values, p[0], p[1], current);
  Eigen::Matrix2d information = Eigen::Matrix2d::Identity();
  double damping = 1e-3;
  for (int iteration = 0; iteration < 30 && damping < 1e6; ++iteration) {
    const double h = 1e-4;
    Eigen::MatrixXd jacobian(r.size(), 2);
    jacobian.col(0) =
        (residuals(positions, values, p[0] + h, p[1], current) - residuals(positions, values, p[0] - h, p[1], current)) /
        (2 * h);
    jacobian.col(1) = (residuals(positions, values, p[0], p[1] + h, shading(p[1] + h)) -
                       residuals(positions, values, p[0], p[1] - h, shading(p[1] - h))) /
                      (2 * h);
    // Levenberg–Marquardt: the damping grows until a step lowers the cost.
    information = jacobian.transpose() * jacobian;
    Eigen::Matrix2d normal = information;
    normal.diagonal() *= 1.0 + damping;
    const Eigen::Vector2d step = -normal.ldlt().solve(jacobian.transpose() * r);
    if (!step.allFinite()) return std::nullopt;
    const Eigen::Vector2d next = p + step;
    if (!(next[1] > 0.2 && next[1] < 4.0 && std::abs(next[0] - start) < 2.5)) {
      damping *= 10.0;
      continue;
    }
    BlurredShading trial = shading(next[1]);
    const Eigen::VectorXd r_next = residuals(positions, values, next[0], next[1], trial);
    if (r_next.squaredNorm() >= r.squaredNorm()) {
      damping *= 10.0;
      continue;
    }
    damping = std::max(damping / 10.0, 1e-9);
    p = next;
    r = r_next;
    current = std::move(trial);
    if (step.norm() < 1e-5) break;
  }
  if (std::abs(p[0] - start) > 2.0 || p[1] < 0.3 || p[1] > 3.0) return std::nullopt;
  // The levels are eliminated (variable projection), so JᵀJ is the information of (u0, σ) alone.
  const double levels = 3.0 * static_cast<double>(positions.size());
  const double dof = std::max(1.0, static_cast<double>(r.size()) - levels - 2.0);
  const double variance = r.squaredNorm() / dof * information.inverse()(0, 0);
  if (!(variance >= 0.0)) return std::nullopt;
  return SilhouetteEdge{p[0], std::sqrt(variance)};
}

}  // namespace mire::metrology
