#pragma once
// camera.yaml (OpenCV FileStorage, doc/file-formats.md, "Camera files") and ViSP's camera XML.
#include "mire/calibration/camera_model.hpp"
#include "mire/support/yaml.hpp"

#include <filesystem>
#include <string>

namespace mire::calibration {

// Reads camera.yaml (any YAML syntax, doc/file-formats.md): OpenCV keys image_width, image_height,
// camera_matrix, distortion_coefficients (0, 4, 5, 8 or 12 values; 4 with model: fisheye),
// OpenCV's and ROS camera_info's variants of them, mire's optional keys model, rms_px,
// covariance (with covariance_parameters naming its order) and sigma. Throws
// support::YamlError (a std::runtime_error) naming the file, the line and the key.
// readCamera (camera_formats.hpp) also reads the other formats.
Camera readCameraYaml(const std::filesystem::path& path);
// The same from a YAML map already loaded (e.g. a camera inline in a simulation spec).
Camera cameraFromYaml(const support::YamlNode& root);

// Serialises to camera.yaml text (write it with support::writeFileAtomically): plain YAML
// with OpenCV's !!opencv-matrix nodes, so that cv::FileStorage reads it.
std::string cameraYamlString(const Camera& camera);

// The side file that carries what a ViSP or Kalibr camera file cannot hold (the covariance,
// the RMS, Kalibr's missing name): "<camera file>.covariance.yaml" beside it. readCamera reads it
// when present; readCovarianceSideFile applies it to `camera` (nothing when absent).
std::filesystem::path covarianceSideFile(const std::filesystem::path& camera_path);
void readCovarianceSideFile(const std::filesystem::path& camera_path, Camera& camera);
std::string cameraCovarianceSideFileString(const Camera& camera);

// ViSP camera XML (vpXmlParserCamera format), projection with distortion: ViSP 3.5 has a
// single radial term, so k1 maps (kud/kdu), and a comment in the file lists what is lost.
// A pinhole camera is written without distortion; a fisheye camera is refused
// (std::invalid_argument).
std::string cameraVispXmlString(const Camera& camera, const std::string& camera_name);

}  // namespace mire::calibration
