#pragma once
// OpenCV's lens distortion, templated on the scalar so that Ceres autodiff (ceres::Jet) and
// plain doubles share one implementation. Coefficients in OpenCV's order:
//   k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]
// with 4, 5, 8 or 12 values (Bouguet's toolbox, Brown–Conrady, rational, rational + thin prism),
// or none (the pinhole model: no distortion).
// Identical to cv::projectPoints for the same coefficients.

namespace mire::calibration {

// Applies distortion to normalised coordinates (x, y) = (X/Z, Y/Z).
template <typename T>
inline void distortNormalized(const T* coefficients, int count, const T& x, const T& y, T* xd, T* yd) {
  if (count == 0) {  // pinhole
    *xd = x;
    *yd = y;
    return;
  }
  const T r2 = x * x + y * y;
  const T r4 = r2 * r2;
  const T r6 = r4 * r2;
  const T& k1 = coefficients[0];
  const T& k2 = coefficients[1];
  const T& p1 = coefficients[2];
  const T& p2 = coefficients[3];
  T numerator = T(1.0) + k1 * r2 + k2 * r4;
  if (count >= 5) numerator += coefficients[4] * r6;
  T denominator = T(1.0);
  if (count >= 8) denominator += coefficients[5] * r2 + coefficients[6] * r4 + coefficients[7] * r6;
  const T radial = numerator / denominator;
  const T xy = x * y;
  *xd = x * radial + T(2.0) * p1 * xy + p2 * (r2 + T(2.0) * x * x);
  *yd = y * radial + p1 * (r2 + T(2.0) * y * y) + T(2.0) * p2 * xy;
  if (count >= 12) {
    *xd += coefficients[8] * r2 + coefficients[9] * r4;
    *yd += coefficients[10] * r2 + coefficients[11] * r4;
  }
}

// True for the coefficient counts OpenCV's model defines here (4, 5, 8, 12).
constexpr bool isSupportedDistortionCount(int count) { return count == 4 || count == 5 || count == 8 || count == 12; }

}  // namespace mire::calibration
