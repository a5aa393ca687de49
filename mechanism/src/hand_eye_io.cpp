// robot_poses.csv (doc/file-formats.md) and the names of the hand-eye mountings; see hand_eye.hpp.
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "mire/mechanism/hand_eye.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

namespace mire::mechanism {

std::string handEyeMountingName(HandEyeMounting mounting) {
  return mounting == HandEyeMounting::CameraOnEffector ? "camera-on-effector" : "camera-fixed";
}

HandEyeMounting parseHandEyeMounting(const std::string& text) {
  if (text == "camera-on-effector") return HandEyeMounting::CameraOnEffector;
  if (text == "camera-fixed") return HandEyeMounting::CameraFixed;
  throw std::invalid_argument("mounting '" + text + "': expected camera-on-effector or camera-fixed");
}

std::vector<std::string> handEyeParameterNames(HandEyeMounting mounting) {
  const bool on_effector = mounting == HandEyeMounting::CameraOnEffector;
  std::vector<std::string> names;
  for (const char* frames : {on_effector ? "EC" : "CB", on_effector ? "BM" : "EM"})
    for (const char* component : {"tx_", "ty_", "tz_", "rx_", "ry_", "rz_"})
      names.push_back(std::string(component) + frames);
  return names;
}

namespace {

// Index of an optional column, or npos.
std::size_t optionalColumn(const support::CsvTable& table, const std::string& name) {
  for (std::size_t c = 0; c < table.header.size(); ++c)
    if (table.header[c] == name) return c;
  return std::string::npos;
}

}  // namespace

std::vector<RobotPoseRow> readRobotPosesCsv(const std::filesystem::path& robot_poses_csv) {
  const support::CsvTable table = support::readCsv(robot_poses_csv);
  const std::size_t id_col = table.column("pose_id");
  std::vector<std::size_t> value_cols;
  for (const char* name : {"tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad"})
    value_cols.push_back(table.column(name));
  const std::size_t sigma_t_col = optionalColumn(table, "sigma_t_mm");
  const std::size_t sigma_r_col = optionalColumn(table, "sigma_r_deg");
  if ((sigma_t_col == std::string::npos) != (sigma_r_col == std::string::npos))
    throw std::runtime_error(robot_poses_csv.string() +
                             ": sigma_t_mm and sigma_r_deg go together: give both columns or neither");
  std::vector<RobotPoseRow> rows;
  std::unordered_map<std::string, int> seen;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    RobotPoseRow row;
    row.id = table.rows[r][id_col];
    row.line = static_cast<int>(table.line_numbers[r]);
    if (row.id.empty()) throw std::runtime_error(table.where(r) + ": empty pose_id");
    const auto [it, inserted] = seen.emplace(row.id, row.line);
    if (!inserted)
      throw std::runtime_error(table.where(r) + ": duplicate pose_id '" + row.id + "' (first on line " +
                               std::to_string(it->second) + ")");
    for (int k = 0; k < 6; ++k) row.bTe[k] = table.number(r, value_cols[static_cast<std::size_t>(k)]);
    if (sigma_t_col != std::string::npos) {
      const double t_mm = table.number(r, sigma_t_col), r_deg = table.number(r, sigma_r_col);
      if (!(t_mm > 0.0) || !(r_deg > 0.0))
        throw std::runtime_error(table.where(r) + ": sigma_t_mm and sigma_r_deg must be > 0");
      row.sigma = RobotPoseSigma{t_mm * 1e-3, r_deg / support::kDegreesPerRadian};
    }
    rows.push_back(row);
  }
  if (rows.empty()) throw std::runtime_error(robot_poses_csv.string() + ": no robot pose");
  return rows;
}

}  // namespace mire::mechanism
