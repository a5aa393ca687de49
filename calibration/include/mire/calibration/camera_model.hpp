#pragma once
// The camera: fx fy cx cy and a lens model (lens_models.hpp): OpenCV's radial-tangential
// distortion (0 = pinhole, 4, 5, 8 or 12 coefficients) or OpenCV's fisheye (k1..k4).
// Parameters are laid out as one flat vector, COLMAP-style, so that cost functors take a
// single parameter block:
//   OpenCV:  params = [fx, fy, cx, cy, (k1, k2, p1, p2, (k3, (k4, k5, k6, (s1, s2, s3, s4))))]
//   Fisheye: params = [fx, fy, cx, cy, k1, k2, k3, k4]
// Pixel convention: OpenCV's (integer coordinates at pixel centres).
#include "mire/calibration/lens_models.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mire::calibration {

constexpr int kIntrinsicCount = 4;  // fx fy cx cy

// Projects a point given in the camera frame to pixels: the one templated projection of
// every model (lens dispatch in lens_models.hpp). `params` as above with `distortion_count`
// coefficients of model `lens` after the 4 intrinsics. Returns false (leaving `pixel` unset)
// for points at or behind the camera plane (z <= 0).
template <typename T>
inline bool projectPoint(const T* params, LensModel lens, int distortion_count, const T* point_camera, T* pixel) {
  if (!(point_camera[2] > T(0.0))) return false;
  const T x = point_camera[0] / point_camera[2];
  const T y = point_camera[1] / point_camera[2];
  T xd, yd;
  distortLens(lens, params + kIntrinsicCount, distortion_count, x, y, &xd, &yd);
  pixel[0] = params[0] * xd + params[2];
  pixel[1] = params[1] * yd + params[3];
  return true;
}

// A calibrated camera: geometry, and what the calibration knows about its own precision.
struct Camera {
  int width = 0;
  int height = 0;
  LensModel lens = LensModel::OpenCV;
  // fx fy cx cy followed by the lens model's coefficients (OpenCV's order).
  std::vector<double> params;

  // Calibration quality and uncertainty (empty / zero when unknown).
  double rms_px = 0.0;
  // Covariance of `params` (same order as parameterNames()); empty if unknown. Fixed
  // parameters have zero rows and columns.
  Eigen::MatrixXd covariance;
  // The camera's name where the file has one (ROS camera_name, ViSP <name>, mrcal's
  // mire_camera_name, camera.yaml's camera_name); empty otherwise. Converters keep it.
  std::string name;

  int distortionCount() const { return static_cast<int>(params.size()) - kIntrinsicCount; }
  double fx() const { return params[0]; }
  double fy() const { return params[1]; }
  double cx() const { return params[2]; }
  double cy() const { return params[3]; }

  // "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3", ... for this camera's size and lens
  // (fisheye: "k1".."k4").
  std::vector<std::string> parameterNames() const;
  // One-sigma of each parameter (sqrt of the covariance diagonal); empty if unknown.
  std::vector<double> sigmas() const;

  // "pinhole" (OpenCV, no coefficient), "opencv4", "opencv5", "opencv8", "opencv12", "fisheye".
  std::string modelName() const;

  // Throws std::invalid_argument if sizes or values are not a valid camera.
  void validate() const;

  // Pixel of a camera-frame point; returns false behind the camera.
  bool project(const Eigen::Vector3d& point_camera, Eigen::Vector2d* pixel) const;

  // Exact inverse of the lens model: the normalised ray (x, y, 1) whose projection is
  // `pixel`, found by Newton iterations to convergence (|Δ| < 1e-14) rather than a fixed
  // count. Returns false if it does not converge (far outside the calibrated field).
  bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const;
};

// Builds a camera from OpenCV's matrix and coefficients.
Camera cameraFromOpenCV(int width, int height, double fx, double fy, double cx, double cy,
                        const std::vector<double>& distortion);

}  // namespace mire::calibration
