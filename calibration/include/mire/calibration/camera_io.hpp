#pragma once
// camera.yaml (OpenCV FileStorage, ../shared/BRIEF.md §10) and ViSP's camera XML.
#include "mire/calibration/camera_model.hpp"

#include <filesystem>
#include <string>

namespace mire::calibration {

// Reads camera.yaml: OpenCV keys image_width, image_height, camera_matrix,
// distortion_coefficients (4, 5, 8 or 12 values); mire's optional keys model, rms_px,
// covariance (with covariance_parameters naming its order) and sigma.
// Throws std::runtime_error naming the file and the key on any problem.
Camera readCameraYaml(const std::filesystem::path& path);

// Serialises to camera.yaml text (write it with support::writeFileAtomically).
std::string cameraYamlString(const Camera& camera);

// ViSP camera XML (vpXmlParserCamera format), projection with distortion: ViSP 3.5 has a
// single radial term, so k1 maps (kud/kdu), and a comment in the file lists what is lost.
std::string cameraVispXmlString(const Camera& camera, const std::string& camera_name);

}  // namespace mire::calibration
