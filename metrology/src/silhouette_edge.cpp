#include "silhouette_edge.hpp"

#include "mire/support/constants.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace mire::metrology {
namespace {

// The shading h blurred by g_σ on a grid of kStep px from `low` (x = u − u0), by a discrete
// convolution over ±5σ.
class BlurredShading {
 public:
  BlurredShading(double low, double high, double sigma, double radius) : low_(low) {
    const int size = static_cast<int>((high - low) / kStep) + 2;
    const int reach = static_cast<int>(5.0 * sigma / kStep) + 1;
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
  static constexpr double kStep = 0.02;
  double low_;
  std::vector<double> blurred_;
};

// The residuals of the best levels (B, A − B, C) for this edge and blur.
Eigen::VectorXd residuals(const std::vector<double>& u, const std::vector<double>& values, double u0, double sigma,
                          double radius) {
  const auto [low, high] = std::minmax_element(u.begin(), u.end());
  const BlurredShading shading(*low - u0, *high - u0, sigma, radius);
  const auto n = static_cast<Eigen::Index>(u.size());
  Eigen::MatrixXd basis(n, 3);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = u[static_cast<std::size_t>(i)] - u0;
    basis(i, 0) = 1.0;
    basis(i, 1) = 0.5 * std::erfc(-x / (sigma * std::sqrt(2.0)));
    basis(i, 2) = shading(x);
    y[i] = values[static_cast<std::size_t>(i)];
  }
  const Eigen::Vector3d levels = (basis.transpose() * basis).ldlt().solve(basis.transpose() * y);
  return basis * levels - y;
}

}  // namespace

std::optional<double> silhouetteEdge(const std::vector<double>& positions, const std::vector<double>& values,
                                     double start, double radius_px) {
  Eigen::Vector2d p(start, 1.0);  // (u0, σ)
  const auto cost = [&](const Eigen::Vector2d& q) { return residuals(positions, values, q[0], q[1], radius_px); };
  Eigen::VectorXd r = cost(p);
  double damping = 1e-3;
  for (int iteration = 0; iteration < 40 && damping < 1e6; ++iteration) {
    Eigen::MatrixXd jacobian(r.size(), 2);
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-4;
      Eigen::Vector2d plus = p, minus = p;
      plus[k] += h;
      minus[k] -= h;
      jacobian.col(k) = (cost(plus) - cost(minus)) / (2 * h);
    }
    // Levenberg–Marquardt: the damping grows until a step lowers the cost.
    Eigen::Matrix2d normal = jacobian.transpose() * jacobian;
    normal.diagonal() *= 1.0 + damping;
    const Eigen::Vector2d step = -normal.ldlt().solve(jacobian.transpose() * r);
    if (!step.allFinite()) return std::nullopt;
    const Eigen::Vector2d next = p + step;
    const Eigen::VectorXd r_next = next[1] > 0.2 ? cost(next) : Eigen::VectorXd();
    if (r_next.size() == 0 || r_next.squaredNorm() >= r.squaredNorm()) {
      damping *= 10.0;
      continue;
    }
    damping = std::max(damping / 10.0, 1e-9);
    p = next;
    r = r_next;
    if (step.norm() < 1e-6) break;
  }
  if (std::abs(p[0] - start) > 2.0 || p[1] < 0.3 || p[1] > 3.0) return std::nullopt;
  return p[0];
}

}  // namespace mire::metrology
