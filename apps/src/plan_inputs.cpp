// Readers of the plan/select inputs (doc/plan-and-select.md), on the strict YAML layer of
// support/ (doc/file-formats.md) and the parameter-file reader of mechanism/io.hpp.
#include "plan_inputs.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/yaml.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace mech = mire::mechanism;
using support::kRadiansPerDegree;

mech::Interval interval(const support::YamlNode& map, const std::string& key, double scale) {
  const support::YamlNode node = map.at(key);
  const std::vector<double> v = node.asDoubles({-1e3, 1e3});
  if (v.size() != 2) node.fail("expected [min, max]");
  if (v[0] > v[1]) node.fail("min is greater than max");
  return {v[0] * scale, v[1] * scale};
}

}  // namespace

mech::DesignModel readDesignModel(const std::string& name, const std::filesystem::path& nominal_yaml) {
  pipeline::ModelChoice choice;
  choice.model = mech::modelInfo(name).name;  // "unknown model 'x' (known: ...)"
  if (!nominal_yaml.empty()) pipeline::applyNominalFile(choice, nominal_yaml);
  mech::DesignModel model = mech::makeDesignModel(name, choice.h4);
  model.registered = choice.registered();
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
  // A single point gives identical candidates: nothing to choose, and the mounting guess
  // from them would fail with a message about orientations the user never measured.
  bool single_point = w.x.min == w.x.max && w.y.min == w.y.max && w.z.min == w.z.max;
  for (const mech::Interval& r : w.rotations) single_point = single_point && r.min == r.max;
  if (single_point)
    root.fail("the workspace is a single point (every range has min = max): give ranges to choose poses from");
  if (prismatic)
    w.joint_margin = root.optionalNumber("joint_margin_m", {0.0, 1.0}).value_or(1e-3);
  else
    w.joint_margin = root.optionalNumber("joint_margin_deg", {0.0, 90.0}).value_or(1.0) * kRadiansPerDegree;
  return w;
}

mech::MountingGuess readMountingYaml(const std::filesystem::path& path, bool camera_on_effector) {
  const support::YamlFile file = support::YamlFile::load(path);
  const support::YamlNode& root = file.rootMap();
  const mech::ExternalParameterization form(camera_on_effector ? mech::ExternalForm::CameraOnEffector
                                                               : mech::ExternalForm::Full);
  const std::vector<std::string> names = form.parameters().names();
  root.checkKeys(names);
  Eigen::VectorXd v(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k)
    v[static_cast<Eigen::Index>(k)] = root.number(names[k], {-100.0, 100.0});
  mech::MountingGuess m;
  m.camera_on_effector = camera_on_effector;
  // With the camera on the effector the form's chain is bTm and cTe (external.hpp).
  if (camera_on_effector) {
    m.bTm = form.baseFromCamera(v);
    m.eTc = form.targetFromEffector(v).inverse();
  } else {
    m.bTc = form.baseFromCamera(v);
    m.mTe = form.targetFromEffector(v);
  }
  return m;
}

mech::DesignModel withMounting(mech::DesignModel model, bool camera_on_effector, const std::string& what) {
  if (!camera_on_effector) return model;
  try {
    return mech::withCameraOnEffector(std::move(model));
  } catch (const std::invalid_argument& refused) {
    throw UsageError("--mounting camera-on-effector: " + what + " " + refused.what());
  }
}

}  // namespace mire::app
