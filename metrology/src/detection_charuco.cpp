// ChArUco boards and ArUco grid boards through OpenCV's aruco module (doc/targets.md).
#include "mire/metrology/aruco_boards.hpp"

#include "detection_internal.hpp"

#include <opencv2/aruco.hpp>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mire::metrology::detail {
namespace {

// Every marker of `dictionary` in the image, corners in OpenCV's order (top-left, top-right,
// bottom-right, bottom-left of the upright marker: the target's corner order).
std::vector<SquareInstance> detectArucoMarkers(const cv::Mat& gray, const cv::Ptr<cv::aruco::Dictionary>& dictionary,
                                               int corner_refinement) {
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  parameters->cornerRefinementMethod = corner_refinement;
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  cv::aruco::detectMarkers(gray, dictionary, corners, ids, parameters);
  std::vector<SquareInstance> instances;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    SquareInstance instance;
    instance.id = ids[i];
    for (int j = 0; j < 4; ++j) instance.corners[j] = Eigen::Vector2d(corners[i][j].x, corners[i][j].y);
    instances.push_back(instance);
  }
  return instances;
}

// The markers of an OpenCV board as a layout (marker id -> corners in frame M).
SquareLayout boardLayout(const cv::aruco::Board& board) {
  SquareLayout layout;
  for (std::size_t k = 0; k < board.ids.size(); ++k) {
    std::array<Eigen::Vector2d, 4> corners;
    for (int j = 0; j < 4; ++j) corners[j] = Eigen::Vector2d(board.objPoints[k][j].x, board.objPoints[k][j].y);
    layout.emplace(board.ids[k], corners);
  }
  return layout;
}

// Each corner's smallest image distance to a detected neighbour along the board's rows and
// columns (the foreshortening differs across a tilted board); the overall smallest for a corner
// without a detected neighbour.
std::vector<double> charucoSpacingsPx(const Target& target, const std::vector<int>& ids,
                                      const std::vector<cv::Point2f>& pixels) {
  const int cols = target.spec().cols - 1;
  std::map<int, cv::Point2f> by_id;
  for (std::size_t i = 0; i < ids.size(); ++i) by_id.emplace(ids[i], pixels[i]);
  std::vector<double> spacings(ids.size(), std::numeric_limits<double>::infinity());
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const int id = ids[i];
    for (const int neighbour : {id % cols + 1 < cols ? id + 1 : -1, id % cols > 0 ? id - 1 : -1, id + cols, id - cols}) {
      const auto other = by_id.find(neighbour);
      if (other != by_id.end())
        spacings[i] = std::min(spacings[i], static_cast<double>(cv::norm(other->second - pixels[i])));
    }
    smallest = std::min(smallest, spacings[i]);
  }
  for (double& spacing : spacings)
    if (!std::isfinite(spacing)) spacing = smallest;
  return spacings;
}

// cornerSubPix as for chessboards, with a window per corner that stays inside the squares'
// margin around the markers (a marker edge inside the window would pull the corner).
void refineCharucoCorners(const Target& target, const cv::Mat& gray, const DetectionOptions& options,
                          std::vector<int>* ids, std::vector<cv::Point2f>* pixels) {
  const std::vector<double> spacings = charucoSpacingsPx(target, *ids, *pixels);
  const TargetSpec& spec = target.spec();
  const double clear_fraction = 0.5 * (spec.square_size_m - spec.marker_size_m) / spec.square_size_m;
  std::vector<int> kept_ids;
  std::vector<cv::Point2f> kept;
  for (std::size_t i = 0; i < ids->size(); ++i) {
    int window = options.subpixel_window_px;
    if (window <= 0)
      window = std::isfinite(spacings[i])
                   ? std::clamp(static_cast<int>(std::floor(0.8 * clear_fraction * spacings[i])), 2, 15)
                   : 3;
    std::vector<cv::Point2f> refined = {(*pixels)[i]};
    cv::cornerSubPix(gray, refined, cv::Size(window, window), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
    const cv::Point2f& p = refined.front();
    const bool inside = p.x >= 0 && p.y >= 0 && p.x <= gray.cols - 1 && p.y <= gray.rows - 1;
    if (!inside || cv::norm(p - (*pixels)[i]) > 0.5 * window) continue;  // did not converge on the X-junction
    kept_ids.push_back((*ids)[i]);
    kept.push_back(p);
  }
  *ids = std::move(kept_ids);
  *pixels = std::move(kept);
}

}  // namespace

Detection detectCharuco(const Target& target, const cv::Mat& gray, const DetectionOptions& options) {
  const cv::Ptr<cv::aruco::CharucoBoard> board = charucoBoard(target);
  // Markers that fit the board (foreign and repeated ids sorted out as for tag layouts).
  const std::vector<SquareInstance> instances =
      detectArucoMarkers(gray, board->dictionary, cv::aruco::CORNER_REFINE_NONE);
  const std::vector<std::vector<int>> groups = groupLayoutInstances(boardLayout(*board), instances);
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  if (!groups.empty()) {
    for (const int i : groups.front()) {
      marker_ids.push_back(instances[i].id);
      std::vector<cv::Point2f> corners;
      for (const Eigen::Vector2d& corner : instances[i].corners)
        corners.emplace_back(static_cast<float>(corner.x()), static_cast<float>(corner.y()));
      marker_corners.push_back(corners);
    }
  }
  Detection result;
  const std::size_t expected = target.points().size();
  std::vector<cv::Point2f> pixels;
  std::vector<int> ids;
  if (!marker_ids.empty())
    cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, board, pixels, ids, cv::noArray(),
                                         cv::noArray(), 2);
  if (options.subpixel && !ids.empty()) refineCharucoCorners(target, gray, options, &ids, &pixels);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    result.ids.push_back(ids[i]);
    result.pixels.emplace_back(pixels[i].x, pixels[i].y);
  }
  // Four corners at least: fewer do not fix a homography (a view's pose).
  result.found = result.ids.size() >= 4 && (options.allow_partial || result.ids.size() == expected);
  if (result.ids.size() < expected)
    result.reason = std::to_string(result.ids.size()) + " of " + std::to_string(expected) + " ChArUco corners found (" +
                    std::to_string(marker_ids.size()) + " markers)";
  return result;
}

std::vector<Detection> detectArucoGridCandidates(const Target& target, const cv::Mat& gray,
                                                 const DetectionOptions& options) {
  const cv::Ptr<cv::aruco::GridBoard> board = arucoGridBoard(target);
  // Of OpenCV's marker corner refinements, SUBPIX measured best on renders (0.19 px RMS against
  // 0.61 for CONTOUR and 0.69 for APRILTAG, tests/metrology/test_detection_tag_layouts.cpp).
  const int refinement = options.subpixel ? cv::aruco::CORNER_REFINE_SUBPIX : cv::aruco::CORNER_REFINE_NONE;
  std::vector<Detection> candidates =
      layoutDetections(target, detectArucoMarkers(gray, board->dictionary, refinement), options, "markers");
  if (candidates.empty()) {
    Detection none;
    none.reason = "no marker of the board (" + target.spec().dictionary + ") found";
    candidates.push_back(none);
  }
  return candidates;
}

}  // namespace mire::metrology::detail
