// Writer of the shared calibration term (shared_term_csv.hpp).
#include "mire/metrology/shared_term_csv.hpp"

#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include <sstream>

namespace mire::metrology {

namespace {

// The camera's parameters when it carries a covariance, then the detector-bias modes.
struct SharedColumns {
  std::vector<std::string> names;
  Eigen::MatrixXd covariance;
  Eigen::Index camera = 0;  // leading columns that are the camera's
};

SharedColumns sharedColumns(const calibration::Camera& camera, const DetectorBiasTerm& bias) {
  SharedColumns columns;
  const std::vector<std::string> names = camera.parameterNames();
  const auto n = static_cast<Eigen::Index>(names.size());
  if (n > 0 && camera.covariance.rows() == n && camera.covariance.cols() == n) {
    columns.names = names;
    columns.camera = n;
  }
  columns.names.insert(columns.names.end(), bias.names.begin(), bias.names.end());
  const auto total = static_cast<Eigen::Index>(columns.names.size());
  columns.covariance = Eigen::MatrixXd::Identity(total, total);
  columns.covariance.topLeftCorner(columns.camera, columns.camera) =
      camera.covariance.topLeftCorner(columns.camera, columns.camera);
  return columns;
}

// Pose's 6 × columns sensitivity; empty when the pose lacks a part the columns hold.
Eigen::MatrixXd poseSensitivity(const MeasuredPose& pose, const SharedColumns& columns, const DetectorBiasTerm& bias) {
  const Eigen::MatrixXd& d = pose.estimate.intrinsics_sensitivity;
  if (columns.camera > 0 && (d.rows() != 6 || d.cols() != columns.camera)) return {};
  const auto modes = static_cast<Eigen::Index>(bias.names.size());
  const auto found = bias.sensitivity.find(pose.pose_id);
  if (modes > 0 && found == bias.sensitivity.end()) return {};
  Eigen::MatrixXd out(6, columns.camera + modes);
  if (columns.camera > 0) out.leftCols(columns.camera) = d;
  if (modes > 0) out.rightCols(modes) = found->second;
  return out;
}

}  // namespace

std::string sharedTermCsvString(const calibration::Camera& camera, const std::vector<MeasuredPose>& poses,
                                const DetectorBiasTerm& bias) {
  const SharedColumns columns = sharedColumns(camera, bias);
  const auto n = static_cast<Eigen::Index>(columns.names.size());
  if (n == 0) return {};
  std::ostringstream out;
  out << "kind,id,row";
  for (const auto& name : columns.names) out << ',' << name;
  out << '\n';
  for (Eigen::Index r = 0; r < n; ++r) {
    out << "covariance," << (r < columns.camera ? "camera," : "detector,") << columns.names[static_cast<std::size_t>(r)];
    for (Eigen::Index c = 0; c < n; ++c) out << ',' << support::formatNumber(columns.covariance(r, c));
    out << '\n';
  }
  const char* const axes[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  int written = 0;
  for (const MeasuredPose& pose : poses) {
    const Eigen::MatrixXd d = poseSensitivity(pose, columns, bias);
    if (d.size() == 0) continue;
    ++written;
    for (int r = 0; r < 6; ++r) {
      out << "sensitivity," << pose.pose_id << ',' << axes[r];
      for (Eigen::Index c = 0; c < n; ++c) out << ',' << support::formatNumber(d(r, c));
      out << '\n';
    }
  }
  return written > 0 ? out.str() : std::string();
}

bool writeSharedTermCsv(const std::filesystem::path& path, const calibration::Camera& camera,
                        const std::vector<MeasuredPose>& poses, const DetectorBiasTerm& bias) {
  const std::string text = sharedTermCsvString(camera, poses, bias);
  if (text.empty()) return false;
  support::writeFileAtomically(path, text);
  return true;
}

}  // namespace mire::metrology
