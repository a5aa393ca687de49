// Per-step CPU cost of `mire demo`'s image pipeline (doc/detection-speed.md), on one
// thread: renderer set-up, one render, the noise of one image, PNG encoding and decoding
// (OpenCV's settings and mire's stored PNG), detection, refinement and one pose of 10 images.
// Run by hand: bench_demo_stages DEMO_DIR (the output of `mire demo -o DEMO_DIR`).
#include "mire/calibration/camera_formats.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/datasets/png.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <ctime>
#include <iostream>
#include <memory>

namespace {

// CPU time of this thread: the machine is shared, wall time is not reproducible.
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

template <typename Function>
double bestMs(int repeats, Function&& function) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const double start = threadCpuMs();
    function();
    best = std::min(best, threadCpuMs() - start);
  }
  return best;
}

void pngRow(const char* name, const cv::Mat& image, const std::vector<int>& params) {
  std::vector<uchar> bytes;
  const double encode = bestMs(3, [&] { cv::imencode(".png", image, bytes, params); });
  const double decode = bestMs(3, [&] { cv::imdecode(bytes, cv::IMREAD_GRAYSCALE); });
  std::cout << "  " << name << ": encode " << encode << " ms, decode " << decode << " ms, " << bytes.size() / 1024
            << " KiB\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mire;
  if (argc != 2) {
    std::cerr << "usage: bench_demo_stages DEMO_DIR   (from `mire demo -o DEMO_DIR`)\n";
    return 2;
  }
  const std::filesystem::path demo = argv[1];
  cv::setNumThreads(1);
  const auto spec = datasets::MechanismImageCampaignSpec::reference("h4");
  const calibration::Camera camera = calibration::readCamera(spec.camera_file);
  const metrology::Target target = metrology::Target::fromFile(spec.target_file);

  std::unique_ptr<datasets::Renderer> renderer;
  std::cout << "renderer set-up: " << bestMs(1, [&] {
    renderer = std::make_unique<datasets::Renderer>(camera, target, spec.render);
  }) << " ms\n";
  datasets::ViewPlacement placement;
  placement.centre_pixel = Eigen::Vector2d(511.5, 383.5);
  placement.distance_m = 0.75;
  placement.tilt_rad = 0.3;
  const Eigen::Isometry3d pose = datasets::placeTarget(camera, target, placement);
  datasets::Rendering rendering;
  std::cout << "render: " << bestMs(3, [&] { rendering = renderer->render(pose); }) << " ms ("
            << rendering.supersampled_pixels << " pixels supersampled)\n";
  cv::Mat sigma, noisy;
  std::cout << "noise sigma (once per render): "
            << bestMs(3, [&] { sigma = datasets::noiseSigma(rendering.radiance, spec.noise); }) << " ms\n";
  std::cout << "noisy image: " << bestMs(3, [&] { noisy = datasets::addNoiseWithSigma(rendering.radiance, sigma, 7); })
            << " ms\n";

  std::cout << "PNG of the noisy image:\n";
  pngRow("OpenCV default (zlib 1, RLE, Sub filter)", noisy, {});
  pngRow("OpenCV level 0 (no compression, adaptive filters)", noisy, {cv::IMWRITE_PNG_COMPRESSION, 0});
  pngRow("OpenCV Huffman only", noisy, {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY});
  {
    std::string stored;
    const double encode = bestMs(3, [&] { stored = datasets::encodePng(noisy, datasets::PngEncoding::Stored); });
    const std::vector<uchar> bytes(stored.begin(), stored.end());
    const double decode = bestMs(3, [&] { cv::imdecode(bytes, cv::IMREAD_GRAYSCALE); });
    std::cout << "  mire stored (no filter, zlib 0): encode " << encode << " ms, decode " << decode << " ms, "
              << bytes.size() / 1024 << " KiB\n";
  }

  const auto files = metrology::listPoseImages(demo / "campaign/poses/p001");
  if (files.empty()) {
    std::cerr << demo << ": no campaign/poses/p001 images\n";
    return 1;
  }
  const cv::Mat image = cv::imread(files.front().string(), cv::IMREAD_GRAYSCALE);
  metrology::Detection detection;
  std::cout << "detectTarget: " << bestMs(3, [&] { detection = metrology::detectTarget(target, image); }) << " ms ("
            << detection.pixels.size() << " corners)\n";
  std::cout << "refineDetection: " << bestMs(3, [&] { metrology::refineDetection(target, image, detection); }) << " ms\n";
  const calibration::Camera calibrated = calibration::readCamera(demo / "camera.yaml");
  metrology::MeasurementOptions options;
  options.integrity.split = metrology::SplitPolicy::KeepLargest;
  std::cout << "measurePoseFromFiles (" << files.size() << " images, p001): "
            << bestMs(3, [&] { metrology::measurePoseFromFiles(calibrated, target, files, options); }) << " ms\n";
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& file : files)
    images.push_back(cv::imread(file.string(), cv::IMREAD_GRAYSCALE)), names.push_back(file.string());
  std::cout << "measurePose (decoded images): "
            << bestMs(3, [&] { metrology::measurePose(calibrated, target, images, names, options); }) << " ms\n";
  return 0;
}
