#include "mire/metrology/pose_measurement.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace mire::metrology {
namespace {

std::string imageName(const std::vector<std::string>& names, std::size_t index) {
  if (index < names.size()) return names[index];
  return "image #" + std::to_string(index + 1);
}

std::string sizeText(const cv::Size& size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

// Identical pixels, same size and type. Row by row with an early exit:
// two different noisy images differ in their first bytes, where a full cv::norm read both
// images to the end (45 pairs per pose of 10 images: a third of measurePose's time, doc/detection-speed.md).
bool samePixels(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  const std::size_t row_bytes = static_cast<std::size_t>(a.cols) * a.elemSize();
  for (int r = 0; r < a.rows; ++r)
    if (std::memcmp(a.ptr(r), b.ptr(r), row_bytes) != 0) return false;
  return true;
}

// Per image: the index of an earlier image with identical pixels, or −1.
std::vector<int> identicalImages(const std::vector<cv::Mat>& images) {
  std::vector<int> copy_of(images.size(), -1);
  for (std::size_t j = 1; j < images.size(); ++j)
    for (std::size_t k = 0; k < j; ++k)
      if (copy_of[k] < 0 && samePixels(images[j], images[k])) {
        copy_of[j] = static_cast<int>(k);
        break;
      }
  return copy_of;
}

// The static-pose test, then the average of the images it keeps (duplicates once). False
// when the pose fails (result->error set).
bool averageIntegrity(const calibration::Camera& camera, const Target& target, const std::vector<std::string>& names,
                      const MeasurementOptions& options, std::vector<Detection>* detections, PoseMeasurement* result) {
  result->integrity = checkStaticPose(camera, target.points(), *detections, names, options.integrity);
  const IntegrityResult& integrity = result->integrity;
  result->notes.insert(result->notes.end(), integrity.notes.begin(), integrity.notes.end());
  if (!integrity.consistent) {
    result->error = integrity.error;
    return false;
  }
  AveragingOptions averaging = options.averaging;
  if (options.integrity.enabled) {
    averaging.reject_images = false;  // motion is the integrity test's business, named there
    for (std::size_t j = 0; j < detections->size(); ++j)
      if (!integrity.use[j]) (*detections)[j].found = false;
  }
  result->features = averageDetections(*detections, averaging);
  for (const int j : result->features.rejected_images)
    result->warnings.push_back(imageName(names, static_cast<std::size_t>(j)) +
                               ": rejected as an outlier (whole-image displacement, chi-square test)");
  return true;
}

// Sizes first: mixed sizes mean mixed cameras or settings, and the calibration holds for one.
// The error, or empty when every image is 8-bit grey at the camera's size.
std::string checkImageSizes(const calibration::Camera& camera, const std::vector<cv::Mat>& images,
                            const std::vector<std::string>& names) {
  const cv::Size first_size = images.front().size();
  for (std::size_t j = 0; j < images.size(); ++j) {
    if (images[j].type() != CV_8UC1) return imageName(names, j) + ": not an 8-bit grey image";
    if (images[j].size() != first_size)
      return "mixed image sizes: " + imageName(names, j) + " is " + sizeText(images[j].size()) + " but " +
             imageName(names, 0) + " is " + sizeText(first_size);
  }
  if (first_size != cv::Size(camera.width, camera.height))
    return imageName(names, 0) + " is " + sizeText(first_size) + " but the camera was calibrated at " +
           sizeText(cv::Size(camera.width, camera.height));
  return {};
}

// Every image's detection: full detection until the target is found once (the reference),
// then cheap refinement from it; a copied frame (copy_of) gets its original's detection.
// False (result->error set) when no image shows the target.
bool detectAll(const Target& target, const std::vector<cv::Mat>& images, const std::vector<std::string>& names,
               const std::vector<int>& copy_of, const MeasurementOptions& options, std::vector<Detection>* detections,
               PoseMeasurement* result) {
  std::size_t reference = images.size();
  for (std::size_t j = 0; j < images.size() && reference == images.size(); ++j) {
    (*detections)[j] = copy_of[j] >= 0 ? (*detections)[static_cast<std::size_t>(copy_of[j])]
                                       : detectTarget(target, images[j], options.detection);
    if ((*detections)[j].found)
      reference = j;
    else
      result->warnings.push_back(imageName(names, j) + ": target not found (" + (*detections)[j].reason + ")");
  }
  if (reference == images.size()) {
    result->error = "target not found in any of the " + std::to_string(images.size()) + " images";
    if (!detections->empty() && !detections->front().reason.empty())
      result->error += " (" + detections->front().reason + ")";
    return false;
  }
  for (std::size_t j = reference + 1; j < images.size(); ++j) {
    Detection& detection = (*detections)[j];
    if (copy_of[j] >= 0) {
      detection = (*detections)[static_cast<std::size_t>(copy_of[j])];
      continue;
    }
    detection = refineDetection(target, images[j], (*detections)[reference], options.detection);
    // A refinement that lost much of the target (the camera or the target moved): search again.
    if (!detection.found || detection.size() * 2 < (*detections)[reference].size())
      detection = detectTarget(target, images[j], options.detection);
    if (!detection.found)
      result->warnings.push_back(imageName(names, j) + ": target not found (" + detection.reason + ")");
  }
  // The reference image through the same refinement as the others: a full detection's
  // sub-pixel step differs from refineDetection's, and that difference, common to nothing but
  // the reference image, would read as a motion of it (pose_integrity.hpp).
  const Detection rerefined = refineDetection(target, images[reference], (*detections)[reference], options.detection);
  if (rerefined.found && rerefined.size() == (*detections)[reference].size()) (*detections)[reference] = rerefined;
  for (std::size_t j = 0; j < images.size(); ++j)
    if (copy_of[j] >= 0) (*detections)[j] = (*detections)[static_cast<std::size_t>(copy_of[j])];
  return true;
}

// Rules of doc/measurement.md, "Warnings with numbers".
constexpr double kMisfitRatio = 3.0;    // residual RMS beyond 3× the calibration's RMS ...
constexpr double kMisfitFloorPx = 1.0;  // ... and beyond 1 px: the camera does not fit the images
constexpr int kMinResidualDof = 10;     // a σ estimated from fewer residual degrees of freedom

std::string fixedText(double value, int digits) {
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(digits);
  text << value;
  return text.str();
}

// A wrong camera file (another camera, resolution or zoom) leaves pixel-sized residuals that no
// pose can remove: the pose is then biased, whatever its σ says.
void warnCameraMisfit(const calibration::Camera& camera, PoseMeasurement* result) {
  const double rms = result->estimate.rms_px, expected = camera.rms_px;
  if (rms <= std::max(kMisfitRatio * expected, kMisfitFloorPx)) return;
  result->warnings.push_back(
      "the camera does not fit the images: reprojection RMS " + fixedText(rms, 3) + " px against " +
      (expected > 0.0 ? fixedText(expected, 3) + " px expected (the calibration's RMS in the camera file)"
                      : std::string("at most 1 px expected (the camera file gives no calibration RMS)")) +
      "; the pose is biased: check that the camera file is this camera's (same resolution, focus and zoom)");
}

// One image of few features: the pixel noise, hence the σ, comes from 2N − 6 residuals; with
// ν degrees of freedom that estimate is itself uncertain by ≈ 1/√(2ν). When the camera file gives
// the calibration's RMS, estimatePose pooled it in as kMinResidualDof more (doc/measurement.md).
void warnFewResidualDof(const calibration::Camera& camera, PoseMeasurement* result) {
  const int dof = 2 * result->estimate.feature_count - 6;
  if (!result->estimate.scatter_from_residuals || dof >= kMinResidualDof) return;
  const double relative = dof > 0 ? 1.0 / std::sqrt(2.0 * dof) : 1.0;
  const double pooled = 1.0 / std::sqrt(2.0 * (std::max(dof, 0) + kMinResidualDof));
  const std::string what = camera.rms_px > 0.0
                               ? "; pooled with the camera file's calibration RMS (" + fixedText(camera.rms_px, 3) +
                                     " px) as " + std::to_string(kMinResidualDof) + " more, it is uncertain by about " +
                                     fixedText(100.0 * pooled, 0) + " % if that RMS is this detector's noise"
                               : "; the camera file gives no calibration RMS to pool it with";
  result->warnings.push_back("sigma from " + std::to_string(dof) + " residual degree(s) of freedom (one image, " +
                             std::to_string(result->estimate.feature_count) +
                             " features): on its own uncertain by about " + fixedText(100.0 * relative, 0) +
                             " % (1/sqrt(2 dof))" + what +
                             "; take several images of the pose (their scatter gives the noise) or a target with "
                             "more features");
}

// What the reader must know about a valid pose: an ambiguous planar flip, a σ from residuals.
void notePoseCaveats(PoseMeasurement* result) {
  if (result->estimate.ambiguous) {
    std::ostringstream text;
    text << "ambiguous pose: the planar flip fits almost as well (cost ratio " << result->estimate.ambiguity_cost_ratio
         << ")";
    result->warnings.push_back(text.str());
  }
  if (result->estimate.scatter_from_residuals) {
    std::ostringstream text;
    text << (result->features.zero_scatter ? "zero scatter between the images: " : "one image: ")
         << "sigma from the fit residuals (" << result->estimate.rms_px << " px rms, isotropic), reduced_chi2 = 1 by "
         << "construction";
    result->notes.push_back(text.str());
  }
}

}  // namespace

// Stages: image checks, detection in every image, the static-pose test and the average, the
// pose, then its caveats.
PoseMeasurement measurePose(const calibration::Camera& camera, const Target& target, const std::vector<cv::Mat>& images,
                            const std::vector<std::string>& names, const MeasurementOptions& options) {
  PoseMeasurement result;
  if (images.empty()) {
    result.error = "no images";
    return result;
  }
  result.error = checkImageSizes(camera, images, names);
  if (!result.error.empty()) return result;
  // Identical decoded pixels: a copied frame gets its original's detection (and so identical
  // features, which the integrity test counts once).
  const std::vector<int> copy_of = identicalImages(images);
  std::vector<Detection> detections(images.size());
  if (!detectAll(target, images, names, copy_of, options, &detections, &result)) return result;
  result.detections = detections;  // every image's, before the integrity test leaves any out
  if (!averageIntegrity(camera, target, names, options, &detections, &result)) return result;
  result.estimate = estimatePose(camera, target.points(), result.features, options.pose);
  if (!result.estimate.valid) {
    result.error = result.estimate.reason;
    return result;
  }
  notePoseCaveats(&result);
  warnCameraMisfit(camera, &result);
  warnFewResidualDof(camera, &result);
  result.ok = true;
  return result;
}

PoseMeasurement measurePoseFromFiles(const calibration::Camera& camera, const Target& target,
                                     const std::vector<std::filesystem::path>& files, const MeasurementOptions& options) {
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& file : files) {
    cv::Mat image;
    try {
      image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      image.release();
    }
    if (image.empty()) {
      PoseMeasurement failed;
      failed.error = file.string() + ": unreadable image (not a format OpenCV reads, or corrupt)";
      return failed;
    }
    if (image.depth() != CV_8U) {
      PoseMeasurement failed;
      failed.error = file.string() + ": not an 8-bit image";
      return failed;
    }
    if (image.channels() == 3)
      cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
    else if (image.channels() == 4)
      cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
    images.push_back(image);
    names.push_back(file.string());
  }
  return measurePose(camera, target, images, names, options);
}

std::vector<std::filesystem::path> listPoseImages(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace mire::metrology
