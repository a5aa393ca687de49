// Mechanism description files (described.hpp; keys: doc/mechanisms.md, "Described mechanisms"):
// read through mire::support's YAML layer, so that every error names the file, the line and the
// key, and written back with numbers that round-trip.
#include "mire/mechanism/described.hpp"

#include "mire/support/constants.hpp"
#include "mire/support/yaml.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::mechanism {

namespace {

using support::YamlNode;

constexpr support::YamlRange kCoordinate{-100.0, 100.0};  // m: a robot, not a building
constexpr support::YamlRange kLength{1e-6, 100.0};        // m
constexpr support::YamlRange kGain{1e-6, 1e6};
constexpr double kTwoPi = 2.0 * support::kPi;

std::string number(double value) { return support::formatYamlNumber(value); }

std::string legLabel(std::size_t i) { return "leg " + std::to_string(i + 1); }

Eigen::Vector3d vector3(const YamlNode& node, const std::string& what) {
  if (!node.isSequence()) node.fail("expected 3 numbers " + what);
  const std::vector<double> values = node.asDoubles(kCoordinate);
  if (values.size() != 3) node.fail("expected 3 numbers " + what + ", not " + std::to_string(values.size()));
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

// "+1", "1", "-1" (and 1.0): YAML readers differ on a leading '+', people write it.
int readBranch(const YamlNode& node) {
  const auto value = node.isScalar() ? support::parseYamlNumber(node.asString()) : std::nullopt;
  if (!value || (*value != 1.0 && *value != -1.0))
    node.fail("'" + (node.isScalar() ? node.asString() : std::string("...")) + "' is not +1 or -1");
  return *value > 0 ? 1 : -1;
}

// Keys a leg may hold, by kind (an extensible leg's length is its joint: no rod, no axis).
std::vector<std::string> legKeys(LegActuator kind) {
  switch (kind) {
    case LegActuator::Prismatic:
      return {"actuator", "base", "axis", "rod", "platform", "branch", "offset", "gain", "stroke"};
    case LegActuator::Revolute:
      return {"actuator", "base", "axis", "arm", "rod", "platform", "branch", "offset", "gain", "stroke"};
    case LegActuator::Extensible:
      return {"actuator", "base", "platform", "offset", "gain", "stroke"};
  }
  return {};
}

LegActuator readActuator(const YamlNode& node) {
  const std::string kind = node.isScalar() ? node.asString() : std::string();
  if (kind == "prismatic") return LegActuator::Prismatic;
  if (kind == "revolute") return LegActuator::Revolute;
  if (kind == "extensible") return LegActuator::Extensible;
  node.fail("'" + kind + "' is not an actuator kind (prismatic, revolute or extensible)");
}

// A key that this leg kind does not take: say why rather than only "unknown key".
void rejectForeignKeys(const YamlNode& leg, LegActuator kind, std::size_t index) {
  const std::vector<std::string> allowed = legKeys(kind);
  for (const std::string& key : leg.keys()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    const bool known = key == "rod" || key == "axis" || key == "arm" || key == "branch";
    if (!known) break;  // checkKeys() names it with a suggestion
    const char* article = kind == LegActuator::Extensible ? ": an " : ": a ";
    leg.at(key).fail(legLabel(index) + article + legActuatorName(kind) + " leg has no '" + key + "'" +
                     (kind == LegActuator::Extensible ? " (its length is the joint: q = |w| - offset)" : ""));
  }
  leg.checkKeys(allowed);
}

// `stroke: [min, max]`, the reading's range in joints.csv's unit (m; rad for a revolute leg).
Eigen::Vector2d readStroke(const YamlNode& node, LegActuator kind, const std::string& label) {
  const bool angle = kind == LegActuator::Revolute;
  const std::string what =
      angle ? "[min, max] (" + label + "'s reading range, rad)" : "[min, max] (" + label + "'s reading range, m)";
  if (!node.isSequence()) node.fail("expected 2 numbers " + what);
  const std::vector<double> values = node.asDoubles(angle ? support::YamlRange{-kTwoPi, kTwoPi} : kCoordinate);
  if (values.size() != 2) node.fail("expected 2 numbers " + what + ", not " + std::to_string(values.size()));
  if (!(values[0] < values[1]))
    node.fail(label + ": the stroke's minimum " + number(values[0]) + " is not below its maximum " + number(values[1]));
  return Eigen::Vector2d(values[0], values[1]);
}

LegDescription readLeg(const YamlNode& leg, std::size_t index, bool gains) {
  leg.requireMap();
  LegDescription out;
  out.actuator = readActuator(leg.at("actuator"));
  rejectForeignKeys(leg, out.actuator, index);
  const std::string label = legLabel(index);
  out.base = vector3(leg.at("base"), "[x, y, z] (" + label + "'s base point A, m)");
  out.platform = vector3(leg.at("platform"), "[x, y, z] (" + label + "'s platform joint p, m)");
  if (out.actuator != LegActuator::Extensible) {
    const YamlNode axis = leg.at("axis");
    out.axis = vector3(axis, "[x, y, z] (" + label + "'s axis u)");
    if (!(out.axis.norm() > 1e-9)) axis.fail(label + ": the axis is zero: a direction is needed");
    out.axis.normalize();
    out.rod = leg.at("rod").asDouble(kLength);
    if (const auto branch = leg.find("branch")) out.branch = readBranch(*branch);
  }
  if (out.actuator == LegActuator::Revolute) {
    const YamlNode arm = leg.at("arm");
    out.arm = vector3(arm, "[x, y, z] (" + label + "'s arm at s = 0, m)");
    const Eigen::Vector3d across = out.arm - out.arm.dot(out.axis) * out.axis;
    if (!(across.norm() > 1e-9)) arm.fail(label + ": the arm lies along the axis: the elbow would not move");
  }
  if (const auto offset = leg.find("offset")) {
    const bool angle = out.actuator == LegActuator::Revolute;
    out.offset = offset->asDouble(angle ? support::YamlRange{-kTwoPi, kTwoPi} : kCoordinate);
  }
  if (const auto gain = leg.find("gain")) {
    if (!gains) gain->fail(label + ": a gain needs 'gains: true' at the top level");
    out.gain = gain->asDouble(kGain);
  }
  if (const auto stroke = leg.find("stroke")) out.stroke = readStroke(*stroke, out.actuator, label);
  return out;
}

PoseVector readHome(const YamlNode& node, DescribedPlatform platform) {
  PoseVector home = PoseVector::Zero();
  if (node.isSequence()) {
    home.head<3>() = vector3(node, "[x, y, z] (m) or {t: [x, y, z], r: [rx, ry, rz]}");
    return home;
  }
  if (!node.isMap()) node.fail("expected [x, y, z] (m) or {t: [x, y, z], r: [rx, ry, rz]}");
  node.checkKeys({"t", "r"});
  home.head<3>() = vector3(node.at("t"), "[x, y, z] (m)");
  if (const auto r = node.find("r")) {
    home.tail<3>() = vector3(*r, "[rx, ry, rz] (a rotation vector, rad)");
    if (platform == DescribedPlatform::Translation && home.tail<3>().norm() > 0.0)
      r->fail("a translation platform keeps the base orientation: no rotation");
  }
  return home;
}

void checkLegCount(const YamlNode& legs, DescribedPlatform platform, std::size_t count) {
  const std::size_t expected = platform == DescribedPlatform::Translation ? 3 : 6;
  if (count != expected)
    legs.fail("a " + describedPlatformName(platform) + " platform needs exactly " + std::to_string(expected) +
              " legs, not " + std::to_string(count));
}

MechanismDescription readDescription(const support::YamlFile& file) {
  const YamlNode& root = file.rootMap();
  root.checkKeys({"name", "platform", "legs", "gains", "home"});
  MechanismDescription out;
  out.name = root.string("name");
  const YamlNode platform = root.at("platform");
  const std::string kind = platform.isScalar() ? platform.asString() : std::string();
  if (kind == "translation")
    out.platform = DescribedPlatform::Translation;
  else if (kind == "full")
    out.platform = DescribedPlatform::Full;
  else
    platform.fail("'" + kind + "' is not a platform kind (translation or full)");
  if (const auto gains = root.find("gains")) out.gains = gains->asBool();
  const YamlNode legs = root.at("legs");
  if (!legs.isSequence()) legs.fail("expected a list of legs (one entry per actuated joint)");
  const std::vector<YamlNode> items = legs.items();
  checkLegCount(legs, out.platform, items.size());
  for (std::size_t i = 0; i < items.size(); ++i) out.legs.push_back(readLeg(items[i], i, out.gains));
  if (const auto home = root.find("home")) out.home = readHome(*home, out.platform);
  return out;
}

// ----- writing -----

std::string vectorText(const Eigen::Vector3d& v) {
  return "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
}

}  // namespace

std::string legActuatorName(LegActuator actuator) {
  switch (actuator) {
    case LegActuator::Prismatic:
      return "prismatic";
    case LegActuator::Revolute:
      return "revolute";
    case LegActuator::Extensible:
      return "extensible";
  }
  return "?";
}

std::string describedPlatformName(DescribedPlatform platform) {
  return platform == DescribedPlatform::Translation ? "translation" : "full";
}

MechanismDescription parseMechanismDescription(const std::string& text, const std::string& name) {
  try {
    MechanismDescription description = readDescription(support::YamlFile::parse(text, name));
    validateMechanismDescription(description);
    return description;
  } catch (const support::YamlError& e) {
    throw std::invalid_argument(e.what());
  }
}

MechanismDescription readMechanismDescription(const std::filesystem::path& file) {
  try {
    MechanismDescription description = readDescription(support::YamlFile::load(file));
    validateMechanismDescription(description);
    return description;
  } catch (const support::YamlError& e) {
    throw std::invalid_argument(e.what());
  }
}

void validateMechanismDescription(const MechanismDescription& d) {
  const auto fail = [&d](const std::string& what) {
    throw std::invalid_argument("mechanism description '" + d.name + "': " + what);
  };
  const std::size_t expected = d.platform == DescribedPlatform::Translation ? 3 : 6;
  if (d.legs.size() != expected)
    fail("a " + describedPlatformName(d.platform) + " platform needs exactly " + std::to_string(expected) +
         " legs, not " + std::to_string(d.legs.size()));
  for (std::size_t i = 0; i < d.legs.size(); ++i) {
    const LegDescription& leg = d.legs[i];
    const std::string label = legLabel(i) + ": ";
    if (!leg.base.allFinite() || !leg.platform.allFinite() || !std::isfinite(leg.offset) || !std::isfinite(leg.gain))
      fail(label + "a non-finite value");
    if (!(leg.gain > 0.0)) fail(label + "the gain must be positive");
    if (leg.stroke && (!leg.stroke->allFinite() || !((*leg.stroke)[0] < (*leg.stroke)[1])))
      fail(label + "the stroke must be two finite readings [min, max] with min < max");
    if (leg.actuator == LegActuator::Extensible) continue;
    if (!leg.axis.allFinite() || std::abs(leg.axis.norm() - 1.0) > 1e-9) fail(label + "the axis must be a unit vector");
    if (!(leg.rod > 0.0) || !std::isfinite(leg.rod)) fail(label + "the rod length must be positive");
    if (leg.branch != 1 && leg.branch != -1) fail(label + "the branch must be +1 or -1");
    if (leg.actuator == LegActuator::Revolute) {
      if (!leg.arm.allFinite()) fail(label + "a non-finite value");
      if (!((leg.arm - leg.arm.dot(leg.axis) * leg.axis).norm() > 1e-9)) fail(label + "the arm lies along the axis");
    }
  }
  if (d.home) {
    if (!d.home->allFinite()) fail("home: a non-finite value");
    if (d.platform == DescribedPlatform::Translation && d.home->tail<3>().norm() > 0.0)
      fail("home: a translation platform keeps the base orientation");
  }
}

std::string MechanismDescription::yamlString() const {
  std::ostringstream out;
  out << "name: " << support::yamlQuoted(name) << "\n";
  out << "platform: " << describedPlatformName(platform) << "\n";
  if (gains) out << "gains: true\n";
  if (home) {
    if (platform == DescribedPlatform::Translation)
      out << "home: " << vectorText(home->head<3>()) << "\n";
    else
      out << "home: {t: " << vectorText(home->head<3>()) << ", r: " << vectorText(home->tail<3>()) << "}\n";
  }
  out << "legs:\n";
  for (const LegDescription& leg : legs) {
    out << "  - actuator: " << legActuatorName(leg.actuator) << "\n";
    out << "    base: " << vectorText(leg.base) << "\n";
    if (leg.actuator != LegActuator::Extensible) out << "    axis: " << vectorText(leg.axis) << "\n";
    if (leg.actuator == LegActuator::Revolute) out << "    arm: " << vectorText(leg.arm) << "\n";
    if (leg.actuator != LegActuator::Extensible) out << "    rod: " << number(leg.rod) << "\n";
    out << "    platform: " << vectorText(leg.platform) << "\n";
    if (leg.actuator != LegActuator::Extensible) out << "    branch: " << (leg.branch > 0 ? "+1" : "-1") << "\n";
    out << "    offset: " << number(leg.offset) << "\n";
    if (gains) out << "    gain: " << number(leg.gain) << "\n";
    if (leg.stroke) out << "    stroke: [" << number((*leg.stroke)[0]) << ", " << number((*leg.stroke)[1]) << "]\n";
  }
  return out.str();
}

}  // namespace mire::mechanism
