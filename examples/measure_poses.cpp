// Measures the target's pose for every pose folder (several images of one static pose each) —
// what `mire measure` does: average the features over the images, estimate cTm and its 6×6
// covariance (pixel noise + the camera's own uncertainty), write poses.csv and its covariances.
//   measure_poses camera.yaml target.yaml poses/ poses.csv
#include "mire/calibration/camera_formats.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s camera.yaml target.yaml poses/ poses.csv\n", argv[0]);
    return 2;
  }
  try {
    namespace fs = std::filesystem;
    const auto camera = mire::calibration::readCamera(argv[1]);  // mire, OpenCV, ROS, ViSP, Kalibr
    const auto target = mire::metrology::Target::fromFile(argv[2]);

    std::vector<fs::path> folders;  // one per pose, named by the pose id
    for (const auto& entry : fs::directory_iterator(argv[3]))
      if (entry.is_directory()) folders.push_back(entry.path());
    std::sort(folders.begin(), folders.end());

    std::vector<mire::metrology::MeasuredPose> poses;
    for (const auto& folder : folders) {
      const auto images = mire::metrology::listPoseImages(folder);
      const auto m = mire::metrology::measurePoseFromFiles(camera, target, images);
      if (!m.ok) {
        std::fprintf(stderr, "%s: %s\n", folder.c_str(), m.error.c_str());
        continue;
      }
      const auto sigma = mire::metrology::PoseEstimate::sigmas(m.estimate.covariance);
      const auto& t = m.estimate.translation;
      std::printf("%s  t = (%.5f, %.5f, %.5f) m  sigma = (%.3f, %.3f, %.3f) mm\n", folder.filename().c_str(), t.x(),
                  t.y(), t.z(), 1e3 * sigma(0), 1e3 * sigma(1), 1e3 * sigma(2));
      poses.emplace_back(folder.filename().string(), m.features.images_used, static_cast<int>(images.size()), m.estimate);
    }
    mire::metrology::writePosesCsv(argv[4], poses);
    mire::metrology::writePosesCovarianceCsv(mire::support::covarianceSidePath(argv[4]), poses);
    std::printf("%zu of %zu poses measured\n", poses.size(), folders.size());
    return poses.empty() ? 1 : 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
}
