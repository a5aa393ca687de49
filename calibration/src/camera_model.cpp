#include "mire/calibration/camera_model.hpp"

#include <ceres/jet.h>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace mire::calibration {

std::vector<std::string> Camera::parameterNames() const {
  std::vector<std::string> names = {"fx", "fy", "cx", "cy"};
  names.resize(std::min<std::size_t>(names.size(), params.size()));
  for (int i = 0; i < distortionCount(); ++i) {
    const std::string name = coefficientName(lens, i);
    if (name.empty()) break;
    names.push_back(name);
  }
  return names;
}

std::string Camera::modelName() const {
  if (lens == LensModel::OpenCV)
    return distortionCount() == 0 ? std::string("pinhole") : "opencv" + std::to_string(distortionCount());
  return lensName(lens);
}

std::vector<double> Camera::sigmas() const {
  std::vector<double> result;
  if (covariance.rows() != static_cast<Eigen::Index>(params.size())) return result;
  for (Eigen::Index i = 0; i < covariance.rows(); ++i) result.push_back(std::sqrt(std::max(0.0, covariance(i, i))));
  return result;
}

void Camera::validate() const {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  if (params.size() < kIntrinsicCount)
    throw std::invalid_argument("a camera needs fx, fy, cx, cy (" + std::to_string(params.size()) +
                                " parameters given)");
  if (!isValidCoefficientCount(lens, distortionCount()))
    throw std::invalid_argument(
        lens == LensModel::Fisheye
            ? "the fisheye model has 4 coefficients (k1..k4), not " + std::to_string(distortionCount())
            : "distortion must have 0 (pinhole), 4, 5, 8 or 12 coefficients, not " + std::to_string(distortionCount()));
  for (const double value : params)
    if (!std::isfinite(value)) throw std::invalid_argument("camera parameters must be finite");
  if (!(fx() > 0.0) || !(fy() > 0.0)) throw std::invalid_argument("focal lengths must be positive");
  if (covariance.size() != 0 &&
      (covariance.rows() != static_cast<Eigen::Index>(params.size()) || covariance.cols() != covariance.rows()))
    throw std::invalid_argument("covariance size does not match the parameter count");
}

bool Camera::project(const Eigen::Vector3d& point_camera, Eigen::Vector2d* pixel) const {
  return projectPoint(params.data(), lens, distortionCount(), point_camera.data(), pixel->data());
}

bool Camera::unproject(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const {
  // Newton on distort(x) = target in normalised coordinates, with the Jacobian from dual
  // numbers (exact, and the same distortLens as projection).
  const Eigen::Vector2d target((pixel.x() - cx()) / fx(), (pixel.y() - cy()) / fy());
  const int count = distortionCount();
  using Jet = ceres::Jet<double, 2>;
  std::vector<Jet> coefficients;
  coefficients.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) coefficients.emplace_back(params[kIntrinsicCount + i]);
  Eigen::Vector2d x = target;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Jet jx(x.x(), 0), jy(x.y(), 1);
    Jet xd, yd;
    distortLens(lens, coefficients.data(), count, jx, jy, &xd, &yd);
    const Eigen::Vector2d residual(xd.a - target.x(), yd.a - target.y());
    Eigen::Matrix2d jacobian;
    jacobian << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
    const Eigen::Vector2d step = jacobian.partialPivLu().solve(residual);
    if (!step.allFinite()) return false;
    x -= step;
    if (step.norm() < 1e-14 * (1.0 + x.norm())) {
      *normalized = x;
      return true;
    }
  }
  return false;
}

Camera cameraFromOpenCV(int width, int height, double fx, double fy, double cx, double cy,
                        const std::vector<double>& distortion) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.params = {fx, fy, cx, cy};
  camera.params.insert(camera.params.end(), distortion.begin(), distortion.end());
  camera.validate();
  return camera;
}

}  // namespace mire::calibration
