#pragma once
// Detections in and out (doc/targets.md, "Detections file"): mire's detections CSV, one row
// per image and feature, and mrcal's corners vnlog (as mrgingham and mrcal-from-cv2 write it).
#include "mire/metrology/target.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace mire::metrology {

// The features found in one image.
struct ImageDetections {
  std::string image;                    // file name (mire measure: "<pose id>/<file name>")
  std::vector<int> ids;                 // indices into Target::points()
  std::vector<Eigen::Vector2d> pixels;  // OpenCV's pixel convention
};

// The CSV's header line (after the comment lines).
inline constexpr const char* kDetectionsCsvHeader = "image,feature_id,u_px,v_px,x_m,y_m,z_m";

// mire's detections CSV: comment lines (the image size when known: "# image_size_px: W H"),
// then kDetectionsCsvHeader, then one row per image and feature, in the given order, numbers
// with 17 significant digits (they read back to the same doubles).
std::string detectionsCsv(const Target& target, const std::vector<ImageDetections>& images, int width, int height);

struct DetectionsFile {
  std::vector<ImageDetections> images;  // in order of first appearance
  std::optional<int> width, height;     // from "# image_size_px: W H" when present
};

// Reads a detections file for `target`: mire's CSV (its target points must be the target's,
// to 1e-9 m) or mrcal's corners vnlog ("# filename x y level": each image's rows are the
// corners of a chessboard target in its feature order, cols x rows of them; rows with "-" are
// points not seen). Throws std::runtime_error "file:line: what" on anything malformed.
DetectionsFile readDetectionsFile(const std::filesystem::path& path, const Target& target);

}  // namespace mire::metrology
