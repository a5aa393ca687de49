#pragma once
// OpenCV's ArUco dictionaries and boards for the `charuco` and `aruco_grid` targets
// (doc/targets.md). The boards' object points agree with Target::points().
#include "mire/metrology/target.hpp"

#include <opencv2/aruco/charuco.hpp>

#include <string>
#include <vector>

namespace mire::metrology {

// OpenCV's predefined dictionary by its enum name ("DICT_6X6_250", "DICT_APRILTAG_36h11", …);
// null when the name is unknown.
cv::Ptr<cv::aruco::Dictionary> arucoDictionary(const std::string& name);
// Every name arucoDictionary knows, in OpenCV's enum order.
std::vector<std::string> arucoDictionaryNames();

// The OpenCV board of a `charuco` / `aruco_grid` target; throws std::invalid_argument for
// another type.
cv::Ptr<cv::aruco::CharucoBoard> charucoBoard(const Target& target);
cv::Ptr<cv::aruco::GridBoard> arucoGridBoard(const Target& target);

}  // namespace mire::metrology
