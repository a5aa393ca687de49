// Calibrates a camera from a folder of images of a planar target — what `mire calibrate` does,
// without its reports: detect the target in every image, solve, print each parameter with its σ,
// write camera.yaml.
//   calibrate_folder target.yaml images/ camera.yaml
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/pose_measurement.hpp"  // listPoseImages
#include "mire/metrology/target.hpp"
#include "mire/support/atomic_file.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s target.yaml images/ camera.yaml\n", argv[0]);
    return 2;
  }
  try {
    const auto target = mire::metrology::Target::fromFile(argv[1]);
    std::vector<mire::calibration::CalibrationView> views;
    cv::Size size;
    for (const auto& path : mire::metrology::listPoseImages(argv[2])) {
      const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
      const auto detection = mire::metrology::detectTarget(target, gray);
      if (gray.empty() || !detection.found) {
        std::fprintf(stderr, "%s: target not found, skipped\n", path.c_str());
        continue;
      }
      size = gray.size();
      views.push_back({path.filename().string(), detection.ids, detection.pixels});
    }

    // Default options: OpenCV's 5-coefficient model, Huber loss, outlier rejection.
    const auto result = mire::calibration::calibrateCamera(target.points(), views, size.width, size.height);
    const auto& camera = result.camera;
    std::printf("views used %d of %zu, rms %.4f px\n", result.used_views, views.size(), camera.rms_px);
    const auto names = camera.parameterNames();
    const auto sigmas = camera.sigmas();
    for (std::size_t i = 0; i < names.size(); ++i)
      std::printf("%-3s %14.6f  sigma %.6f\n", names[i].c_str(), camera.params[i], sigmas[i]);

    mire::support::writeFileAtomically(argv[3], mire::calibration::cameraYamlString(camera));
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
}
