#include "mire/metrology/poses_csv.hpp"

#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace mire::metrology {
namespace {

constexpr double kMillimetresPerMetre = 1000.0;
constexpr double kDegreesPerRadian = 180.0 / M_PI;
const char* const kComponents[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};

// σ of (t, r) in mm and degrees.
Eigen::Matrix<double, 6, 1> humanSigmas(const Matrix6d& covariance) {
  Eigen::Matrix<double, 6, 1> sigma = PoseEstimate::sigmas(covariance);
  sigma.head<3>() *= kMillimetresPerMetre;
  sigma.tail<3>() *= kDegreesPerRadian;
  return sigma;
}

std::string number(double value) { return support::formatNumber(value, 17); }
std::string shortNumber(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return support::formatNumber(value, 6);
}

}  // namespace

std::string posesCsvString(const std::vector<MeasuredPose>& poses) {
  std::ostringstream out;
  out << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,"
         "sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px,"
         "sigma_pixel_tx_mm,sigma_pixel_ty_mm,sigma_pixel_tz_mm,sigma_pixel_rx_deg,sigma_pixel_ry_deg,"
         "sigma_pixel_rz_deg,sigma_intrinsics_tx_mm,sigma_intrinsics_ty_mm,sigma_intrinsics_tz_mm,"
         "sigma_intrinsics_rx_deg,sigma_intrinsics_ry_deg,sigma_intrinsics_rz_deg,reduced_chi2,features,"
         "ambiguous,ambiguity_ratio\n";
  for (const MeasuredPose& pose : poses) {
    const PoseEstimate& e = pose.estimate;
    if (pose.pose_id.find_first_of(",\n\"") != std::string::npos)
      throw std::invalid_argument("pose id '" + pose.pose_id + "' contains a comma, quote or newline");
    out << pose.pose_id << ',' << pose.images_used << ',' << pose.images_total;
    for (int i = 0; i < 3; ++i) out << ',' << number(e.translation[i]);
    for (int i = 0; i < 3; ++i) out << ',' << number(e.rotation_vector[i]);
    const auto total = humanSigmas(e.covariance);
    for (int i = 0; i < 6; ++i) out << ',' << shortNumber(total[i]);
    out << ',' << shortNumber(e.rms_px);
    const auto pixel = humanSigmas(e.covariance_pixel_noise);
    for (int i = 0; i < 6; ++i) out << ',' << shortNumber(pixel[i]);
    const auto intrinsics = humanSigmas(e.covariance_intrinsics);
    for (int i = 0; i < 6; ++i) out << ',' << shortNumber(intrinsics[i]);
    out << ',' << shortNumber(e.reduced_chi2) << ',' << e.feature_count << ',' << (e.ambiguous ? 1 : 0) << ','
        << shortNumber(e.ambiguity_cost_ratio) << '\n';
  }
  return out.str();
}

std::string posesCovarianceCsvString(const std::vector<MeasuredPose>& poses) {
  std::ostringstream out;
  out << "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
  for (const MeasuredPose& pose : poses) {
    const std::pair<const char*, const Matrix6d*> parts[] = {
        {"total", &pose.estimate.covariance},
        {"features", &pose.estimate.covariance_noise},
        {"intrinsics", &pose.estimate.covariance_intrinsics},
        {"pixel_noise", &pose.estimate.covariance_pixel_noise}};
    for (const auto& [name, matrix] : parts)
      for (int r = 0; r < 6; ++r) {
        out << pose.pose_id << ',' << name << ',' << kComponents[r];
        for (int c = 0; c < 6; ++c) out << ',' << number((*matrix)(r, c));
        out << '\n';
      }
  }
  return out.str();
}

void writePosesCsv(const std::filesystem::path& path, const std::vector<MeasuredPose>& poses) {
  support::writeFileAtomically(path, posesCsvString(poses));
}

void writePosesCovarianceCsv(const std::filesystem::path& path, const std::vector<MeasuredPose>& poses) {
  support::writeFileAtomically(path, posesCovarianceCsvString(poses));
}

std::filesystem::path covarianceSidePath(const std::filesystem::path& poses_csv) {
  std::filesystem::path result = poses_csv;
  result.replace_filename(poses_csv.stem().string() + "_covariance.csv");
  return result;
}

std::vector<PoseRecord> readPosesCsv(const std::filesystem::path& path, const std::filesystem::path& covariance_csv) {
  const support::CsvTable table = support::readCsv(path);
  const std::size_t id_column = table.column("pose_id");
  const std::size_t used_column = table.column("images_used");
  const std::size_t total_column = table.column("images_total");
  const char* const value_names[6] = {"tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad"};
  const char* const sigma_names[6] = {"sigma_tx_mm", "sigma_ty_mm", "sigma_tz_mm",
                                      "sigma_rx_deg", "sigma_ry_deg", "sigma_rz_deg"};
  std::size_t value_columns[6], sigma_columns[6];
  for (int i = 0; i < 6; ++i) {
    value_columns[i] = table.column(value_names[i]);
    sigma_columns[i] = table.column(sigma_names[i]);
  }
  const std::size_t rms_column = table.column("rms_px");
  std::vector<PoseRecord> records;
  std::map<std::string, std::size_t> index;
  for (std::size_t row = 0; row < table.rows.size(); ++row) {
    PoseRecord record;
    record.pose_id = table.rows[row][id_column];
    if (record.pose_id.empty()) throw std::runtime_error(table.where(row) + ": empty pose_id");
    if (!index.emplace(record.pose_id, records.size()).second)
      throw std::runtime_error(table.where(row) + ": pose_id '" + record.pose_id + "' appears twice");
    record.images_used = static_cast<int>(table.number(row, used_column));
    record.images_total = static_cast<int>(table.number(row, total_column));
    for (int i = 0; i < 3; ++i) {
      record.translation[i] = table.number(row, value_columns[i]);
      record.rotation_vector[i] = table.number(row, value_columns[3 + i]);
    }
    for (int i = 0; i < 6; ++i) {
      const double sigma = table.number(row, sigma_columns[i]) / (i < 3 ? kMillimetresPerMetre : kDegreesPerRadian);
      record.covariance(i, i) = sigma * sigma;
    }
    record.rms_px = table.number(row, rms_column);
    records.push_back(record);
  }
  if (covariance_csv.empty()) return records;

  const support::CsvTable covariance = support::readCsv(covariance_csv);
  const std::size_t cov_id = covariance.column("pose_id");
  const std::size_t part = covariance.column("part");
  const std::size_t row_name = covariance.column("row");
  std::size_t columns[6];
  for (int i = 0; i < 6; ++i) columns[i] = covariance.column(kComponents[i]);
  for (std::size_t row = 0; row < covariance.rows.size(); ++row) {
    if (covariance.rows[row][part] != "total") continue;
    const auto found = index.find(covariance.rows[row][cov_id]);
    if (found == index.end())
      throw std::runtime_error(covariance.where(row) + ": pose_id '" + covariance.rows[row][cov_id] +
                               "' is not in " + path.string());
    int r = -1;
    for (int i = 0; i < 6; ++i)
      if (covariance.rows[row][row_name] == kComponents[i]) r = i;
    if (r < 0)
      throw std::runtime_error(covariance.where(row) + ": row '" + covariance.rows[row][row_name] +
                               "' is not one of tx, ty, tz, rx, ry, rz");
    for (int c = 0; c < 6; ++c) records[found->second].covariance(r, c) = covariance.number(row, columns[c]);
  }
  return records;
}

}  // namespace mire::metrology
