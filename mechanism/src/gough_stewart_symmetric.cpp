// The symmetric hexapod's factory (detail/parallel_kinematics.hpp, doc/mechanisms.md).
#include <cmath>
#include <stdexcept>

#include "mire/mechanism/detail/parallel_kinematics.hpp"
#include "mire/mechanism/mechanism_adapter.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using K = GoughStewartSymmetricKinematics;

// The half-angle of `angles_deg` about the layout's pair centres; throws unless every joint sits
// at centre + sign·(that half-angle).
double halfAngleDeg(const std::array<double, 6>& angles_deg, const std::array<double, 6>& centres,
                    const std::array<double, 6>& signs, const char* which) {
  const auto offset = [&](std::size_t i) { return std::remainder(angles_deg[i] - centres[i], 360.0) * signs[i]; };
  const double half = offset(0);
  for (std::size_t i = 1; i < 6; ++i)
    if (std::abs(offset(i) - half) > 1e-9)
      throw std::invalid_argument(std::string("gough-stewart-symmetric: the nominal's ") + which +
                                  " joints are not in the symmetric layout");
  return half;
}

}  // namespace

ParameterSet goughStewartSymmetricParameters(const GoughStewartNominal& n) {
  constexpr double kDeg = support::kPi / 180.0;
  const double beta_b = halfAngleDeg(n.base_angles_deg, K::kBaseCentreDeg, K::kBaseSign, "base") * kDeg;
  const double beta_p = halfAngleDeg(n.platform_angles_deg, K::kPlatformCentreDeg, K::kPlatformSign, "platform") * kDeg;
  const double ab = n.base_angles_deg[0] * kDeg, ap = n.platform_angles_deg[0] * kDeg;
  const Eigen::Vector3d leg(n.platform_radius * std::cos(ap) - n.base_radius * std::cos(ab),
                            n.platform_radius * std::sin(ap) - n.base_radius * std::sin(ab), n.home_height);
  ParameterSet set;
  set.add({"rb", n.base_radius, Unit::Metre, false, "radius of the base joints' circle"});
  set.add({"beta_b", beta_b, Unit::Radian, false, "half-angle between the two base joints of a pair"});
  set.add({"rp", n.platform_radius, Unit::Metre, false, "radius of the platform joints' circle"});
  set.add({"beta_p", beta_p, Unit::Radian, false, "half-angle between the two platform joints of a pair"});
  set.add({"rho0", leg.norm() - n.home_reading, Unit::Metre, false, "leg length at encoder zero (every leg)"});
  return set;
}

std::unique_ptr<Mechanism> makeGoughStewartSymmetricMechanism(const GoughStewartNominal& nominal) {
  return std::make_unique<MechanismAdapter<K>>(hexapodKinematics<K>(nominal), goughStewartSymmetricParameters(nominal));
}

}  // namespace mire::mechanism
