#pragma once
// Column-major 3×3 helpers of the templated kinematics (usable with ceres::Jet): products and
// the rotation about z, shared by the external pose chain and the H4 models.
#include <cmath>

namespace mire::mechanism {

namespace detail {

// out = a · b for column-major 3x3 matrices.
template <class T, class U, class V>
void multiply3(const U* a, const V* b, T* out) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) out[3 * c + r] = a[r] * b[3 * c] + a[3 + r] * b[3 * c + 1] + a[6 + r] * b[3 * c + 2];
}

// out = m · v for a column-major 3x3 matrix.
template <class T, class U, class V>
void apply3(const U* m, const V* v, T* out) {
  for (int r = 0; r < 3; ++r) out[r] = m[r] * v[0] + m[3 + r] * v[1] + m[6 + r] * v[2];
}

// Column-major Rz(angle).
template <class T>
void rotationZ(const T& angle, T* out) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  out[0] = c;
  out[1] = s;
  out[2] = T(0);
  out[3] = -s;
  out[4] = c;
  out[5] = T(0);
  out[6] = T(0);
  out[7] = T(0);
  out[8] = T(1);
}

}  // namespace detail

}  // namespace mire::mechanism
