// Writer of the shared calibration term (shared_term_csv.hpp).
#include "mire/metrology/shared_term_csv.hpp"

#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include <sstream>

namespace mire::metrology {

std::filesystem::path sharedTermSidePath(const std::filesystem::path& poses_csv) {
  return poses_csv.parent_path() / (poses_csv.stem().string() + "_shared.csv");
}

std::string sharedTermCsvString(const calibration::Camera& camera, const std::vector<MeasuredPose>& poses) {
  const std::vector<std::string> names = camera.parameterNames();
  const auto n = static_cast<Eigen::Index>(names.size());
  if (camera.covariance.rows() != n || camera.covariance.cols() != n || n == 0) return {};
  std::ostringstream out;
  out << "kind,id,row";
  for (const auto& name : names) out << ',' << name;
  out << '\n';
  for (Eigen::Index r = 0; r < n; ++r) {
    out << "covariance,camera," << names[static_cast<std::size_t>(r)];
    for (Eigen::Index c = 0; c < n; ++c) out << ',' << support::formatNumber(camera.covariance(r, c));
    out << '\n';
  }
  const char* const axes[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  int written = 0;
  for (const MeasuredPose& pose : poses) {
    const Eigen::MatrixXd& d = pose.estimate.intrinsics_sensitivity;
    if (d.rows() != 6 || d.cols() != n) continue;
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
                        const std::vector<MeasuredPose>& poses) {
  const std::string text = sharedTermCsvString(camera, poses);
  if (text.empty()) return false;
  support::writeFileAtomically(path, text);
  return true;
}

}  // namespace mire::metrology
