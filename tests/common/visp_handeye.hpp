#pragma once
// ViSP's hand-eye tutorial data (../shared/datasets/external/visp-handeye, its README): 8 flange
// poses fPe and 8 target poses cPo, each a 6-vector (t in metres, θu in radians) in a
// vpPoseVector YAML file, and ViSP's published eMc.
#include <Eigen/Core>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace mire::test {

inline constexpr const char* kVispHandEyeDir = "datasets/external/visp-handeye";

// ViSP's published eMc (t [m], θu [rad]).
inline Eigen::Matrix<double, 6, 1> vispPublishedEmc() {
  Eigen::Matrix<double, 6, 1> v;
  v << 0.05345567035, -0.009516983454, -0.04510223842, -0.0234728216, -0.07938837693, 1.574587196;
  return v;
}

// The six values of a vpPoseVector YAML file ("data:" then "- [value]" lines).
inline Eigen::Matrix<double, 6, 1> readVispPoseVector(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  Eigen::Matrix<double, 6, 1> v;
  int count = 0;
  std::string line;
  while (std::getline(in, line)) {
    const auto open = line.find('['), close = line.find(']');
    if (open == std::string::npos || close == std::string::npos) continue;
    if (count == 6) throw std::runtime_error(path.string() + ": more than 6 values");
    v[count++] = std::stod(line.substr(open + 1, close - open - 1));
  }
  if (count != 6) throw std::runtime_error(path.string() + ": fewer than 6 values");
  return v;
}

struct VispHandEyePair {
  std::string id;
  Eigen::Matrix<double, 6, 1> fPe, cPo;
};

inline std::vector<VispHandEyePair> readVispHandEye() {
  const std::filesystem::path dir = sharedDir() / kVispHandEyeDir;
  std::vector<VispHandEyePair> pairs;
  for (int i = 1; i <= 8; ++i) {
    const std::string id = std::to_string(i);
    pairs.push_back({id, readVispPoseVector(dir / ("pose_fPe_" + id + ".yaml")),
                     readVispPoseVector(dir / ("pose_cPo_" + id + ".yaml"))});
  }
  return pairs;
}

// robot_poses.csv and poses.csv (doc/file-formats.md) of the pairs, in the given order; the
// camera poses carry no σ (their columns are 0).
inline void writeVispHandEyeCsv(const std::vector<VispHandEyePair>& pairs, const std::filesystem::path& robot_poses,
                                const std::filesystem::path& poses) {
  std::ofstream robot(robot_poses), camera(poses);
  robot.precision(17);
  camera.precision(17);
  robot << "pose_id,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad\n";
  camera << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
            "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  for (const VispHandEyePair& p : pairs) {
    robot << p.id;
    camera << p.id << ",1,1";
    for (int k = 0; k < 6; ++k) {
      robot << ',' << p.fPe[k];
      camera << ',' << p.cPo[k];
    }
    robot << '\n';
    camera << ",0,0,0,0,0,0,0\n";
  }
}

}  // namespace mire::test
