#include "mire/metrology/leg_axis.hpp"

#include "mire/support/constants.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mire::metrology {
namespace {

// (θ1, ρ1, θ2, ρ2), the angles unwrapped to within π of `reference`'s.
Eigen::Vector4d contourParameters(const std::array<ContourFit, 2>& contours, const Eigen::Vector4d& reference) {
  Eigen::Vector4d x(contours[0].line.theta, contours[0].line.rho, contours[1].line.theta, contours[1].line.rho);
  for (int k : {0, 2}) x[k] = reference[k] + std::remainder(x[k] - reference[k], 2.0 * support::kPi);
  return x;
}

}  // namespace

LegAxis averageLegAxis(const std::vector<std::array<ContourFit, 2>>& images, double radius) {
  if (images.empty()) throw std::invalid_argument("no image to average");
  const auto count = static_cast<double>(images.size());
  const Eigen::Vector4d first = contourParameters(images.front(), Eigen::Vector4d::Zero());
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  Eigen::Matrix4d fit = Eigen::Matrix4d::Zero(), systematic = Eigen::Matrix4d::Zero();
  for (const auto& contours : images) {
    mean += contourParameters(contours, first) / count;
    fit.topLeftCorner<2, 2>() += contours[0].covariance / count;
    fit.bottomRightCorner<2, 2>() += contours[1].covariance / count;
    systematic.topLeftCorner<2, 2>() += contours[0].systematic / count;
    systematic.bottomRightCorner<2, 2>() += contours[1].systematic / count;
  }
  LegAxis result;
  result.images_used = static_cast<int>(images.size());
  if (images.size() > 1) {
    Eigen::Matrix4d scatter = Eigen::Matrix4d::Zero();
    for (const auto& contours : images) {
      const Eigen::Vector4d e = contourParameters(contours, first) - mean;
      scatter += e * e.transpose() / (count - 1.0);
    }
    result.spread_ratio = (fit.ldlt().solve(scatter)).trace() / 4.0;
  }
  const std::array<ContourLine, 2> contours{ContourLine{mean[0], mean[1]}, ContourLine{mean[2], mean[3]}};
  result.axis = cylinderAxis(contours, radius);
  const Eigen::Matrix4d jacobian = cylinderAxisJacobian(contours, radius);
  const Eigen::Matrix4d mean_covariance = fit * (std::max(1.0, result.spread_ratio) / count) + systematic;
  result.covariance = jacobian * mean_covariance * jacobian.transpose();
  return result;
}

}  // namespace mire::metrology
