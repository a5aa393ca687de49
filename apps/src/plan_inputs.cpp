// Readers of the plan/select inputs (doc/plan-and-select.md), on the strict YAML layer of
// support/ (doc/file-formats.md) and the parameter-file reader of mechanism/io.hpp.
#include "plan_inputs.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/yaml.hpp"

namespace mire::app {
namespace {

namespace mech = mire::mechanism;
using support::kRadiansPerDegree;

// Keys every parameter file may carry besides the model's geometry: mounting values.
std::vector<std::string> mountingKeys() {
  std::vector<std::string> keys{"amplification"};
  for (auto form : {mech::ExternalForm::AxisAligned, mech::ExternalForm::Full, mech::ExternalForm::CameraFrame})
    for (const auto& n : mech::ExternalParameterization(form).parameters().names()) keys.push_back(n);
  return keys;
}

mech::H4Nominal h4NominalFrom(const mech::ParameterSet& g, const mech::ParameterFile& file) {
  mech::H4Nominal n;
  n.R = g.value("R");
  n.L = g.value("L");
  n.l = g.value("l");
  n.h = g.value("h");
  n.d = g.value("d");
  for (int i = 0; i < 4; ++i) {
    n.alpha[static_cast<std::size_t>(i)] = g.value("alpha" + std::to_string(i + 1));
    n.q0[static_cast<std::size_t>(i)] = g.value("q0" + std::to_string(i + 1));
  }
  if (const auto* entry = file.find("amplification")) n.amplification = file.number(*entry);
  return n;
}

// Model-12 values of an H4 parameter file; mounting keys (an identified file's) are ignored.
mech::H4Nominal h4NominalFromFile(const mech::ParameterFile& file) {
  mech::ParameterSet g = mech::h4Model12Parameters(mech::H4Nominal{});
  mech::applyParameterFile(file, g, mountingKeys());
  return h4NominalFrom(g, file);
}

mech::Interval interval(const support::YamlNode& map, const std::string& key, double scale) {
  const support::YamlNode node = map.at(key);
  const std::vector<double> v = node.asDoubles({-1e3, 1e3});
  if (v.size() != 2) node.fail("expected [min, max]");
  if (v[0] > v[1]) node.fail("min is greater than max");
  return {v[0] * scale, v[1] * scale};
}

}  // namespace

mech::H4Nominal readH4Nominal(const std::filesystem::path& path) {
  return h4NominalFromFile(mech::readParameterFile(path));
}

mech::DesignModel readDesignModel(const std::string& name, const std::filesystem::path& nominal_yaml) {
  mech::makeRegisteredModel(name);  // "unknown model 'x' (known: ...)"
  if (nominal_yaml.empty()) return mech::makeDesignModel(name);
  const mech::ParameterFile file = mech::readParameterFile(nominal_yaml);
  if (mech::modelInfo(name).h4_nominal) return mech::makeDesignModel(name, h4NominalFromFile(file));
  mech::DesignModel model = mech::makeDesignModel(name);
  mech::applyParameterFile(file, model.registered.nominal, mountingKeys());
  return model;
}

mech::Workspace readWorkspaceYaml(const std::filesystem::path& path, const mech::Mechanism& mechanism) {
  const support::YamlFile file = support::YamlFile::load(path);
  const support::YamlNode& root = file.rootMap();
  std::vector<std::string> rotations;
  if (mechanism.motionType() == mech::MotionType::Schoenflies) rotations = {"theta_deg"};
  if (mechanism.motionType() == mech::MotionType::Spatial) rotations = {"rx_deg", "ry_deg", "rz_deg"};
  const bool prismatic = mechanism.jointUnits().front() == mech::Unit::Metre;
  std::vector<std::string> known{"shape", "x_m", "y_m", "z_m", prismatic ? "joint_margin_m" : "joint_margin_deg"};
  known.insert(known.end(), rotations.begin(), rotations.end());
  root.checkKeys(known);
  mech::Workspace w;
  if (const auto shape = root.find("shape")) {
    const std::string s = shape->asString();
    if (s == "cylinder")
      w.shape = mech::Workspace::Shape::Cylinder;
    else if (s != "box")
      shape->fail("'" + s + "': expected box or cylinder");
  }
  w.x = interval(root, "x_m", 1.0);
  w.y = interval(root, "y_m", 1.0);
  w.z = interval(root, "z_m", 1.0);
  for (const std::string& key : rotations) w.rotations.push_back(interval(root, key, kRadiansPerDegree));
  if (prismatic)
    w.joint_margin = root.optionalNumber("joint_margin_m", {0.0, 1.0}).value_or(1e-3);
  else
    w.joint_margin = root.optionalNumber("joint_margin_deg", {0.0, 90.0}).value_or(1.0) * kRadiansPerDegree;
  return w;
}

mech::MountingGuess readMountingYaml(const std::filesystem::path& path) {
  const support::YamlFile file = support::YamlFile::load(path);
  const support::YamlNode& root = file.rootMap();
  const std::vector<std::string> names = mech::ExternalParameterization(mech::ExternalForm::Full).parameters().names();
  root.checkKeys(names);
  Eigen::VectorXd v(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k)
    v[static_cast<Eigen::Index>(k)] = root.number(names[k], {-100.0, 100.0});
  const mech::ExternalParameterization full(mech::ExternalForm::Full);
  mech::MountingGuess m;
  m.bTc = full.baseFromCamera(v);
  m.mTe = full.targetFromEffector(v);
  return m;
}

}  // namespace mire::app
