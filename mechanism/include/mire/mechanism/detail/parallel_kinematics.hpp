#pragma once
// Templated IKMs of the Delta and Gough–Stewart models for MechanismAdapter (formulas in
// delta.hpp, gough_stewart.hpp and doc/mechanisms.md).
#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "mire/mechanism/detail/h4_kinematics.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

// The depth below the base of a Delta's plate when its arms are level, from the arm's reach
// (pivot radius − plate radius + arm length) and the forearm; 0 where the forearm is too short.
inline double levelArmDepth(double reach, double forearm) {
  return forearm > reach ? -std::sqrt(forearm * forearm - reach * reach) : 0.0;
}

// Translation-only pose convention: X = (x, y, z), bTe = [I, X]. The reference pose is on the
// z axis at `home_ratio` times the level-arm depth of the geometry it is given, so that a Delta
// of another size (`--nominal`) starts inside its own workspace (1.04: −0.65 m for the built-in).
template <class Depth>
struct TranslationPoseConvention {
  static constexpr MotionType kMotion = MotionType::Translation;
  static constexpr Unit kJointUnit = Unit::Radian;
  static constexpr int kPoseDof = 3;
  double home_ratio = 1.0;

  std::vector<std::string> poseComponentNames() const { return {"x", "y", "z"}; }
  std::vector<Unit> poseComponentUnits() const { return {Unit::Metre, Unit::Metre, Unit::Metre}; }
  Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const { return bTe.translation(); }
  Eigen::VectorXd referencePose(const Eigen::VectorXd& g) const {
    return Eigen::Vector3d(0.0, 0.0, home_ratio * Depth::levelDepth(g));
  }
  template <class T>
  void poseToTransform(const T* pose, T* R, T* t) const {
    for (int k = 0; k < 9; ++k) R[k] = T(k % 4 == 0 ? 1 : 0);
    for (int k = 0; k < 3; ++k) t[k] = pose[k];
  }
};

// Model `delta`: R r L l alpha1..3 q01..3.
struct DeltaKinematics : TranslationPoseConvention<DeltaKinematics> {
  static double levelDepth(const Eigen::VectorXd& g) { return levelArmDepth(g[0] - g[1] + g[2], g[3]); }
  static constexpr int kGeometric = 10;
  static constexpr int kJoints = 3;
  std::string name() const { return "delta"; }

  template <class T>
  int inverseKinematics(const T* g, const T* /*R*/, const T* t, T* joints) const {
    using std::cos;
    using std::sin;
    const T &R = g[0], &r = g[1], &L = g[2], &l = g[3];
    int mask = 0;
    for (int i = 0; i < 3; ++i) {
      const T ux = cos(g[4 + i]), uy = sin(g[4 + i]);
      // w = A_i − P_i = X + (r − R)·u_i; a = w·u_i, b = −w_z (the H4's formula, doc/mechanisms.md).
      const T w[3] = {t[0] + (r - R) * ux, t[1] + (r - R) * uy, t[2]};
      const T norm2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
      T phi;
      if (!detail::solveElbowOut(-w[2], w[0] * ux + w[1] * uy, (norm2 + L * L - l * l) / (T(2) * L), &phi)) {
        mask |= 1 << i;
        joints[i] = T(0);
        continue;
      }
      joints[i] = phi - g[7 + i];
    }
    return mask;
  }

  // Forearm i: elbow B_i = P_i + L·(cos φ_i·u_i − sin φ_i·z_B) → plate joint A_i = X + r·u_i.
  bool legSegments(const double* g, const Eigen::Isometry3d& bTe, std::vector<LegSegment>* out) const {
    const Eigen::Vector3d t = bTe.translation();
    double q[3];
    if (inverseKinematics(g, static_cast<const double*>(nullptr), t.data(), q) != 0) return false;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d u(std::cos(g[4 + i]), std::sin(g[4 + i]), 0.0);
      const double phi = q[i] + g[7 + i];
      const Eigen::Vector3d elbow = g[0] * u + g[2] * (std::cos(phi) * u - std::sin(phi) * Eigen::Vector3d::UnitZ());
      out->push_back({elbow, t + g[1] * u});
    }
    return true;
  }
};

// Model `delta-legs`: per leg i (8 values from 8·i): px py pz psi beta L l q0.
struct DeltaLegsKinematics : TranslationPoseConvention<DeltaLegsKinematics> {
  // The legs' mean level-arm depth below their mean pivot height.
  static double levelDepth(const Eigen::VectorXd& g) {
    double depth = 0.0;
    for (int i = 0; i < 3; ++i)
      depth += g[8 * i + 2] + levelArmDepth(std::hypot(g[8 * i], g[8 * i + 1]) + g[8 * i + 5], g[8 * i + 6]);
    return depth / 3.0;
  }
  static constexpr int kGeometric = 24;
  static constexpr int kJoints = 3;
  std::string name() const { return "delta-legs"; }

  template <class T>
  int inverseKinematics(const T* g, const T* /*R*/, const T* t, T* joints) const {
    T W[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) W[i][k] = t[k] - g[8 * i + k];
    return detail::generalAxisJoints(W, g, {3, 4, 5, 6, 7, /*stride=*/8}, joints);
  }
};

// Model `gough-stewart`: b (18), p (18), rho0 (6); pose (x, y, z, rotation vector).
struct GoughStewartKinematics {
  static constexpr MotionType kMotion = MotionType::Spatial;
  static constexpr Unit kJointUnit = Unit::Metre;
  static constexpr int kGeometric = 42;
  static constexpr int kJoints = 6;
  static constexpr int kPoseDof = 6;
  double home_height = 0.40;
  // Leg-length stroke [m]: ρ_i = q̄_i + ρ0_i must lie in [leg_min, leg_max].
  double leg_min = 0.0;
  double leg_max = std::numeric_limits<double>::infinity();

  std::string name() const { return "gough-stewart"; }
  bool inStroke(const double* g, int leg, double q) const {
    const double rho = q + g[36 + leg];
    return rho >= leg_min && rho <= leg_max;
  }
  std::vector<std::string> poseComponentNames() const { return {"x", "y", "z", "rx", "ry", "rz"}; }
  std::vector<Unit> poseComponentUnits() const {
    return {Unit::Metre, Unit::Metre, Unit::Metre, Unit::Radian, Unit::Radian, Unit::Radian};
  }
  Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const {
    const Eigen::AngleAxisd aa(bTe.linear());
    Eigen::VectorXd pose(6);
    pose << bTe.translation(), aa.axis() * aa.angle();
    return pose;
  }
  Eigen::VectorXd referencePose(const Eigen::VectorXd&) const {
    Eigen::VectorXd pose = Eigen::VectorXd::Zero(6);
    pose[2] = home_height;
    return pose;
  }
  template <class T>
  void poseToTransform(const T* pose, T* R, T* t) const {
    ceres::AngleAxisToRotationMatrix(pose + 3, ceres::ColumnMajorAdapter3x3(R));
    for (int k = 0; k < 3; ++k) t[k] = pose[k];
  }
  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* joints) const {
    using std::sqrt;
    for (int i = 0; i < 6; ++i) {
      const T* b = g + 3 * i;
      const T* p = g + 18 + 3 * i;
      T d[3];
      for (int k = 0; k < 3; ++k) d[k] = t[k] + R[k] * p[0] + R[3 + k] * p[1] + R[6 + k] * p[2] - b[k];
      joints[i] = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - g[36 + i];
    }
    return 0;
  }

  // Leg i: base joint b_i → platform joint t + R·p_i.
  bool legSegments(const double* g, const Eigen::Isometry3d& bTe, std::vector<LegSegment>* out) const {
    for (int i = 0; i < 6; ++i)
      out->push_back(
          {Eigen::Map<const Eigen::Vector3d>(g + 3 * i), bTe * Eigen::Map<const Eigen::Vector3d>(g + 18 + 3 * i)});
    return true;
  }
};

// Model `gough-stewart-symmetric` (doc/mechanisms.md): the Gough–Stewart legs above with
// the joints placed by the 3-fold symmetric layout of the nominal hexapod, g = (rb, beta_b, rp, beta_p, rho0):
//   b_i = rb·(cos(c_i + σ_i·beta_b), sin(…), 0),  p_i = rp·(cos(d_i + τ_i·beta_p), sin(…), 0),
//   q̄_i = ‖t + R·p_i − b_i‖ − rho0,
// with the pair centres c = (0, 0, 120, 120, 240, 240)°, d = (300, 60, 60, 180, 180, 300)° and the
// signs σ = (−, +, −, +, −, +), τ = (+, −, +, −, +, −) of doc/mechanisms.md.
struct GoughStewartSymmetricKinematics : GoughStewartKinematics {
  static constexpr int kGeometric = 5;
  static constexpr int kRho0 = 4;  // index of rho0
  static constexpr std::array<double, 6> kBaseCentreDeg{0, 0, 120, 120, 240, 240};
  static constexpr std::array<double, 6> kPlatformCentreDeg{300, 60, 60, 180, 180, 300};
  static constexpr std::array<double, 6> kBaseSign{-1, 1, -1, 1, -1, 1};
  static constexpr std::array<double, 6> kPlatformSign{1, -1, 1, -1, 1, -1};

  std::string name() const { return "gough-stewart-symmetric"; }
  bool inStroke(const double* g, int, double q) const {
    const double rho = q + g[kRho0];
    return rho >= leg_min && rho <= leg_max;
  }
  // Leg i's base joint b_i and platform joint p_i (x, y; z = 0) from the layout.
  template <class T>
  static void joints(const T* g, std::size_t i, T* b, T* p) {
    using std::cos;
    using std::sin;
    constexpr double kDeg = support::kPi / 180.0;
    const T base_angle = kBaseCentreDeg[i] * kDeg + kBaseSign[i] * g[1];
    const T platform_angle = kPlatformCentreDeg[i] * kDeg + kPlatformSign[i] * g[3];
    b[0] = g[0] * cos(base_angle);
    b[1] = g[0] * sin(base_angle);
    p[0] = g[2] * cos(platform_angle);
    p[1] = g[2] * sin(platform_angle);
  }
  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* q) const {
    using std::sqrt;
    for (std::size_t i = 0; i < 6; ++i) {
      T b[2], p[2];
      joints(g, i, b, p);
      T d[3];
      for (int k = 0; k < 3; ++k) d[k] = t[k] + R[k] * p[0] + R[3 + k] * p[1];
      d[0] -= b[0];
      d[1] -= b[1];
      q[i] = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - g[kRho0];
    }
    return 0;
  }
  // Leg i: base joint b_i → platform joint t + R·p_i (the layout's, not the 42 values').
  bool legSegments(const double* g, const Eigen::Isometry3d& bTe, std::vector<LegSegment>* out) const {
    for (std::size_t i = 0; i < 6; ++i) {
      double b[2], p[2];
      joints(g, i, b, p);
      out->push_back({Eigen::Vector3d(b[0], b[1], 0.0), bTe * Eigen::Vector3d(p[0], p[1], 0.0)});
    }
    return true;
  }
};

// A Gough–Stewart kinematics K (GoughStewartKinematics or derived) at the nominal's home height
// and leg strokes, for the hexapod models' factories.
template <class K>
K hexapodKinematics(const GoughStewartNominal& nominal) {
  K k;
  k.home_height = nominal.home_height;
  k.leg_min = nominal.leg_min;
  k.leg_max = nominal.leg_max;
  return k;
}

// Its factory and nominal (gough_stewart_symmetric.cpp): the hexapod as a controller with a
// symmetric geometry sees it, the nominal's layout required (pairs about 0/120/240° on the base,
// 60/180/300° on the platform, equal half-angles; std::invalid_argument otherwise).
ParameterSet goughStewartSymmetricParameters(const GoughStewartNominal& nominal = {});
std::unique_ptr<Mechanism> makeGoughStewartSymmetricMechanism(const GoughStewartNominal& nominal = {});

}  // namespace mire::mechanism
