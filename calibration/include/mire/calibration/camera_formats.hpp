#pragma once
// Camera files of other tools, both ways (doc/file-formats.md "Camera files"): one reader that
// detects the format from the content, and a writer per format.
//   opencv : mire's camera.yaml and OpenCV's own key variants (readCameraYaml)
//   ros    : ROS camera_info YAML (camera_calibration, camera_info_manager)
//   visp   : ViSP's camera XML (vpXmlParserCamera)
//   kalibr : Kalibr camchain YAML (read: the single camera cam0; written)
//   mrcal  : mrcal .cameramodel (LENSMODEL_PINHOLE, LENSMODEL_OPENCV4/5/8/12; others refused by name)
#include "mire/calibration/camera_model.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace mire::calibration {

enum class CameraFormat { OpenCV, Ros, Visp, Kalibr, Mrcal };

// "opencv", "ros", "visp", "kalibr", "mrcal".
std::string cameraFormatName(CameraFormat format);
std::optional<CameraFormat> cameraFormatFromName(const std::string& name);
// The format an output file name implies: .yaml/.yml → opencv, .xml → visp,
// .cameramodel → mrcal; none otherwise.
std::optional<CameraFormat> cameraFormatFromExtension(const std::filesystem::path& path);

// The format of an existing file, from its content (not its name): XML → visp; YAML with
// distortion_model / projection_matrix / rectification_matrix / camera_name → ros; YAML with
// cam0 → kalibr; a Python dict with 'lensmodel' → mrcal; other YAML → opencv.
// Throws std::runtime_error naming the file when it cannot be read.
CameraFormat detectCameraFormat(const std::filesystem::path& path);

// Reads a camera in any readable format (detected from the content). Errors name the file,
// the line and the key, and what is wrong (support::YamlError, a std::runtime_error).
Camera readCamera(const std::filesystem::path& path);

// The format readers (readCamera dispatches to them; readCameraYaml is in camera_io.hpp and
// reads opencv and ros files).
Camera readCameraVispXml(const std::filesystem::path& path);
Camera readCameraKalibrYaml(const std::filesystem::path& path);
// mrcal's .cameramodel: 'lensmodel' (LENSMODEL_PINHOLE or LENSMODEL_OPENCV4/5/8/12; any other
// is refused by name), 'intrinsics', 'imagersize'; the extrinsics and mrcal's other keys are not
// used; mire's own keys (mire_camera_name, mire_rms_px, mire_covariance) when present.
Camera readCameraMrcal(const std::filesystem::path& path);

// Writers; they throw std::invalid_argument when the format cannot hold the camera exactly
// (e.g. Kalibr's radtan has k1 k2 p1 p2 only) — except ViSP, whose one-term model is fitted
// and documented in the file (cameraVispXmlString).
std::string cameraRosYamlString(const Camera& camera, const std::string& camera_name);
std::string cameraKalibrYamlString(const Camera& camera);
std::string cameraMrcalString(const Camera& camera);
std::string cameraString(const Camera& camera, CameraFormat format, const std::string& camera_name);

// What writing `camera` as `format` loses: the terms the format has no place for (empty when
// the file holds the model exactly), the camera the file would hold, and the projection
// difference between the two over the image (every 8th pixel: unprojected by `camera`,
// projected by `written`). Throws std::invalid_argument when the format has no model for the
// camera at all (a fisheye camera as ViSP or mrcal).
struct ConversionLoss {
  std::string lost;  // "k2 p1 p2 k3", empty when exact
  Camera written;
  double rms_px = 0.0;
  double max_px = 0.0;
  bool exact() const { return lost.empty(); }
};
ConversionLoss conversionLoss(const Camera& camera, CameraFormat format);

// Whether the format's file holds the covariance (opencv, ros, mrcal); the others get the side
// file (camera_io.hpp).
bool formatHoldsCovariance(CameraFormat format);

}  // namespace mire::calibration
