// Described mechanisms: the parameter list and its layout, the identified description, the
// default FKM start (described.hpp; doc/mechanisms.md, "Described mechanisms").
#include "mire/mechanism/described.hpp"

#include <cmath>
#include <stdexcept>

#include "described_kinematics.hpp"

namespace mire::mechanism {

namespace {

const char* const kAxes[3] = {"x", "y", "z"};

std::string leg(int i) { return std::to_string(i + 1); }

void addVector(ParameterSet& set, const std::string& prefix, const std::string& suffix, const Eigen::Vector3d& v,
               const std::string& what) {
  for (int k = 0; k < 3; ++k) set.add({prefix + kAxes[k] + suffix, v[k], Unit::Metre, false, what + ", " + kAxes[k]});
}

Eigen::Vector3d vectorOf(const ParameterSet& set, const std::string& prefix, const std::string& suffix) {
  return Eigen::Vector3d(set.value(prefix + "x" + suffix), set.value(prefix + "y" + suffix),
                         set.value(prefix + "z" + suffix));
}

void addLeg(ParameterSet& set, const LegDescription& d, int i, bool gains) {
  const std::string n = leg(i), of = " of leg " + n;
  addVector(set, "a", n, d.base, "base point A" + n + " in B");
  if (d.actuator != LegActuator::Extensible) {
    set.add({"ua" + n, 0.0, Unit::Radian, false, "axis tilt towards e_a" + of});
    set.add({"ub" + n, 0.0, Unit::Radian, false, "axis tilt towards e_b" + of});
  }
  if (d.actuator == LegActuator::Revolute) addVector(set, "arm", n, d.arm, "arm at s = 0" + of);
  if (d.actuator != LegActuator::Extensible) set.add(positiveLength("l" + n, d.rod, "rod length" + of));
  addVector(set, "p", n, d.platform, "platform joint p" + n + " in E");
  if (d.actuator == LegActuator::Extensible)
    set.add({"rho0" + n, d.offset, Unit::Metre, false, "leg " + n + " length at reading 0"});
  else
    set.add({"q0" + n, d.offset, d.actuator == LegActuator::Revolute ? Unit::Radian : Unit::Metre, false,
             "joint offset" + of + " (s = q + q0)"});
  if (gains) set.add({"g" + n, d.gain, Unit::Dimensionless, false, "encoder gain" + of + " (s = g q + q0)"});
}

// The point a leg's joint side sits at for a reading of 0 (carriage, elbow, base joint).
Eigen::Vector3d zeroReadingPoint(const LegDescription& d) {
  switch (d.actuator) {
    case LegActuator::Prismatic:
      return d.base + d.offset * d.axis;
    case LegActuator::Revolute: {
      const Eigen::Vector3d along = d.arm.dot(d.axis) * d.axis, across = d.arm - along;
      return d.base + along + std::cos(d.offset) * across + std::sin(d.offset) * d.axis.cross(across);
    }
    case LegActuator::Extensible:
      return d.base;
  }
  return d.base;
}

}  // namespace

void axisTiltBasis(const Eigen::Vector3d& axis, Eigen::Vector3d* e_a, Eigen::Vector3d* e_b) {
  const Eigen::Vector3d u = axis.normalized();
  int least = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(u[k]) < std::abs(u[least])) least = k;
  const Eigen::Vector3d c = Eigen::Vector3d::Unit(least);
  *e_a = (c - c.dot(u) * u).normalized();
  *e_b = u.cross(*e_a);
}

ParameterSet describedParameters(const MechanismDescription& description) {
  validateMechanismDescription(description);
  ParameterSet set;
  for (std::size_t i = 0; i < description.legs.size(); ++i)
    addLeg(set, description.legs[i], static_cast<int>(i), description.gains);
  return set;
}

MechanismDescription describedWithParameters(const MechanismDescription& description, const ParameterSet& geometric) {
  MechanismDescription out = description;
  for (std::size_t i = 0; i < out.legs.size(); ++i) {
    LegDescription& d = out.legs[i];
    const std::string n = leg(static_cast<int>(i));
    d.base = vectorOf(geometric, "a", n);
    d.platform = vectorOf(geometric, "p", n);
    d.offset = geometric.value((d.actuator == LegActuator::Extensible ? "rho0" : "q0") + n);
    if (out.gains) d.gain = geometric.value("g" + n);
    if (d.actuator == LegActuator::Extensible) continue;
    Eigen::Vector3d e_a, e_b;
    axisTiltBasis(d.axis, &e_a, &e_b);
    d.axis = (d.axis + geometric.value("ua" + n) * e_a + geometric.value("ub" + n) * e_b).normalized();
    d.rod = geometric.value("l" + n);
    if (d.actuator == LegActuator::Revolute) d.arm = vectorOf(geometric, "arm", n);
  }
  validateMechanismDescription(out);
  return out;
}

namespace detail {

DescribedKinematics describedKinematics(const MechanismDescription& description) {
  const ParameterSet set = describedParameters(description);
  DescribedKinematics k;
  k.full = description.platform == DescribedPlatform::Full;
  for (std::size_t i = 0; i < description.legs.size(); ++i) {
    const LegDescription& d = description.legs[i];
    const std::string n = leg(static_cast<int>(i));
    const auto at = [&set](const std::string& name) { return static_cast<int>(set.index(name)); };
    DescribedLeg l;
    l.actuator = d.actuator;
    l.branch = d.branch;
    l.axis0 = d.axis;
    axisTiltBasis(d.axis, &l.e_a, &l.e_b);
    l.base = at("ax" + n);
    l.platform = at("px" + n);
    l.offset = at((d.actuator == LegActuator::Extensible ? "rho0" : "q0") + n);
    if (description.gains) l.gain = at("g" + n);
    if (d.actuator != LegActuator::Extensible) {
      l.tilt = at("ua" + n);
      l.rod = at("l" + n);
    }
    if (d.actuator == LegActuator::Revolute) l.arm = at("armx" + n);
    k.legs.push_back(l);
  }
  return k;
}

PoseVector describedDefaultHome(const MechanismDescription& description) {
  const DescribedKinematics k = describedKinematics(description);
  const Eigen::VectorXd g = describedParameters(description).values();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double length = 0.0;
  for (const LegDescription& d : description.legs) {
    centre += zeroReadingPoint(d) - d.platform;
    length += d.actuator == LegActuator::Extensible ? std::abs(d.offset) : d.rod;
  }
  const double n = static_cast<double>(description.legs.size());
  centre /= n;
  length /= n;
  PoseVector pose = PoseVector::Zero();
  const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<double> q(description.legs.size());
  // Hexapods stand on their base, a Delta hangs below it; the mirror pose through the base
  // plane has the same extensible-leg lengths, so the side is not left to the search.
  const double first = description.platform == DescribedPlatform::Full ? 1.0 : -1.0;
  for (const double side : {first, -first})
    for (const double fraction : {0.9, 0.7, 0.5, 0.3}) {
      const Eigen::Vector3d t = centre + side * fraction * length * Eigen::Vector3d::UnitZ();
      if (k.inverseKinematics(g.data(), identity, t.data(), q.data()) == 0) {
        pose.head<3>() = t;
        return pose;
      }
    }
  pose.head<3>() = centre;
  return pose;
}

}  // namespace detail

}  // namespace mire::mechanism
