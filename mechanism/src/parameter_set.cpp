#include "mire/mechanism/parameter_set.hpp"
#include "mire/support/constants.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace mire::mechanism {

std::string unitName(Unit unit) {
  switch (unit) {
    case Unit::Metre:
      return "m";
    case Unit::Radian:
      return "rad";
    case Unit::Dimensionless:
      return "1";
  }
  return "?";
}

std::string displayUnitName(Unit unit) {
  switch (unit) {
    case Unit::Metre:
      return "mm";
    case Unit::Radian:
      return "deg";
    case Unit::Dimensionless:
      return "1";
  }
  return "?";
}

double toDisplay(Unit unit, double value_in_si) {
  switch (unit) {
    case Unit::Metre:
      return value_in_si * 1e3;
    case Unit::Radian:
      return value_in_si * 180.0 / support::kPi;
    case Unit::Dimensionless:
      return value_in_si;
  }
  return value_in_si;
}

Parameter positiveLength(std::string name, double value, std::string description, bool fixed) {
  return Parameter{std::move(name), value, Unit::Metre, fixed, std::move(description), true};
}

namespace {

void requireFinite(const std::string& name, double value) {
  if (!std::isfinite(value)) throw std::invalid_argument("parameter '" + name + "': value is not finite");
}

}  // namespace

void ParameterSet::add(Parameter parameter) {
  if (parameter.name.empty()) throw std::invalid_argument("parameter with an empty name");
  if (contains(parameter.name)) throw std::invalid_argument("parameter '" + parameter.name + "' defined twice");
  requireFinite(parameter.name, parameter.value);
  leader_.push_back(parameters_.size());
  parameters_.push_back(std::move(parameter));
}

void ParameterSet::append(const ParameterSet& other) {
  const std::size_t offset = parameters_.size();
  for (const Parameter& p : other.parameters_) add(p);
  for (std::size_t i = 0; i < other.size(); ++i) leader_[offset + i] = offset + other.leader_[i];
}

bool ParameterSet::contains(const std::string& name) const {
  for (const Parameter& p : parameters_)
    if (p.name == name) return true;
  return false;
}

std::size_t ParameterSet::index(const std::string& name) const {
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (parameters_[i].name == name) return i;
  std::string known;
  for (const Parameter& p : parameters_) known += (known.empty() ? "" : ", ") + p.name;
  throw std::invalid_argument("unknown parameter '" + name + "' (known: " + known + ")");
}

const Parameter& ParameterSet::at(const std::string& name) const { return parameters_[index(name)]; }

std::vector<std::string> ParameterSet::names() const {
  std::vector<std::string> out;
  for (const Parameter& p : parameters_) out.push_back(p.name);
  return out;
}

double ParameterSet::value(const std::string& name) const { return at(name).value; }

void ParameterSet::setValue(const std::string& name, double value) {
  requireFinite(name, value);
  const std::size_t leader = leader_[index(name)];
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (leader_[i] == leader) parameters_[i].value = value;
}

void ParameterSet::setFixed(const std::string& name, bool fixed) {
  const std::size_t leader = leader_[index(name)];
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (leader_[i] == leader) parameters_[i].fixed = fixed;
}

void ParameterSet::fix(const std::vector<std::string>& names) {
  for (const std::string& n : names) index(n);  // validate all first: nothing changes on error
  for (const std::string& n : names) setFixed(n, true);
}

void ParameterSet::freeAll() {
  for (Parameter& p : parameters_) p.fixed = false;
}

void ParameterSet::tie(const std::vector<std::string>& names) {
  if (names.size() < 2) throw std::invalid_argument("a tie needs at least two parameters");
  std::vector<std::size_t> members;
  members.reserve(names.size());
  for (const std::string& n : names) members.push_back(index(n));
  for (std::size_t m : members) {
    if (parameters_[m].unit != parameters_[members[0]].unit)
      throw std::invalid_argument("cannot tie '" + parameters_[m].name + "' and '" + parameters_[members[0]].name +
                                  "': units differ");
    if (leader_[m] != m || isTied(m))
      throw std::invalid_argument("parameter '" + parameters_[m].name + "' is already tied");
  }
  const std::size_t leader = *std::min_element(members.begin(), members.end());
  for (std::size_t m : members) {
    leader_[m] = leader;
    parameters_[m].value = parameters_[members[0]].value;
    parameters_[m].fixed = parameters_[members[0]].fixed;
  }
}

bool ParameterSet::isTied(std::size_t i) const {
  for (std::size_t j = 0; j < parameters_.size(); ++j)
    if (j != i && leader_[j] == leader_.at(i)) return true;
  return false;
}

Eigen::VectorXd ParameterSet::values() const {
  Eigen::VectorXd v(static_cast<Eigen::Index>(parameters_.size()));
  for (std::size_t i = 0; i < parameters_.size(); ++i) v[static_cast<Eigen::Index>(i)] = parameters_[i].value;
  return v;
}

void ParameterSet::setValues(const Eigen::VectorXd& values) {
  if (static_cast<std::size_t>(values.size()) != parameters_.size())
    throw std::invalid_argument("parameter vector has " + std::to_string(values.size()) + " values, expected " +
                                std::to_string(parameters_.size()));
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    requireFinite(parameters_[i].name, values[static_cast<Eigen::Index>(i)]);
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    parameters_[i].value = values[static_cast<Eigen::Index>(leader_[i])];
}

std::vector<std::size_t> ParameterSet::freeIndices() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (leader_[i] == i && !parameters_[i].fixed) out.push_back(i);
  return out;
}

std::vector<std::string> ParameterSet::freeNames() const {
  std::vector<std::string> out;
  for (std::size_t i : freeIndices()) out.push_back(parameters_[i].name);
  return out;
}

Eigen::MatrixXd ParameterSet::expansion() const {
  const std::vector<std::size_t> free = freeIndices();
  Eigen::MatrixXd E =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(parameters_.size()), static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k)
    for (std::size_t i = 0; i < parameters_.size(); ++i)
      if (leader_[i] == free[k]) E(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = 1.0;
  return E;
}

}  // namespace mire::mechanism
