// Mechanism parameter files (io.hpp; keys: doc/file-formats.md): read through
// mire::support's YAML layer, written as plain YAML that PyYAML reads too.
#include "mire/mechanism/io.hpp"

#include "mire/mechanism/registry.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/yaml.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::mechanism {

namespace {

constexpr double kTwoPi = 6.283185307179586476925;

bool listed(const std::vector<std::string>& list, const std::string& key) {
  return std::find(list.begin(), list.end(), key) != list.end();
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// Every key a file may hold for these parameters, for "did you mean" hints.
std::vector<std::string> knownKeys(const ParameterSet& parameters, const std::vector<std::string>& also_allowed) {
  std::vector<std::string> keys = parameterFileMetadataKeys();
  for (const auto& name : parameters.names()) {
    keys.push_back(name);
    keys.push_back("sigma_" + name);
  }
  keys.insert(keys.end(), also_allowed.begin(), also_allowed.end());
  return keys;
}

[[noreturn]] void unknownKey(const ParameterFile& file, const ParameterFileEntry& entry, const ParameterSet& parameters,
                             const std::vector<std::string>& also_allowed) {
  const std::string hint = support::closestName(entry.key, knownKeys(parameters, also_allowed));
  throw std::runtime_error(
      file.where(entry) + ": unknown parameter name '" + entry.key + "'" +
      (hint.empty() ? " (known: " + joined(parameters.names()) + ")" : " (did you mean '" + hint + "'?)"));
}

// `.inf` (or `inf`): the σ of a parameter the data do not determine, as parameterFileString writes it.
bool isInfinite(const ParameterFileEntry& entry) {
  const auto value = support::parseYamlNumber(entry.text);
  return value && std::isinf(*value) && *value > 0.0;
}

// An angle beyond one turn is degrees typed where radians are expected (alpha1: 45).
void checkAngle(const ParameterFile& file, const ParameterFileEntry& entry, const Parameter& parameter, double value) {
  if (parameter.unit != Unit::Radian || std::abs(value) <= kTwoPi) return;
  throw std::runtime_error(file.where(entry) + ": key '" + entry.key + "': " + support::formatMessageNumber(value) +
                           " rad is more than a turn: angles are in radians (if you meant " +
                           support::formatMessageNumber(value) + " degrees, write " +
                           support::formatMessageNumber(value * kTwoPi / 360.0) + ")");
}

// A rod, arm, leg or radius of zero or negative length is a typo or a sign slip, not a robot
// (Parameter::positive); kinematics would still run on it and write confident predictions.
void checkPositive(const ParameterFile& file, const ParameterFileEntry& entry, const Parameter& parameter, double value) {
  if (!parameter.positive || value > 0.0) return;
  throw std::runtime_error(file.where(entry) + ": " + entry.key + " = " + support::formatMessageNumber(value) + " " +
                           unitName(parameter.unit) + ": a length must be positive (" + parameter.description + ")");
}

void checkNoneMissing(const ParameterFile& file, const ParameterSet& parameters,
                      const std::vector<std::string>& set_names, const std::vector<std::string>& may_default) {
  std::vector<std::string> missing;
  for (const auto& name : parameters.names())
    if (!listed(set_names, name) && !listed(may_default, name)) missing.push_back(name);
  if (missing.empty()) return;
  const int line = file.entries.empty() ? 1 : file.entries.front().line;
  throw std::runtime_error(file.path.string() + ":" + std::to_string(line) + ": missing " +
                           (missing.size() == 1 ? "parameter '" : "parameters '") + joined(missing) +
                           "' (a parameter file gives every parameter of the model: " + joined(parameters.names()) +
                           ")");
}

}  // namespace

const ParameterFileEntry* ParameterFile::find(const std::string& key) const {
  for (const auto& entry : entries)
    if (entry.key == key) return &entry;
  return nullptr;
}

std::string ParameterFile::where(const ParameterFileEntry& entry) const {
  return path.string() + ":" + std::to_string(entry.line);
}

double ParameterFile::number(const ParameterFileEntry& entry) const {
  const auto value = support::parseYamlNumber(entry.text);
  if (!value || !std::isfinite(*value))
    throw std::runtime_error(where(entry) + ": key '" + entry.key + "': '" + entry.text + "' is not a finite number");
  return *value;
}

ParameterFile readParameterFile(const std::filesystem::path& path) {
  const support::YamlFile yaml = support::YamlFile::load(path);
  const support::YamlNode& root = yaml.rootMap();
  ParameterFile file;
  file.path = path;
  for (const auto& key : root.keys()) {
    const support::YamlNode value = root.at(key);
    if (!value.isScalar()) value.fail("expected a single value (a number, or text for metadata)");
    ParameterFileEntry entry;
    entry.key = key;
    entry.text = value.asString();
    entry.line = value.line();
    file.entries.push_back(std::move(entry));
  }
  return file;
}

std::string parameterFileModel(const ParameterFile& file) {
  const ParameterFileEntry* entry = file.find("model");
  if (!entry) return {};
  const std::filesystem::path model(entry->text);
  if (!isDescriptionFile(entry->text) || model.is_absolute()) return entry->text;
  return (file.path.parent_path() / model).string();
}

const std::vector<std::string>& parameterFileMetadataKeys() {
  static const std::vector<std::string> keys{
      "model",          "variant",          "external_form", "mechanism", "units", "poses", "rms_joint_residual_rad",
      "residual_scale", "condition_number", "created_by",    "mounting"};
  return keys;
}

std::vector<std::string> applyParameterFile(const ParameterFile& file, ParameterSet& parameters,
                                            const std::vector<std::string>& also_allowed,
                                            const std::vector<std::string>& may_default) {
  const auto& metadata = parameterFileMetadataKeys();
  std::vector<std::string> set_names;
  for (const auto& entry : file.entries) {
    if (listed(metadata, entry.key)) continue;
    const bool is_sigma = entry.key.rfind("sigma_", 0) == 0;
    const std::string name = is_sigma ? entry.key.substr(6) : entry.key;
    const bool known = parameters.contains(name) || listed(also_allowed, name);
    if (known && is_sigma && isInfinite(entry)) continue;  // a σ mire writes for what the data do not determine
    if (parameters.contains(name)) {
      const double value = file.number(entry);
      if (is_sigma) {
        if (value < 0.0)
          throw std::runtime_error(file.where(entry) + ": key '" + entry.key + "': negative standard deviation");
        continue;
      }
      checkAngle(file, entry, parameters.at(name), value);
      checkPositive(file, entry, parameters.at(name), value);
      parameters.setValue(name, value);
      set_names.push_back(name);
      continue;
    }
    if (listed(also_allowed, name)) {
      file.number(entry);  // still must be a finite number
      continue;
    }
    unknownKey(file, entry, parameters, also_allowed);
  }
  checkNoneMissing(file, parameters, set_names, may_default);
  return set_names;
}

std::string parameterFileString(const ParameterSet& parameters, const Eigen::VectorXd& sigma,
                                const std::vector<std::pair<std::string, std::string>>& metadata,
                                const std::string& comment) {
  if (sigma.size() != 0 && sigma.size() != static_cast<Eigen::Index>(parameters.size()))
    throw std::invalid_argument("parameter file: sigma size differs from the parameter count");
  std::ostringstream out;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "# " << line << '\n';
  out << "# Values in SI units (m, rad); each comment gives the human value (mm, deg).\n";
  for (const auto& [key, text] : metadata) out << key << ": " << support::yamlQuoted(text) << "\n";
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const Parameter& p = parameters[i];
    out << p.name << ": " << support::formatYamlNumber(p.value) << "  # " << unitName(p.unit) << ", "
        << support::formatNumber(toDisplay(p.unit, p.value), 8) << ' ' << displayUnitName(p.unit)
        << (p.fixed ? ", fixed" : "") << (p.description.empty() ? "" : "; " + p.description) << '\n';
  }
  for (std::size_t i = 0; i < parameters.size() && sigma.size() > 0; ++i) {
    const Parameter& p = parameters[i];
    if (!(sigma[static_cast<Eigen::Index>(i)] > 0.0)) continue;
    const double s = sigma[static_cast<Eigen::Index>(i)];
    out << "sigma_" << p.name << ": " << support::formatYamlNumber(s) << "  # " << unitName(p.unit) << ", "
        << (std::isfinite(s) ? support::formatNumber(toDisplay(p.unit, s), 4) + ' ' + displayUnitName(p.unit)
                             : "not determined by the data")
        << '\n';
  }
  return out.str();
}

void writeParameterFile(const std::filesystem::path& path, const ParameterSet& parameters, const Eigen::VectorXd& sigma,
                        const std::vector<std::pair<std::string, std::string>>& metadata, const std::string& comment) {
  support::writeFileAtomically(path, parameterFileString(parameters, sigma, metadata, comment));
}

}  // namespace mire::mechanism
