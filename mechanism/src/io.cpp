// Identification files (doc/file-formats.md); see io.hpp.
#include "mire/mechanism/io.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

namespace mire::mechanism {

namespace {

using support::kPi;

std::vector<std::string> jointColumns(int joint_count) {
  std::vector<std::string> names;
  for (int i = 1; i <= joint_count; ++i) names.push_back("q" + std::to_string(i) + "_rad");
  return names;
}

// Row index of every id, rejecting duplicates with both lines.
void checkUniqueId(std::unordered_map<std::string, std::size_t>& seen, const support::CsvTable& table, std::size_t row,
                   const std::string& id, const char* what) {
  if (id.empty()) throw std::runtime_error(table.where(row) + ": empty " + what);
  const auto [it, inserted] = seen.emplace(id, row);
  if (!inserted)
    throw std::runtime_error(table.where(row) + ": duplicate " + what + " '" + id + "' (first on line " +
                             std::to_string(table.line_numbers.at(it->second)) + ")");
}

// Side file of `mire measure`: pose_id,part,row,tx,ty,tz,rx,ry,rz; the `total` part.
std::map<std::string, PoseCovariance> readCovarianceCsv(const std::filesystem::path& path) {
  const support::CsvTable table = support::readCsv(path);
  const std::size_t id_col = table.column("pose_id"), part_col = table.column("part"), row_col = table.column("row");
  const std::vector<std::string> axes{"tx", "ty", "tz", "rx", "ry", "rz"};
  std::vector<std::size_t> value_cols;
  value_cols.reserve(axes.size());
  for (const auto& axis : axes) value_cols.push_back(table.column(axis));
  std::map<std::string, PoseCovariance> covariances;
  std::map<std::string, std::set<int>> rows_seen;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    if (table.rows[r][part_col] != "total") continue;
    const std::string& id = table.rows[r][id_col];
    const std::string& axis = table.rows[r][row_col];
    int index = -1;
    for (int k = 0; k < 6; ++k)
      if (axes[static_cast<std::size_t>(k)] == axis) index = k;
    if (index < 0)
      throw std::runtime_error(table.where(r) + ": column 'row': '" + axis + "' is not one of tx ty tz rx ry rz");
    if (!rows_seen[id].insert(index).second)
      throw std::runtime_error(table.where(r) + ": duplicate row '" + axis + "' of pose '" + id + "'");
    auto& covariance = covariances.try_emplace(id, PoseCovariance::Zero()).first->second;
    for (int k = 0; k < 6; ++k) covariance(index, k) = table.number(r, value_cols[static_cast<std::size_t>(k)]);
  }
  for (const auto& [id, rows] : rows_seen)
    if (rows.size() != 6)
      throw std::runtime_error(path.string() + ": pose '" + id + "' has " + std::to_string(rows.size()) +
                               " of the 6 rows of its 'total' covariance");
  // Named here, with the file: the identification's own check knows only the pose.
  for (const auto& [id, covariance] : covariances)
    if (!covariance.allFinite() || Eigen::LLT<PoseCovariance>(covariance).info() != Eigen::Success)
      throw std::runtime_error(path.string() + ": pose '" + id +
                               "': the 6x6 'total' covariance is not positive definite (a variance <= 0 or rows "
                               "that contradict each other): fix or remove the pose's rows");
  return covariances;
}

}  // namespace

std::vector<PoseRow> readPosesCsv(const std::filesystem::path& poses_csv,
                                  const std::optional<std::filesystem::path>& covariance_csv) {
  const support::CsvTable table = support::readCsv(poses_csv);
  const std::size_t id_col = table.column("pose_id");
  for (const char* name : {"images_used", "images_total", "rms_px"}) table.column(name);  // required by §10
  std::vector<std::size_t> pose_cols, sigma_cols;
  for (const char* name : {"tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad"})
    pose_cols.push_back(table.column(name));
  for (const char* name : {"sigma_tx_mm", "sigma_ty_mm", "sigma_tz_mm", "sigma_rx_deg", "sigma_ry_deg", "sigma_rz_deg"})
    sigma_cols.push_back(table.column(name));
  std::map<std::string, PoseCovariance> side;
  if (covariance_csv) side = readCovarianceCsv(*covariance_csv);

  std::vector<PoseRow> rows;
  rows.reserve(table.rows.size());
  std::unordered_map<std::string, std::size_t> seen(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    PoseRow row;
    row.line = static_cast<int>(table.line_numbers[r]);
    row.observation.id = table.rows[r][id_col];
    checkUniqueId(seen, table, r, row.observation.id, "pose_id");
    for (int k = 0; k < 6; ++k) row.observation.cTm[k] = table.number(r, pose_cols[static_cast<std::size_t>(k)]);
    Eigen::Matrix<double, 6, 1> sigma;
    for (int k = 0; k < 6; ++k) {
      sigma[k] = table.number(r, sigma_cols[static_cast<std::size_t>(k)]);
      if (sigma[k] < 0.0)
        throw std::runtime_error(table.where(r) + ": column '" + table.header[sigma_cols[static_cast<std::size_t>(k)]] +
                                 "': negative standard deviation");
    }
    if (covariance_csv) {
      const auto it = side.find(row.observation.id);
      if (it == side.end())
        throw std::runtime_error(table.where(r) + ": pose '" + row.observation.id + "' has no covariance in " +
                                 covariance_csv->string());
      row.observation.covariance = it->second;
    } else if ((sigma.array() > 0.0).all()) {
      sigma.head<3>() *= 1e-3;
      sigma.tail<3>() *= kPi / 180.0;
      row.observation.covariance = PoseCovariance(sigma.array().square().matrix().asDiagonal());
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw std::runtime_error(poses_csv.string() + ": no pose rows");
  return rows;
}

namespace {

// A joint column (q<i>_rad, q<i>_m) the model does not have: the readings are of another
// mechanism (an H4's four joints given to a three-joint Delta would be read as three).
void requireNoOtherJoints(const support::CsvTable& table, const std::vector<std::string>& joint_columns) {
  for (const std::string& name : table.header) {
    const auto endsWith = [&name](const std::string& tail) {
      return name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
    };
    const bool joint_like = name.size() > 1 && name[0] == 'q' && std::isdigit(static_cast<unsigned char>(name[1])) &&
                            (endsWith("_rad") || endsWith("_m"));
    if (joint_like && std::find(joint_columns.begin(), joint_columns.end(), name) == joint_columns.end())
      throw std::runtime_error(table.path.string() + ": column '" + name + "' is not a joint of the model (" +
                               std::to_string(joint_columns.size()) + " joints: " + joint_columns.front() + ".." +
                               joint_columns.back() + "): the readings are of another mechanism; choose its model");
  }
}

}  // namespace

std::vector<JointRow> readJointsCsv(const std::filesystem::path& joints_csv, int joint_count) {
  return readJointsCsv(joints_csv, jointColumns(joint_count));
}

std::vector<JointRow> readJointsCsv(const std::filesystem::path& joints_csv,
                                    const std::vector<std::string>& joint_columns) {
  const int joint_count = static_cast<int>(joint_columns.size());
  const support::CsvTable table = support::readCsv(joints_csv);
  const std::size_t id_col = table.column("pose_id");
  std::vector<std::size_t> cols;
  cols.reserve(joint_columns.size());
  for (const auto& name : joint_columns) cols.push_back(table.column(name));
  requireNoOtherJoints(table, joint_columns);
  std::vector<JointRow> rows;
  rows.reserve(table.rows.size());
  std::unordered_map<std::string, std::size_t> seen(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    JointRow row;
    row.pose_id = table.rows[r][id_col];
    row.line = static_cast<int>(table.line_numbers[r]);
    checkUniqueId(seen, table, r, row.pose_id, "pose_id");
    row.joints.resize(joint_count);
    for (int k = 0; k < joint_count; ++k) row.joints[k] = table.number(r, cols[static_cast<std::size_t>(k)]);
    rows.push_back(std::move(row));
  }
  return rows;
}

void writeJointsCsv(const std::filesystem::path& joints_csv, const std::vector<std::string>& ids,
                    const std::vector<Eigen::VectorXd>& joints) {
  const int n = joints.empty() ? 4 : static_cast<int>(joints.front().size());
  writeJointsCsv(joints_csv, ids, joints, jointColumns(n));
}

void writeJointsCsv(const std::filesystem::path& joints_csv, const std::vector<std::string>& ids,
                    const std::vector<Eigen::VectorXd>& joints, const std::vector<std::string>& joint_columns) {
  if (ids.size() != joints.size()) throw std::invalid_argument("writeJointsCsv: ids and joints differ in count");
  for (const auto& q : joints)
    if (q.size() != static_cast<Eigen::Index>(joint_columns.size()))
      throw std::invalid_argument("writeJointsCsv: a joint vector does not match the columns");
  std::ostringstream out;
  out << "pose_id";
  for (const auto& name : joint_columns) out << ',' << name;
  out << '\n';
  for (std::size_t k = 0; k < ids.size(); ++k) {
    out << ids[k];
    for (int j = 0; j < joints[k].size(); ++j) out << ',' << support::formatNumber(joints[k][j]);
    out << '\n';
  }
  support::writeFileAtomically(joints_csv, out.str());
}

ObservationSet readObservations(const std::filesystem::path& poses_csv, const std::filesystem::path& joints_csv,
                                const std::optional<std::filesystem::path>& covariance_csv, int joint_count) {
  return readObservations(poses_csv, joints_csv, covariance_csv, jointColumns(joint_count));
}

ObservationSet readObservations(const std::filesystem::path& poses_csv, const std::filesystem::path& joints_csv,
                                const std::optional<std::filesystem::path>& covariance_csv,
                                const std::vector<std::string>& joint_columns) {
  const int joint_count = static_cast<int>(joint_columns.size());
  const auto pose_rows = readPosesCsv(poses_csv, covariance_csv);
  const auto joint_rows = readJointsCsv(joints_csv, joint_columns);
  ObservationSet set;
  set.poses.reserve(pose_rows.size());
  const auto pair = [&](const PoseRow& row, const JointRow& joints) {
    set.poses.push_back(row.observation);
    set.poses.back().joints = joints.joints;
  };
  // The files list the same ids in the same order (as mire writes them): paired row by row.
  // Otherwise by hashed id views. Both linear in the pose count (doc/mechanisms.md "Identify
  // linear in the pose count").
  const bool same_order = pose_rows.size() == joint_rows.size() &&
                          std::equal(pose_rows.begin(), pose_rows.end(), joint_rows.begin(),
                                     [](const PoseRow& p, const JointRow& j) { return p.observation.id == j.pose_id; });
  if (same_order) {
    for (std::size_t i = 0; i < pose_rows.size(); ++i) pair(pose_rows[i], joint_rows[i]);
  } else {
    std::unordered_map<std::string_view, const JointRow*> by_id(joint_rows.size());
    for (const auto& row : joint_rows) by_id[row.pose_id] = &row;
    std::unordered_set<std::string_view> used(pose_rows.size());
    for (const auto& row : pose_rows) {
      const auto it = by_id.find(row.observation.id);
      if (it == by_id.end())
        throw std::runtime_error(poses_csv.string() + ":" + std::to_string(row.line) + ": pose '" + row.observation.id +
                                 "' has no joints in " + joints_csv.string());
      pair(row, *it->second);
      used.insert(row.observation.id);
    }
    for (const auto& row : joint_rows)
      if (!used.count(row.pose_id)) set.unused_joint_ids.push_back(row.pose_id);
  }
  validatePoses(set.poses, joint_count);
  return set;
}

std::vector<LineRecord> readLinesCsv(const std::filesystem::path& lines_csv, int joint_count) {
  return readLinesCsv(lines_csv, jointColumns(joint_count));
}

std::vector<LineRecord> readLinesCsv(const std::filesystem::path& lines_csv,
                                     const std::vector<std::string>& joint_columns) {
  const int joint_count = static_cast<int>(joint_columns.size());
  const support::CsvTable table = support::readCsv(lines_csv);
  const std::size_t id_col = table.column("line_id");
  std::vector<std::size_t> cols;
  cols.reserve(joint_columns.size());
  for (const auto& name : joint_columns) cols.push_back(table.column(name));
  std::vector<LineRecord> lines;
  std::map<std::string, std::size_t> index;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const std::string& id = table.rows[r][id_col];
    if (id.empty()) throw std::runtime_error(table.where(r) + ": empty line_id");
    Eigen::VectorXd q(joint_count);
    for (int k = 0; k < joint_count; ++k) q[k] = table.number(r, cols[static_cast<std::size_t>(k)]);
    const auto [it, inserted] = index.emplace(id, lines.size());
    if (inserted) lines.push_back({id, {}});
    lines[it->second].joints.push_back(q);
  }
  for (const auto& line : lines)
    if (line.joints.size() < 3)
      throw std::runtime_error(lines_csv.string() + ": line '" + line.line_id + "' has " +
                               std::to_string(line.joints.size()) + " points; a straightness needs at least 3");
  if (lines.empty()) throw std::runtime_error(lines_csv.string() + ": no line rows");
  return lines;
}

void writeLinesCsv(const std::filesystem::path& lines_csv, const std::vector<LineRecord>& lines) {
  const int n = lines.empty() || lines.front().joints.empty() ? 4 : static_cast<int>(lines.front().joints.front().size());
  writeLinesCsv(lines_csv, lines, jointColumns(n));
}

void writeLinesCsv(const std::filesystem::path& lines_csv, const std::vector<LineRecord>& lines,
                   const std::vector<std::string>& joint_columns) {
  std::ostringstream out;
  out << "line_id";
  for (const auto& name : joint_columns) out << ',' << name;
  out << '\n';
  for (const auto& line : lines)
    for (const auto& q : line.joints) {
      out << line.line_id;
      for (int j = 0; j < q.size(); ++j) out << ',' << support::formatNumber(q[j]);
      out << '\n';
    }
  support::writeFileAtomically(lines_csv, out.str());
}

}  // namespace mire::mechanism
