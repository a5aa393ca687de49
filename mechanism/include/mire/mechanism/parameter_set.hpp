#pragma once
// Named mechanism parameters (geometric and external) with nominal values, units, fixed
// flags and ties (several names sharing one value, e.g. variant E's single arm length).
// doc/file-formats.md, "Mechanism parameter files": parameter names are the YAML keys; values are SI (m, rad).
#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace mire::mechanism {

enum class Unit { Metre, Radian, Dimensionless };

// "m", "rad" or "1".
std::string unitName(Unit unit);
// Human-facing unit and conversion (RULES: mm and degrees): "mm", "deg" or "1".
std::string displayUnitName(Unit unit);
double toDisplay(Unit unit, double value_in_si);

struct Parameter {
  std::string name;
  double value = 0.0;  // SI
  Unit unit = Unit::Metre;
  bool fixed = false;  // held at `value` during identification
  std::string description;
  // A physical length that only makes sense > 0 (a rod, arm, forearm, leg, radius or half
  // width): parameter files refuse a value <= 0 (doc/file-formats.md). Offsets, positions
  // and angles may take any sign.
  bool positive = false;
};

// A length parameter that must be > 0 (Parameter::positive).
Parameter positiveLength(std::string name, double value, std::string description, bool fixed = false);

// An ordered list of uniquely named parameters. Every accessor taking a name throws
// std::invalid_argument naming the unknown parameter (and listing the known ones);
// every setter rejects non-finite values with std::invalid_argument.
class ParameterSet {
 public:
  ParameterSet() = default;

  // Appends a parameter; throws on a duplicate or empty name or a non-finite value.
  void add(Parameter parameter);
  // Appends all parameters of `other` (same rules as add()); ties are preserved.
  void append(const ParameterSet& other);

  std::size_t size() const { return parameters_.size(); }
  bool contains(const std::string& name) const;
  std::size_t index(const std::string& name) const;
  const Parameter& operator[](std::size_t i) const { return parameters_.at(i); }
  const Parameter& at(const std::string& name) const;
  const std::vector<Parameter>& parameters() const { return parameters_; }
  std::vector<std::string> names() const;

  double value(const std::string& name) const;
  // Sets a value; a tied parameter sets its whole group.
  void setValue(const std::string& name, double value);
  void setFixed(const std::string& name, bool fixed = true);  // whole tie group
  void fix(const std::vector<std::string>& names);
  void freeAll();  // clears every fixed flag

  // Ties the named parameters to one shared value (the first one's value is copied to the
  // others). Units must agree. A tie group is free or fixed as a whole.
  void tie(const std::vector<std::string>& names);
  // Index of the leader (first member) of parameter i's tie group; i itself when untied.
  std::size_t tieLeader(std::size_t i) const { return leader_.at(i); }
  bool isTied(std::size_t i) const;

  Eigen::VectorXd values() const;
  // Sets all values (size must match, all finite); ties are re-synchronised from leaders.
  void setValues(const Eigen::VectorXd& values);

  // The estimated unknowns: one index (the leader) per free tie group, in set order.
  std::vector<std::size_t> freeIndices() const;
  std::size_t freeCount() const { return freeIndices().size(); }
  std::vector<std::string> freeNames() const;
  // Ambient-from-free expansion matrix E (size() x freeCount()): δvalues = E · δfree.
  // Column k has a 1 on every member of free group k.
  Eigen::MatrixXd expansion() const;

 private:
  std::vector<Parameter> parameters_;
  std::vector<std::size_t> leader_;
};

}  // namespace mire::mechanism
