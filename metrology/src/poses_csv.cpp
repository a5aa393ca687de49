#include "mire/metrology/poses_csv.hpp"

#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::metrology {
namespace {

constexpr double kMillimetresPerMetre = 1000.0;
using support::kDegreesPerRadian;
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

std::string flagsText(const std::vector<std::string>& flags) {
  std::string text;
  for (const auto& flag : flags) {
    if (flag.find_first_of(",;\n\"") != std::string::npos)
      throw std::invalid_argument("pose flag '" + flag + "' contains a comma, semicolon, quote or newline");
    text += (text.empty() ? "" : ";") + flag;
  }
  return text;
}

}  // namespace

std::string posesCsvString(const std::vector<MeasuredPose>& poses) {
  std::ostringstream out;
  out << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,"
         "sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px,"
         "sigma_pixel_tx_mm,sigma_pixel_ty_mm,sigma_pixel_tz_mm,sigma_pixel_rx_deg,sigma_pixel_ry_deg,"
         "sigma_pixel_rz_deg,sigma_intrinsics_tx_mm,sigma_intrinsics_ty_mm,sigma_intrinsics_tz_mm,"
         "sigma_intrinsics_rx_deg,sigma_intrinsics_ry_deg,sigma_intrinsics_rz_deg,reduced_chi2,features,"
         "ambiguous,ambiguity_ratio,flags\n";
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
        << shortNumber(e.ambiguity_cost_ratio) << ',' << flagsText(pose.flags) << '\n';
  }
  return out.str();
}

std::string posesCovarianceCsvString(const std::vector<MeasuredPose>& poses) {
  std::ostringstream out;
  out << "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
  for (const MeasuredPose& pose : poses) {
    const std::pair<const char*, const Matrix6d*> parts[] = {{"total", &pose.estimate.covariance},
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

}  // namespace mire::metrology
