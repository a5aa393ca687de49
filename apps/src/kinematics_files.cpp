// Files of `mire fkm` / `mire ikm` (doc/mechanisms.md).
#include "kinematics_files.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

namespace mire::app {
namespace {

// Beyond these a value is in another unit: a turn is 2π rad; no mechanism mire models spans
// 100 m (its lengths in millimetres would).
constexpr double kMaxRadians = 2.0 * support::kPi;
constexpr double kMaxMetres = 100.0;

void checkUnit(double value, mechanism::Unit unit, const std::string& where, const std::string& column) {
  if (unit == mechanism::Unit::Radian && std::abs(value) > kMaxRadians)
    throw std::runtime_error(where + ": " + column + " = " + support::formatNumber(value, 6) +
                             " rad is more than a turn (2π): are the values in degrees? (" + column + " is in radians)");
  if (unit == mechanism::Unit::Metre && std::abs(value) > kMaxMetres)
    throw std::runtime_error(where + ": " + column + " = " + support::formatNumber(value, 6) +
                             " m is more than 100 m: are the values in millimetres? (" + column + " is in metres)");
}

}  // namespace

void checkJointUnits(const std::vector<mechanism::JointRow>& rows, const mechanism::Mechanism& m,
                     const std::string& file) {
  const auto units = m.jointUnits();
  const auto columns = m.jointColumnNames();
  for (const auto& row : rows)
    for (Eigen::Index k = 0; k < row.joints.size() && static_cast<std::size_t>(k) < units.size(); ++k)
      checkUnit(row.joints[k], units[static_cast<std::size_t>(k)], file + ":" + std::to_string(row.line),
                columns[static_cast<std::size_t>(k)]);
}

std::vector<std::string> poseColumnNames(const mechanism::Mechanism& m) {
  std::vector<std::string> names;
  const auto components = m.poseComponentNames();
  const auto units = m.poseComponentUnits();
  for (std::size_t k = 0; k < components.size(); ++k)
    names.push_back(components[k] + "_" + mechanism::unitName(units[k]));
  return names;
}

std::vector<EffectorRow> readEffectorCsv(const std::filesystem::path& path, const mechanism::Mechanism& m,
                                         const std::string& group_column) {
  const support::CsvTable table = support::readCsv(path);
  const std::size_t id_col = table.column("pose_id");
  const std::size_t group_col = group_column.empty() ? id_col : table.column(group_column);
  std::vector<std::size_t> cols;
  for (const std::string& name : poseColumnNames(m)) cols.push_back(table.column(name));
  std::vector<EffectorRow> rows;
  std::set<std::string> seen;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    EffectorRow row;
    row.id = table.rows[r][id_col];
    row.line = static_cast<int>(table.line_numbers[r]);
    if (row.id.empty()) throw std::runtime_error(table.where(r) + ": empty pose_id");
    if (!seen.insert(row.id).second) throw std::runtime_error(table.where(r) + ": duplicate pose_id '" + row.id + "'");
    if (!group_column.empty()) {
      row.group = table.rows[r][group_col];
      if (row.group.empty()) throw std::runtime_error(table.where(r) + ": empty " + group_column);
    }
    row.pose.resize(static_cast<Eigen::Index>(cols.size()));
    const auto units = m.poseComponentUnits();
    for (std::size_t k = 0; k < cols.size(); ++k) {
      row.pose[static_cast<Eigen::Index>(k)] = table.number(r, cols[k]);
      checkUnit(row.pose[static_cast<Eigen::Index>(k)], units[k], table.where(r), table.header[cols[k]]);
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw std::runtime_error(path.string() + ": no rows");
  return rows;
}

}  // namespace mire::app
