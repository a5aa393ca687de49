#pragma once
// Lens models, COLMAP-style: one struct per model, each with its coefficient names and a
// templated `distort` on normalised coordinates (x, y) = (X/Z, Y/Z), so that Ceres autodiff
// (ceres::Jet) and plain doubles share one implementation; `distortLens` dispatches on the
// run-time LensModel and is the single entry point used by projectPoint (camera_model.hpp),
// hence by calibration, Camera::project/unproject, pose estimation, the projection
// uncertainty and the renderer. See doc/calibration.md.
//
// Adding a model (the recipe, also in doc/calibration.md):
//  1. a struct below with kLens, kName, isValidCount(count), coefficientName(i) and the
//     templated distort(coefficients, count, x, y, xd, yd) — pure arithmetic on T, no branches
//     on derivatives (compare only values), smooth at the optical axis;
//  2. an enumerator in LensModel and a case in each dispatch function at the end of this file;
//  3. a DistortionModel in calibrate.hpp (name, coefficient count, lens) and a case in
//     calibrate.cpp's makeCost (Ceres needs the parameter-block size at compile time);
//  4. a struct in tests/calibration/test_lens_models.cpp comparing it with a reference
//     implementation (OpenCV) to 1e-10 px, which the typed tests then run through projection,
//     unproject round trips and calibration.
#include "mire/calibration/distortion.hpp"

#include <cmath>

namespace mire::calibration {

// OpenCV: the radial-tangential model of calib3d with 0 (pinhole), 4, 5, 8 or 12 coefficients;
// Fisheye: OpenCV's cv::fisheye equidistant model, coefficients k1..k4.
enum class LensModel { OpenCV, Fisheye };

// cv::projectPoints' model: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]; 0 coefficients = pinhole.
struct OpenCVLens {
  static constexpr LensModel kLens = LensModel::OpenCV;
  static constexpr const char* kName = "opencv";
  static constexpr bool isValidCount(int count) { return count == 0 || isSupportedDistortionCount(count); }
  static constexpr const char* coefficientName(int i) {
    constexpr const char* kNames[] = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "s1", "s2", "s3", "s4"};
    return i >= 0 && i < 12 ? kNames[i] : "";
  }
  template <typename T>
  static void distort(const T* coefficients, int count, const T& x, const T& y, T* xd, T* yd) {
    distortNormalized(coefficients, count, x, y, xd, yd);
  }
};

// cv::fisheye (Kannala–Brandt equidistant): θ = atan(r), r = |(x, y)|,
// θd = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), (xd, yd) = (θd / r) (x, y). Points must be in
// front of the camera (θ < 90°), as everywhere in mire (projectPoint needs Z > 0).
struct FisheyeLens {
  static constexpr LensModel kLens = LensModel::Fisheye;
  static constexpr const char* kName = "fisheye";
  static constexpr bool isValidCount(int count) { return count == 4; }
  static constexpr const char* coefficientName(int i) {
    constexpr const char* kNames[] = {"k1", "k2", "k3", "k4"};
    return i >= 0 && i < 4 ? kNames[i] : "";
  }
  template <typename T>
  static void distort(const T* k, int /*count*/, const T& x, const T& y, T* xd, T* yd) {
    using std::atan;
    using std::sqrt;
    const T r2 = x * x + y * y;
    T scale;
    if (r2 < T(1e-16)) {
      // On the axis θd/r = 1 + (k1 − 1/3) r² + O(r⁴): finite, and differentiable (sqrt is not).
      scale = T(1.0) + (k[0] - T(1.0 / 3.0)) * r2;
    } else {
      const T r = sqrt(r2);
      const T theta = atan(r);
      const T t2 = theta * theta;
      const T theta_d = theta * (T(1.0) + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
      scale = theta_d / r;
    }
    *xd = x * scale;
    *yd = y * scale;
  }
};

// The dispatch (the one entry point; add a case per model).
template <typename T>
inline void distortLens(LensModel lens, const T* coefficients, int count, const T& x, const T& y, T* xd, T* yd) {
  switch (lens) {
    case LensModel::Fisheye:
      FisheyeLens::distort(coefficients, count, x, y, xd, yd);
      return;
    case LensModel::OpenCV:
      break;
  }
  OpenCVLens::distort(coefficients, count, x, y, xd, yd);
}

inline bool isValidCoefficientCount(LensModel lens, int count) {
  switch (lens) {
    case LensModel::Fisheye:
      return FisheyeLens::isValidCount(count);
    case LensModel::OpenCV:
      break;
  }
  return OpenCVLens::isValidCount(count);
}

inline const char* coefficientName(LensModel lens, int i) {
  switch (lens) {
    case LensModel::Fisheye:
      return FisheyeLens::coefficientName(i);
    case LensModel::OpenCV:
      break;
  }
  return OpenCVLens::coefficientName(i);
}

inline const char* lensName(LensModel lens) {
  switch (lens) {
    case LensModel::Fisheye:
      return FisheyeLens::kName;
    case LensModel::OpenCV:
      break;
  }
  return OpenCVLens::kName;
}

}  // namespace mire::calibration
