#include "mire/pipeline/image_folders.hpp"

#include "mire/pipeline/image_check.hpp"

#include "mire/metrology/detection.hpp"
#include "mire/support/progress.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace mire::pipeline {
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> listImages(const fs::path& dir) {
  if (!fs::is_directory(dir))
    throw std::runtime_error("image folder '" + dir.string() + "' does not exist or is not a folder");
  std::vector<fs::path> images;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && isImageFile(entry.path())) images.push_back(entry.path());
  std::sort(images.begin(), images.end());
  if (images.empty())
    throw std::runtime_error("image folder '" + dir.string() + "' holds no image (png, jpg, bmp, tif, pgm, ...)");
  return images;
}

constexpr int kMinImageSide = 32;  // px (doc/limits.md)

struct ImageOutcome {
  bool read = false;
  int width = 0, height = 0;
  metrology::Detection detection;
};

}  // namespace

void parallelForEach(std::size_t count, int threads, const std::function<void(std::size_t)>& work) {
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min(count, threads > 0 ? static_cast<std::size_t>(threads) : cores);
  std::atomic<std::size_t> next{0};
  // The exception boundary of every worker: the first exception stops the others from taking
  // new items and is rethrown here, in the caller's thread (an exception escaping a thread
  // would terminate the process).
  std::exception_ptr first_error;
  std::mutex error_mutex;
  const auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        work(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        next = count;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();
  if (first_error) std::rethrow_exception(first_error);
}

CalibrationFolder detectCalibrationFolder(const metrology::Target& target, const fs::path& folder, int threads) {
  const std::vector<fs::path> images = listImages(folder);
  std::vector<ImageOutcome> outcomes(images.size());
  {
    support::Progress progress("detecting", images.size());
    parallelForEach(images.size(), threads, [&](std::size_t i) {
      try {
        checkImageFile(images[i]);
        const cv::Mat gray = cv::imread(images[i].string(), cv::IMREAD_GRAYSCALE);
        if (gray.empty()) {
          // unreadable: reported below, naming the image
        } else if (gray.cols < kMinImageSide || gray.rows < kMinImageSide) {
          outcomes[i] = {true, gray.cols, gray.rows, {}};  // no detector works on it (OpenCV asserts)
          outcomes[i].detection.reason = "image smaller than " + std::to_string(kMinImageSide) + " px";
        } else {
          outcomes[i] = {true, gray.cols, gray.rows, metrology::detectTarget(target, gray)};
        }
      } catch (const cv::Exception& error) {
        throw std::runtime_error("image '" + images[i].string() + "': OpenCV failed on it (" + error.err + ")");
      } catch (const std::bad_alloc&) {
        throw std::runtime_error("image '" + images[i].string() + "': out of memory while reading or detecting");
      }
      progress.advance();
    });
  }
  CalibrationFolder result;
  result.images = images.size();
  for (std::size_t i = 0; i < images.size(); ++i)
    if (!outcomes[i].read)
      throw std::runtime_error("cannot read image '" + images[i].string() + "' (not a decodable image)");
  result.width = outcomes.front().width;
  result.height = outcomes.front().height;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const ImageOutcome& outcome = outcomes[i];
    if (outcome.width != result.width || outcome.height != result.height)
      throw std::runtime_error("image '" + images[i].string() + "' is " + std::to_string(outcome.width) + "x" +
                               std::to_string(outcome.height) + ", the first image is " + std::to_string(result.width) +
                               "x" + std::to_string(result.height) + ": one camera, one size");
    const std::string name = images[i].filename().string();
    if (!outcome.detection.found) {
      result.skipped.emplace_back(name, outcome.detection.reason.empty() ? "target not found" : outcome.detection.reason);
      continue;
    }
    if (!outcome.detection.reason.empty()) result.notes.emplace_back(name, outcome.detection.reason);
    result.views.push_back({name, outcome.detection.ids, outcome.detection.pixels});
  }
  return result;
}

std::vector<std::pair<std::string, fs::path>> poseFolders(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw std::runtime_error(folder.string() + ": not a directory");
  std::vector<std::pair<std::string, fs::path>> poses;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_directory()) continue;
    const std::string id = entry.path().filename().string();
    if (id.empty() || id[0] == '.') continue;
    if (id.find_first_of(",\"") != std::string::npos)
      throw std::runtime_error(entry.path().string() + ": a pose id (folder name) must not contain ',' or '\"'");
    poses.emplace_back(id, entry.path());
  }
  if (poses.empty()) throw std::runtime_error(folder.string() + ": no pose subfolders (one folder per pose expected)");
  std::sort(poses.begin(), poses.end());
  return poses;
}

std::vector<fs::path> poseImages(const fs::path& folder) {
  std::vector<fs::path> images;
  for (const fs::path& file : metrology::listPoseImages(folder))
    if (isImageFile(file)) images.push_back(file);
  for (const fs::path& image : images) {
    checkImageFile(image);
    const cv::Mat reduced = cv::imread(image.string(), cv::IMREAD_REDUCED_GRAYSCALE_4);
    if (reduced.empty()) continue;  // unreadable: the measurement names it
    double low = 0.0, high = 0.0;
    cv::minMaxLoc(reduced, &low, &high);
    if (high - low < 1.0)
      throw std::runtime_error("image '" + image.string() + "' is blank (every pixel " +
                               std::to_string(static_cast<int>(low)) + ")");
  }
  return images;
}

std::vector<PoseFolderMeasurement> measurePoseFolders(const calibration::Camera& camera,
                                                      const metrology::Target& target, const fs::path& folder,
                                                      const metrology::MeasurementOptions& options, int threads) {
  std::vector<PoseFolderMeasurement> poses;
  for (const auto& [id, path] : poseFolders(folder)) poses.push_back({id, path, {}, 0});

  support::Progress progress("measuring poses", poses.size());
  parallelForEach(poses.size(), threads, [&](std::size_t i) {
    PoseFolderMeasurement& pose = poses[i];
    try {
      const auto images = poseImages(pose.folder);
      pose.images_total = static_cast<int>(images.size());
      if (images.empty())
        pose.measurement.error = "no image files in " + pose.folder.string();
      else
        pose.measurement = metrology::measurePoseFromFiles(camera, target, images, options);
    } catch (const cv::Exception& e) {
      pose.measurement.ok = false;
      pose.measurement.error = pose.folder.string() + ": OpenCV failed (" + e.err + ")";
    } catch (const std::exception& e) {
      pose.measurement.ok = false;
      pose.measurement.error = e.what();
    }
    progress.advance();
  });
  return poses;
}

metrology::DetectorBiasTerm sharedDetectorBias(const calibration::Camera& camera, const metrology::Target& target,
                                               const std::vector<PoseFolderMeasurement>& poses,
                                               const metrology::MeasurementOptions& options) {
  std::vector<std::string> ids;
  std::vector<const metrology::PoseMeasurement*> measurements;
  for (const PoseFolderMeasurement& pose : poses) {
    ids.push_back(pose.pose_id);
    measurements.push_back(&pose.measurement);
  }
  return metrology::estimateDetectorBias(camera, target, ids, measurements, options.pose);
}

}  // namespace mire::pipeline
