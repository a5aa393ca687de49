// legs.csv reader and writer (legs_csv.hpp, doc/file-formats.md).
#include "mire/mechanism/legs_csv.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

namespace mire::mechanism {

namespace {

constexpr const char* kCovariance[10] = {"c11", "c12", "c13", "c14", "c22", "c23", "c24", "c33", "c34", "c44"};

LegObservation readRow(const support::CsvTable& table, std::size_t row, int leg_count) {
  const auto number = [&](const char* name) { return table.number(row, table.column(name)); };
  LegObservation o;
  o.pose_id = table.rows[row][table.column("pose_id")];
  const double leg = number("leg");
  if (leg != std::floor(leg) || leg < 1 || leg > leg_count)
    throw std::runtime_error(table.where(row) + ": leg " + table.rows[row][table.column("leg")] +
                             " is not a leg number 1.." + std::to_string(leg_count));
  o.leg = static_cast<int>(leg) - 1;
  const Eigen::Vector3d d(number("dx"), number("dy"), number("dz"));
  const Eigen::Vector3d m(number("mx_m"), number("my_m"), number("mz_m"));
  if (std::abs(d.norm() - 1.0) > 1e-6)
    throw std::runtime_error(table.where(row) + ": the direction (dx, dy, dz) has length " + std::to_string(d.norm()) +
                             ", expected 1");
  if (std::abs(d.dot(m)) > 1e-6 * std::max(1.0, m.norm()))
    throw std::runtime_error(table.where(row) +
                             ": the moment (mx_m, my_m, mz_m) is not perpendicular to the direction");
  o.line = {d.normalized(), m - m.dot(d.normalized()) * d.normalized()};
  int k = 0;
  for (int r = 0; r < 4; ++r)
    for (int c = r; c < 4; ++c) o.covariance(r, c) = o.covariance(c, r) = number(kCovariance[k++]);
  if (Eigen::LLT<Eigen::Matrix4d>(o.covariance).info() != Eigen::Success)
    throw std::runtime_error(table.where(row) + ": the covariance c11..c44 is not positive definite");
  return o;
}

}  // namespace

std::vector<LegObservation> readLegsCsv(const std::filesystem::path& legs_csv, int leg_count) {
  const support::CsvTable table = support::readCsv(legs_csv);
  for (const char* name : {"pose_id", "leg", "dx", "dy", "dz", "mx_m", "my_m", "mz_m"}) table.column(name);
  for (const char* name : kCovariance) table.column(name);
  std::vector<LegObservation> out;
  std::set<std::pair<std::string, int>> seen;
  for (std::size_t row = 0; row < table.rows.size(); ++row) {
    LegObservation o = readRow(table, row, leg_count);
    if (!seen.insert({o.pose_id, o.leg}).second)
      throw std::runtime_error(table.where(row) + ": pose '" + o.pose_id + "', leg " + std::to_string(o.leg + 1) +
                               " appears twice");
    out.push_back(std::move(o));
  }
  if (out.empty()) throw std::runtime_error(legs_csv.string() + ": no leg observation");
  return out;
}

void writeLegsCsv(const std::filesystem::path& legs_csv, const std::vector<LegObservation>& legs) {
  std::ostringstream out;
  out << "pose_id,leg,dx,dy,dz,mx_m,my_m,mz_m";
  for (const char* c : kCovariance) out << ',' << c;
  out << '\n';
  for (const LegObservation& o : legs) {
    out << o.pose_id << ',' << o.leg + 1;
    for (int k = 0; k < 3; ++k) out << ',' << support::formatNumber(o.line.direction[k]);
    for (int k = 0; k < 3; ++k) out << ',' << support::formatNumber(o.line.moment[k]);
    for (int r = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c) out << ',' << support::formatNumber(o.covariance(r, c));
    out << '\n';
  }
  support::writeFileAtomically(legs_csv, out.str());
}

}  // namespace mire::mechanism
