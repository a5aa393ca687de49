// Per-step CPU cost of the demo's image pipeline (issue 18), one thread: render, noise, PNG
// encode/decode, detection and refinement, one pose measurement. Run by hand.
#include "mire/datasets/h4_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/calibration/camera_formats.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <png.h>
#include <ctime>
#include <iostream>

namespace {
std::vector<unsigned char> pngRaw(const cv::Mat& img, int filter, int level, int strategy) {
  std::vector<unsigned char> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(png, &out, [](png_structp p, png_bytep d, png_size_t n) {
    auto* o = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(p));
    o->insert(o->end(), d, d + n); }, [](png_structp) {});
  png_set_filter(png, PNG_FILTER_TYPE_BASE, filter);
  png_set_compression_level(png, level);
  png_set_compression_strategy(png, strategy);
  png_set_IHDR(png, info, img.cols, img.rows, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  png_write_info(png, info);
  for (int r = 0; r < img.rows; ++r) png_write_row(png, img.ptr<unsigned char>(r));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
}
double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}
template <typename F>
double best(int repeats, F&& f) {
  double b = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const double s = cpuMs();
    f();
    b = std::min(b, cpuMs() - s);
  }
  return b;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace mire;
  cv::setNumThreads(1);
  const std::string dir = argc > 1 ? argv[1] : "/tmp/speed2_base";
  const auto spec = datasets::H4CampaignSpec::reference();
  const calibration::Camera camera = calibration::readCamera(spec.camera_file);
  const metrology::Target target = metrology::Target::fromFile(spec.target_file);
  std::unique_ptr<datasets::Renderer> renderer;
  std::cout << "renderer set-up: " << best(1, [&] { renderer = std::make_unique<datasets::Renderer>(camera, target, spec.render); }) << " ms\n";
  // a pose from the demo's truth: first pose folder's first image is used for detection only
  datasets::ViewPlacement placement;
  placement.centre_pixel = Eigen::Vector2d(511.5, 383.5);
  placement.distance_m = 0.75;
  placement.tilt_rad = 0.3;
  const Eigen::Isometry3d pose = datasets::placeTarget(camera, target, placement);
  datasets::Rendering r;
  std::cout << "render: " << best(3, [&] { r = renderer->render(pose); }) << " ms (" << r.supersampled_pixels << " ss px)\n";
  cv::Mat sigma;
  std::cout << "noiseSigma: " << best(3, [&] { sigma = datasets::noiseSigma(r.radiance, spec.noise); }) << " ms\n";
  cv::Mat noisy;
  std::cout << "addNoiseWithSigma: " << best(3, [&] { noisy = datasets::addNoiseWithSigma(r.radiance, sigma, 7); }) << " ms\n";
  const std::vector<std::vector<int>> settings = {{}, {cv::IMWRITE_PNG_COMPRESSION, 0}, {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY},
      {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_FIXED}, {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_FILTERED},
      {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY}};
  for (const auto& params : settings) {
    const int level = params.empty() ? -1 : params[1] * 100 + (params.size() > 2 ? params[3] : 0);
    std::vector<uchar> buf;
    const double enc = best(3, [&] { cv::imencode(".png", noisy, buf, params); });
    cv::Mat back;
    const double dec = best(3, [&] { back = cv::imdecode(buf, cv::IMREAD_GRAYSCALE); });
    std::cout << "png level " << level << ": encode " << enc << " ms, decode " << dec << " ms, " << buf.size() / 1024 << " KiB\n";
  }
  for (const auto& [name, filter, level, strategy] : std::vector<std::tuple<const char*, int, int, int>>{
           {"none/0", PNG_FILTER_NONE, 0, 0}, {"none/1/huff", PNG_FILTER_NONE, 1, 2}, {"sub/1/rle", PNG_FILTER_SUB, 1, 3}}) {
    std::vector<unsigned char> buf;
    const double enc = best(3, [&] { buf = pngRaw(noisy, filter, level, strategy); });
    cv::Mat back;
    const double dec = best(3, [&] { back = cv::imdecode(buf, cv::IMREAD_GRAYSCALE); });
    std::cout << "libpng " << name << ": encode " << enc << " ms, decode " << dec << " ms, " << buf.size() / 1024 << " KiB, same " << (cv::norm(back, noisy, cv::NORM_INF) == 0) << "\n";
  }
  const cv::Mat image = cv::imread(dir + "/campaign/poses/p001/img_00.png", cv::IMREAD_GRAYSCALE);
  metrology::Detection d;
  std::cout << "detectTarget: " << best(3, [&] { d = metrology::detectTarget(target, image); }) << " ms found " << d.found << "\n";
  std::cout << "refineDetection: " << best(3, [&] { metrology::refineDetection(target, image, d); }) << " ms\n";
  const auto files = metrology::listPoseImages(dir + "/campaign/poses/p001");
  const calibration::Camera calibrated = calibration::readCamera(dir + "/camera.yaml");
  metrology::MeasurementOptions options;
  options.integrity.split = metrology::SplitPolicy::KeepLargest;
  std::cout << "measurePoseFromFiles (10 images): " << best(3, [&] { metrology::measurePoseFromFiles(calibrated, target, files, options); }) << " ms\n";
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& f : files) images.push_back(cv::imread(f.string(), cv::IMREAD_GRAYSCALE)), names.push_back(f.string());
  std::cout << "measurePose (decoded): " << best(3, [&] { metrology::measurePose(calibrated, target, images, names, options); }) << " ms\n";
  return 0;
}
