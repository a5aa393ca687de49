// Renderer timings (doc/simulation.md): one 1024x768 image at 4x4 supersampling, clean, then the
// noise of one image (10 noisy images share one clean render per pose). Run by hand.
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/metrology/detection.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>

namespace {

template <typename Function>
double bestMilliseconds(int repeats, Function&& function) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const auto start = std::chrono::steady_clock::now();
    function();
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

}  // namespace

int main() {
  using namespace mire;
  const calibration::Camera camera = calibration::cameraFromOpenCV(
      1024, 768, 817.2043010752688, 817.2043010752688, 511.5, 383.5, {-0.30, 0.10, 4.0e-4, -3.0e-4, -0.015});
  metrology::TargetSpec spec;
  spec.cols = 10;
  spec.rows = 7;
  spec.square_size_m = 0.03;
  const metrology::Target target(spec);
  datasets::ViewPlacement placement;
  placement.centre_pixel = Eigen::Vector2d(511.5, 383.5);
  placement.distance_m = 0.4;
  placement.tilt_rad = 0.5;
  placement.tilt_axis_rad = 0.4;
  const Eigen::Isometry3d pose = datasets::placeTarget(camera, target, placement);

  for (const int threads : {1, cv::getNumberOfCPUs()}) {
    cv::setNumThreads(threads);
    std::cout << "threads: " << threads << "\n";
    std::unique_ptr<datasets::Renderer> renderer;
    const double build = bestMilliseconds(1, [&] { renderer = std::make_unique<datasets::Renderer>(camera, target); });
    std::cout << "  renderer set-up (exact rays at 1025x769 pixel corners): " << build << " ms\n";
    datasets::Rendering rendering;
    const double clean = bestMilliseconds(5, [&] { rendering = renderer->render(pose); });
    std::cout << "  clean render 1024x768, 4x4 adaptive supersampling: " << clean << " ms ("
              << rendering.supersampled_pixels << " pixels supersampled)\n";
    datasets::RenderOptions full_options;
    full_options.adaptive = false;
    const datasets::Renderer full(camera, target, full_options);
    const double brute = bestMilliseconds(2, [&] { full.render(pose); });
    std::cout << "  clean render, 4x4 on every pixel (no adaptivity): " << brute << " ms (ratio " << brute / clean
              << ")\n";
    datasets::NoiseOptions noise;
    noise.gaussian_sigma = 2.0;
    noise.shot_noise_gain = 20.0;
    const double noisy = bestMilliseconds(5, [&] { datasets::addNoise(rendering.radiance, noise, 1); });
    std::cout << "  noise (Gaussian + shot) and quantisation of one image: " << noisy << " ms\n";
  }

  // Which noise gives the "0.1-0.2 px-equivalent" corner scatter of the default specs.
  cv::setNumThreads(cv::getNumberOfCPUs());
  datasets::RenderOptions options;
  options.blur_sigma_px = 0.6;
  options.vignetting = datasets::Vignetting::Cos4;
  const datasets::Renderer renderer(camera, target, options);
  placement.distance_m = 0.5;
  const datasets::Rendering rendering = renderer.render(datasets::placeTarget(camera, target, placement));
  for (const double sigma : {2.0, 6.0, 10.0, 14.0, 18.0}) {
    for (const double gain : {0.0, 4.0}) {
      datasets::NoiseOptions noise;
      noise.gaussian_sigma = sigma;
      noise.shot_noise_gain = gain;
      double sum = 0.0;
      std::size_t count = 0;
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        const auto detection = metrology::detectTarget(target, datasets::addNoise(rendering.radiance, noise, seed));
        for (std::size_t k = 0; k < detection.size(); ++k, ++count)
          sum += (detection.pixels[k] - rendering.truth.pixels[static_cast<std::size_t>(detection.ids[k])]).squaredNorm();
      }
      std::cout << "noise sigma " << sigma << " grey levels, shot gain " << gain << ": chessboard corner RMS vs truth "
                << std::sqrt(sum / std::max<std::size_t>(count, 1)) << " px (" << count << " corners, 5 images)\n";
    }
  }
  return 0;
}
