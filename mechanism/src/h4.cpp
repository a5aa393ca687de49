// H4 models 12, 31 and 31-in-the-camera-frame (paper §3.2–3.3, §4.2; doc/mechanisms.md).
#include "mire/mechanism/h4.hpp"

#include <cmath>
#include <stdexcept>

#include "mire/mechanism/detail/h4_kinematics.hpp"
#include "mire/mechanism/mechanism_adapter.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using support::kPi;

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

std::string indexed(const std::string& base, int i) { return base + std::to_string(i + 1); }

// Depth of the effector below the pivots when the arms are tilted by φ0 and the horizontal
// pivot-to-attachment distance is r: z = −L sinφ0 − √(l² − (r + L cosφ0)²).
double referenceDepth(double r, double L, double l) {
  for (double phi0 : {0.4, 0.8, 1.2}) {
    const double horizontal = r + L * std::cos(phi0);
    if (l > horizontal) return L * std::sin(phi0) + std::sqrt(l * l - horizontal * horizontal);
  }
  return l;
}

Eigen::VectorXd poseAt(double x, double y, double z) {
  Eigen::VectorXd pose(4);
  pose << x, y, z, 0.0;
  return pose;
}

}  // namespace

std::string h4ModelName(H4ModelKind kind) {
  switch (kind) {
    case H4ModelKind::Model12:
      return "h4-model12";
    case H4ModelKind::Model31:
      return "h4-model31";
    case H4ModelKind::Model31Camera:
      return "h4-model31-camera";
  }
  return "?";
}

ParameterSet h4Model12Parameters(const H4Nominal& n) {
  ParameterSet set;
  set.add(positiveLength("R", n.R, "nacelle attachment to arm pivot distance (H configuration)"));
  set.add(positiveLength("L", n.L, "arm length"));
  set.add(positiveLength("l", n.l, "forearm length"));
  set.add(positiveLength("h", n.h, "half nacelle width along x_B"));
  set.add(positiveLength("d", n.d, "half nacelle length along y_B (no influence in model 12)", true));
  for (int i = 0; i < 4; ++i)
    set.add({indexed("alpha", i), n.alpha[static_cast<std::size_t>(i)], Unit::Radian, false,
             "direction of arm pivot " + std::to_string(i + 1) + " about z_B"});
  for (int i = 0; i < 4; ++i)
    set.add({indexed("q0", i), n.q0[static_cast<std::size_t>(i)], Unit::Radian, false,
             "joint offset " + std::to_string(i + 1)});
  return set;
}

ParameterSet model31FromModel12(const ParameterSet& m12, Eigen::Vector3d* origin_shift) {
  const double R = m12.value("R"), L = m12.value("L"), l = m12.value("l"), h = m12.value("h"), d = m12.value("d");
  std::array<Eigen::Vector3d, 4> P;
  std::array<double, 4> alpha{};
  for (int i = 0; i < 4; ++i) {
    alpha[static_cast<std::size_t>(i)] = m12.value(indexed("alpha", i));
    const double a = alpha[static_cast<std::size_t>(i)];
    P[static_cast<std::size_t>(i)] = Eigen::Vector3d(kH4Epsilon[static_cast<std::size_t>(i)] * h + R * std::cos(a),
                                                     kH4Sigma[static_cast<std::size_t>(i)] * d + R * std::sin(a), 0.0);
  }
  if (origin_shift) *origin_shift = P[0];
  ParameterSet set;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 1; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      set.add({indexed(axes[k], i), P[static_cast<std::size_t>(i)][k] - P[0][k], Unit::Metre, false,
               std::string("arm pivot ") + std::to_string(i + 1) + " relative to pivot 1, " + axes[k]});
  for (int i = 0; i < 4; ++i)
    set.add({indexed("psi", i), wrap(alpha[static_cast<std::size_t>(i)] + kPi), Unit::Radian, false,
             "pivot axis " + std::to_string(i + 1) + ", first Euler angle (eq. 17)"});
  for (int i = 0; i < 4; ++i)
    set.add({indexed("beta", i), kPi / 2.0, Unit::Radian, false,
             "pivot axis " + std::to_string(i + 1) + ", second Euler angle (eq. 17)"});
  for (int i = 0; i < 4; ++i) set.add(positiveLength(indexed("L", i), L, "arm length"));
  for (int i = 0; i < 4; ++i) set.add(positiveLength(indexed("l", i), l, "forearm length"));
  for (int i = 0; i < 4; ++i)
    set.add({indexed("q0", i), m12.value(indexed("q0", i)), Unit::Radian, false, "joint offset"});
  set.add(positiveLength("h", h, "half nacelle width"));
  set.add(positiveLength("d", d, "half nacelle length"));
  return set;
}

ParameterSet model31CameraFromModel31(const ParameterSet& m31, const Eigen::Isometry3d& alignedCamera_T_base) {
  const Eigen::Matrix3d RT = alignedCamera_T_base.linear();
  const double d = m31.value("d");
  ParameterSet set;
  std::array<Eigen::Vector3d, 4> Ppp;
  std::array<double, 4> psi{}, beta{}, q0{};
  for (int i = 0; i < 4; ++i) {
    const auto s = static_cast<std::size_t>(i);
    Eigen::Vector3d P = Eigen::Vector3d::Zero();
    if (i > 0) P << m31.value(indexed("x", i)), m31.value(indexed("y", i)), m31.value(indexed("z", i));
    // P''_i = pivot in the new frame minus the constant σ_i·d·y_B term (eq. 26).
    Ppp[s] = RT * P + alignedCamera_T_base.translation() - kH4Sigma[s] * d * RT * Eigen::Vector3d::UnitY();
    // Axis: R_T·Rz(ψ)·Rx(β) = Rz(ψ')·Rx(β')·Rz(γ); γ folds into the joint offset.
    const Eigen::Matrix3d M = RT * Eigen::AngleAxisd(m31.value(indexed("psi", i)), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(m31.value(indexed("beta", i)), Eigen::Vector3d::UnitX());
    psi[s] = std::atan2(M(0, 2), -M(1, 2));
    beta[s] = std::atan2(std::hypot(M(0, 2), M(1, 2)), M(2, 2));
    q0[s] = m31.value(indexed("q0", i)) + std::atan2(M(2, 0), M(2, 1));
  }
  const char* axes[3] = {"xpp", "ypp", "zpp"};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      set.add({indexed(axes[k], i), Ppp[static_cast<std::size_t>(i)][k], Unit::Metre, false,
               "combined pivot " + std::to_string(i + 1) + " (P_i − σ_i d x_H) in the aligned camera frame"});
  for (int i = 0; i < 4; ++i)
    set.add({indexed("psi", i), psi[static_cast<std::size_t>(i)], Unit::Radian, false, "pivot axis, first Euler angle"});
  for (int i = 0; i < 4; ++i)
    set.add(
        {indexed("beta", i), beta[static_cast<std::size_t>(i)], Unit::Radian, false, "pivot axis, second Euler angle"});
  for (int i = 0; i < 4; ++i)
    set.add({indexed("q0", i), wrap(q0[static_cast<std::size_t>(i)]), Unit::Radian, false, "joint offset"});
  for (int i = 0; i < 4; ++i) set.add(positiveLength(indexed("l", i), m31.value(indexed("l", i)), "forearm length"));
  for (int i = 0; i < 4; ++i) set.add(positiveLength(indexed("L", i), m31.value(indexed("L", i)), "arm length"));
  set.add(positiveLength("h", m31.value("h"), "half nacelle width"));
  return set;
}

ParameterSet H4Model12Kinematics::nominal(const H4Nominal& n) const { return h4Model12Parameters(n); }
ParameterSet H4Model31Kinematics::nominal(const H4Nominal& n) const {
  return model31FromModel12(h4Model12Parameters(n));
}
ParameterSet H4Model31CameraKinematics::nominal(const H4Nominal& n) const {
  return model31CameraFromModel31(model31FromModel12(h4Model12Parameters(n)), Eigen::Isometry3d::Identity());
}

Eigen::VectorXd H4Model12Kinematics::referencePose(const Eigen::VectorXd& g) const {
  return poseAt(0.0, 0.0, -referenceDepth(g[0], g[1], g[2]));
}

Eigen::VectorXd H4Model31Kinematics::referencePose(const Eigen::VectorXd& g) const {
  std::array<Eigen::Vector3d, 4> P;
  P[0].setZero();
  for (int i = 1; i < 4; ++i) P[static_cast<std::size_t>(i)] = g.segment<3>(3 * (i - 1));
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : P) centre += p / 4.0;
  double r = 0.0, L = 0.0, l = 0.0;
  for (int i = 0; i < 4; ++i) {
    const auto s = static_cast<std::size_t>(i);
    const Eigen::Vector2d offset(kH4Epsilon[s] * g[29], kH4Sigma[s] * g[30]);
    r += ((P[s] - centre).head<2>() - offset).norm() / 4.0;
    L += g[17 + i] / 4.0;
    l += g[21 + i] / 4.0;
  }
  return poseAt(centre.x(), centre.y(), centre.z() - referenceDepth(r, L, l));
}

Eigen::VectorXd H4Model31CameraKinematics::referencePose(const Eigen::VectorXd& g) const {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) centre += g.segment<3>(3 * i) / 4.0;
  double r = 0.0, L = 0.0, l = 0.0;
  for (int i = 0; i < 4; ++i) {
    r += (g.segment<3>(3 * i) - centre).head<2>().norm() / 4.0;
    L += g[28 + i] / 4.0;
    l += g[24 + i] / 4.0;
  }
  // P''_i sit about √(h² + d²) farther out than the H corners: subtract the nacelle part.
  r = std::max(0.0, r - g[32]);
  return poseAt(centre.x(), centre.y(), centre.z() - referenceDepth(r, L, l));
}

std::unique_ptr<Mechanism> makeH4Mechanism(H4ModelKind kind, const H4Nominal& nominal) {
  if (!(std::isfinite(nominal.amplification) && nominal.amplification != 0.0))
    throw std::invalid_argument("H4 amplification ratio must be finite and non-zero");
  switch (kind) {
    case H4ModelKind::Model12: {
      H4Model12Kinematics k;
      k.amplification = nominal.amplification;
      return std::make_unique<MechanismAdapter<H4Model12Kinematics>>(k, k.nominal(nominal));
    }
    case H4ModelKind::Model31: {
      H4Model31Kinematics k;
      k.amplification = nominal.amplification;
      return std::make_unique<MechanismAdapter<H4Model31Kinematics>>(k, k.nominal(nominal));
    }
    case H4ModelKind::Model31Camera: {
      if (nominal.amplification != 1.0)
        throw std::invalid_argument("H4 model 31 in the camera frame assumes an amplification ratio of 1 (paper §3.1)");
      H4Model31CameraKinematics k;
      return std::make_unique<MechanismAdapter<H4Model31CameraKinematics>>(k, k.nominal(nominal));
    }
  }
  throw std::invalid_argument("unknown H4 model");
}

}  // namespace mire::mechanism
