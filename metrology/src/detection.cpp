// Target detection entry points and the grid ordering shared by chessboards and circle
// grids (doc/file-formats.md, "Target frame M": chessboard colour rule).
#include "mire/metrology/detection.hpp"

#include "detection_internal.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace mire::metrology {
namespace detail {
namespace {

// One symmetry of the index grid: target (c, r) -> OpenCV's (c', r').
struct GridSymmetry {
  bool transpose = false;
  bool flip_cols = false;
  bool flip_rows = false;
};

int opencvIndex(const GridSymmetry& symmetry, int cols, int rows, int c, int r) {
  int cc = symmetry.transpose ? r : c;
  int rr = symmetry.transpose ? c : r;
  if (symmetry.flip_cols) cc = cols - 1 - cc;
  if (symmetry.flip_rows) rr = rows - 1 - rr;
  return rr * cols + cc;
}

cv::Point2d applyHomography(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

// Mean grey level over the middle of a square of frame M (centre, half-size), or NaN when
// it falls outside the image.
double meanLevel(const cv::Mat& gray, const cv::Matx33d& h, double cx, double cy, double half) {
  double sum = 0.0;
  int count = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      const cv::Point2d p = applyHomography(h, cx + half * i / 4.0, cy + half * j / 4.0);
      const int u = static_cast<int>(std::lround(p.x));
      const int v = static_cast<int>(std::lround(p.y));
      if (u < 0 || v < 0 || u >= gray.cols || v >= gray.rows) return std::numeric_limits<double>::quiet_NaN();
      sum += gray.at<unsigned char>(v, u);
      ++count;
    }
  }
  return sum / count;
}

// One ordering of the grid finder's points: its symmetry, the homography frame M → image it
// implies, and what decides between orderings.
struct GridCandidate {
  GridSymmetry symmetry;
  cv::Matx33d homography;
  double rms_px = 0.0;
  double x_axis_rightness = 0.0;  // cosine between the image of x_M and the image's +u
  int dark_origin = 0;            // +1 dark, -1 light, 0 unknown (chessboard only)
};

// The ordering of `symmetry` as a candidate, or nothing when no homography fits it or it
// mirrors the board.
std::optional<GridCandidate> evaluateOrdering(const Target& target, const cv::Mat& gray,
                                              const std::vector<cv::Point2f>& model,
                                              const std::vector<cv::Point2f>& opencv_grid, const GridSymmetry& symmetry) {
  const TargetSpec& spec = target.spec();
  const int cols = spec.cols;
  const int rows = spec.rows;
  const cv::Point2d centre_m(0.5 * (model.front().x + model.back().x), 0.5 * (model.front().y + model.back().y));
  GridCandidate candidate;
  candidate.symmetry = symmetry;
  std::vector<cv::Point2f> pixels(model.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      pixels[r * cols + c] = opencv_grid[opencvIndex(candidate.symmetry, cols, rows, c, r)];
  const cv::Mat h = cv::findHomography(model, pixels, 0);
  if (h.empty()) return std::nullopt;
  candidate.homography = cv::Matx33d(h);
  double sum = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const cv::Point2d p = applyHomography(candidate.homography, model[i].x, model[i].y);
    sum += (p.x - pixels[i].x) * (p.x - pixels[i].x) + (p.y - pixels[i].y) * (p.y - pixels[i].y);
  }
  candidate.rms_px = std::sqrt(sum / model.size());
  // Handedness: z_M = x_M × y_M points away from the camera when the board is seen
  // from the front, i.e. the homography keeps the image's orientation (det J > 0).
  const double step = target.featureSpacing();
  const cv::Point2d o = applyHomography(candidate.homography, centre_m.x, centre_m.y);
  const cv::Point2d ex = applyHomography(candidate.homography, centre_m.x + step, centre_m.y) - o;
  const cv::Point2d ey = applyHomography(candidate.homography, centre_m.x, centre_m.y + step) - o;
  if (ex.x * ey.y - ex.y * ey.x <= 0.0) return std::nullopt;
  candidate.x_axis_rightness = ex.x / std::hypot(ex.x, ex.y);
  if (spec.type == TargetType::Chessboard) {
    const double s = spec.square_size_m;
    const double outside = meanLevel(gray, candidate.homography, -0.5 * s, -0.5 * s, 0.5 * s);
    const double beside = meanLevel(gray, candidate.homography, 0.5 * s, -0.5 * s, 0.5 * s);
    if (std::isfinite(outside) && std::isfinite(beside)) candidate.dark_origin = outside < beside ? 1 : -1;
  }
  return candidate;
}

// Every grid symmetry (transposes only for a square grid) that gives a candidate.
std::vector<GridCandidate> gridCandidates(const Target& target, const cv::Mat& gray,
                                          const std::vector<cv::Point2f>& opencv_grid) {
  std::vector<cv::Point2f> model;  // frame M (x, y) of each feature
  for (const Eigen::Vector3d& point : target.points())
    model.emplace_back(static_cast<float>(point.x()), static_cast<float>(point.y()));
  const bool square = target.spec().cols == target.spec().rows;
  std::vector<GridCandidate> candidates;
  for (int t = 0; t < 2; ++t) {
    if (t == 1 && !square) break;  // a transposed grid only fits a square one
    for (int f = 0; f < 4; ++f) {
      const std::optional<GridCandidate> candidate =
          evaluateOrdering(target, gray, model, opencv_grid, {t == 1, (f & 1) != 0, (f & 2) != 0});
      if (candidate) candidates.push_back(*candidate);
    }
  }
  return candidates;
}

// Smallest distance (px) between neighbours along a row of the grid finder's points.
double smallestSpacingPx(const std::vector<cv::Point2f>& opencv_grid, int cols, int rows) {
  double spacing = std::numeric_limits<double>::infinity();
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c)
      spacing = std::min(spacing, cv::norm(opencv_grid[r * cols + c + 1] - opencv_grid[r * cols + c]));
  return spacing;
}

// Keep the orderings that fit the layout (all of them fit a symmetric layout equally; an
// asymmetric one rejects the wrong ones by a residual of the order of the spacing), then
// the chessboard colour rule (doc/file-formats.md): the square just outside the origin is dark.
std::vector<GridCandidate> fittingCandidates(const std::vector<GridCandidate>& candidates,
                                             const std::vector<cv::Point2f>& opencv_grid, int cols, int rows) {
  double best_rms = std::numeric_limits<double>::infinity();
  for (const GridCandidate& candidate : candidates) best_rms = std::min(best_rms, candidate.rms_px);
  const double spacing_px = smallestSpacingPx(opencv_grid, cols, rows);
  std::vector<GridCandidate> fitting;
  for (const GridCandidate& candidate : candidates)
    if (candidate.rms_px <= best_rms + 0.1 * spacing_px) fitting.push_back(candidate);
  const bool any_dark =
      std::any_of(fitting.begin(), fitting.end(), [](const GridCandidate& c) { return c.dark_origin > 0; });
  const bool any_unknown =
      std::any_of(fitting.begin(), fitting.end(), [](const GridCandidate& c) { return c.dark_origin == 0; });
  if (any_dark || any_unknown) {
    const int wanted = any_dark ? 1 : 0;
    fitting.erase(
        std::remove_if(fitting.begin(), fitting.end(), [&](const GridCandidate& c) { return c.dark_origin != wanted; }),
        fitting.end());
  }
  return fitting;
}

}  // namespace

// Stages: every ordering of the grid finder's points as a candidate, the ones that fit the
// layout and the colour rule, then the one whose x_M points most to the image's right.
Detection orderGrid(const Target& target, const cv::Mat& gray, const std::vector<cv::Point2f>& opencv_grid) {
  const TargetSpec& spec = target.spec();
  const int cols = spec.cols;
  const int rows = spec.rows;
  Detection result;
  if (static_cast<int>(opencv_grid.size()) != cols * rows) {
    result.reason = "grid finder returned " + std::to_string(opencv_grid.size()) + " points, expected " +
                    std::to_string(cols * rows);
    return result;
  }
  const std::vector<GridCandidate> candidates = gridCandidates(target, gray, opencv_grid);
  if (candidates.empty()) {
    result.reason = "grid found but no ordering of it fits the target";
    return result;
  }
  const std::vector<GridCandidate> fitting = fittingCandidates(candidates, opencv_grid, cols, rows);
  if (fitting.empty()) {  // non-finite residuals (e.g. an absurd square size): nothing fits
    result.reason = "grid found but no ordering of it fits the target (check target.yaml's sizes)";
    return result;
  }
  // Ambiguous boards: x_M points as much as possible towards the image's right.
  const GridCandidate& chosen = *std::max_element(
      fitting.begin(), fitting.end(),
      [](const GridCandidate& a, const GridCandidate& b) { return a.x_axis_rightness < b.x_axis_rightness; });

  result.found = true;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const cv::Point2f& p = opencv_grid[opencvIndex(chosen.symmetry, cols, rows, c, r)];
      result.ids.push_back(r * cols + c);
      result.pixels.emplace_back(p.x, p.y);
    }
  }
  return result;
}

bool findChessboardSB(const cv::Mat& gray, cv::Size pattern, std::vector<cv::Point2f>* corners) {
  // Without CALIB_CB_EXHAUSTIVE: on a small, steeply tilted board that the classic finder
  // misses, the exhaustive search took 37 s for one 1024x768 image, and found nothing more.
  return cv::findChessboardCornersSB(gray, pattern, *corners, cv::CALIB_CB_ACCURACY | cv::CALIB_CB_NORMALIZE_IMAGE);
}

bool findChessboardClassic(const cv::Mat& gray, cv::Size pattern, int window_px, std::vector<cv::Point2f>* corners) {
  if (!cv::findChessboardCorners(gray, pattern, *corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK) &&
      !cv::findChessboardCorners(gray, pattern, *corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return false;
  if (window_px > 0) {
    cv::cornerSubPix(gray, *corners, cv::Size(window_px, window_px), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  }
  return true;
}

int chessboardWindow(double spacing_px, const DetectionOptions& options) {
  if (options.subpixel_window_px > 0) return options.subpixel_window_px;
  // The window (2w+1 px) must stay clear of the neighbouring corners: w ≈ 40 % of the
  // spacing, at least 2 px, at most 15 px (beyond that blur dominates anyway).
  return std::clamp(static_cast<int>(std::floor(0.4 * spacing_px)), 2, 15);
}

double neighbourSpacingPx(const Target& target, const Detection& detection) {
  const TargetSpec& spec = target.spec();
  std::vector<int> position(target.points().size(), -1);
  for (std::size_t i = 0; i < detection.ids.size(); ++i) position[detection.ids[i]] = static_cast<int>(i);
  double spacing = std::numeric_limits<double>::infinity();
  const auto consider = [&](int a, int b) {
    if (position[a] >= 0 && position[b] >= 0)
      spacing = std::min(spacing, (detection.pixels[position[a]] - detection.pixels[position[b]]).norm());
  };
  if (spec.type == TargetType::AprilTag) {
    for (std::size_t k = 0; k + 3 < position.size(); k += 4)
      for (int j = 0; j < 4; ++j) consider(static_cast<int>(k) + j, static_cast<int>(k) + (j + 1) % 4);
    return spacing;
  }
  for (int r = 0; r < spec.rows; ++r)
    for (int c = 0; c < spec.cols; ++c) {
      if (c + 1 < spec.cols) consider(r * spec.cols + c, r * spec.cols + c + 1);
      if (r + 1 < spec.rows) consider(r * spec.cols + c, (r + 1) * spec.cols + c);
    }
  return spacing;
}

}  // namespace detail

namespace {

cv::Mat toGray(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("detection: empty image");
  if (image.type() == CV_8UC1) return image;
  cv::Mat gray;
  if (image.type() == CV_8UC3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    return gray;
  }
  if (image.type() == CV_8UC4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
    return gray;
  }
  throw std::invalid_argument("detection: image must be 8-bit grey (or BGR), got OpenCV type " +
                              std::to_string(image.type()));
}

Detection refineChessboard(const Target& target, const cv::Mat& gray, const Detection& initial,
                           const DetectionOptions& options);

// Images whose long side exceeds this are searched at half size first (then at full size).
constexpr int kHalfSizeSearchMinSidePx = 1400;

// The chessboard search, cheap path first and bounded (doc/detection-speed.md).
// OpenCV's classic finder with CALIB_CB_FAST_CHECK and its global (histogram) threshold:
// the fast check rejects an image without a board in a few ms, and the quad search runs at
// most 16 passes. Its adaptive-threshold passes (48 more) and the search without the fast
// check are what took 0.8 s to 42 s on one 1024x768 image with a partial board, a board
// whose cols/rows differ from the target file's, or clutter, and findChessboardCornersSB
// costs 0.1-0.7 s: neither runs by default. The corners only seed the full-resolution
// cornerSubPix (refineChessboard), so the finder's own accuracy does not matter.
bool findChessboardFast(const cv::Mat& gray, cv::Size pattern, std::vector<cv::Point2f>* corners) {
  const int flags = cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
  if (std::max(gray.cols, gray.rows) >= kHalfSizeSearchMinSidePx) {
    cv::Mat half;
    cv::pyrDown(gray, half);
    if (cv::findChessboardCorners(half, pattern, *corners, flags)) {
      // A half-size pixel i covers full-size pixels 2i and 2i+1 (centre 2i + 0.5).
      for (cv::Point2f& corner : *corners) corner = 2.0f * corner + cv::Point2f(0.5f, 0.5f);
      return true;
    }
  }
  return cv::findChessboardCorners(gray, pattern, *corners, flags);
}

// findChessboardCorners + cornerSubPix (window from the corner spacing) measured 10×
// more accurate than findChessboardCornersSB on area-sampled renders (0.026 px RMS against
// 0.3–0.7 px, README "Detection accuracy"), and faster.
Detection detectChessboard(const Target& target, const cv::Mat& gray, const DetectionOptions& options) {
  const cv::Size pattern(target.spec().cols, target.spec().rows);
  std::vector<cv::Point2f> corners;
  if (!findChessboardFast(gray, pattern, &corners)) {
    Detection failed;
    failed.reason = "chessboard " + std::to_string(pattern.width) + "x" + std::to_string(pattern.height) +
                    " (inner corners) not found";
    return failed;
  }
  Detection ordered = detail::orderGrid(target, gray, corners);
  if (!ordered.found || !options.subpixel) return ordered;
  Detection refined = refineChessboard(target, gray, ordered, options);
  if (refined.reason.empty()) refined.reason = ordered.reason;
  return refined;
}

Detection refineChessboard(const Target& target, const cv::Mat& gray, const Detection& initial,
                           const DetectionOptions& options) {
  std::vector<cv::Point2f> corners;
  for (const Eigen::Vector2d& p : initial.pixels)
    corners.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  const int window = detail::chessboardWindow(detail::neighbourSpacingPx(target, initial), options);
  std::vector<cv::Point2f> refined = corners;
  cv::cornerSubPix(gray, refined, cv::Size(window, window), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  Detection result;
  for (std::size_t i = 0; i < refined.size(); ++i) {
    // A corner that wandered off by more than half its window did not converge on the
    // same X-junction: drop it.
    const bool inside =
        refined[i].x >= 0 && refined[i].y >= 0 && refined[i].x <= gray.cols - 1 && refined[i].y <= gray.rows - 1;
    if (!inside || cv::norm(refined[i] - corners[i]) > 0.5 * window) continue;
    result.ids.push_back(initial.ids[i]);
    result.pixels.emplace_back(refined[i].x, refined[i].y);
  }
  result.found = !result.ids.empty();
  if (result.ids.size() != initial.ids.size())
    result.reason = std::to_string(initial.ids.size() - result.ids.size()) + " corners dropped in sub-pixel refinement";
  return result;
}

cv::Ptr<cv::FeatureDetector> circleBlobDetector(const cv::Mat& gray, const Target& target) {
  cv::SimpleBlobDetector::Params params;
  params.filterByColor = true;
  params.blobColor = 0;  // dark discs on light paper
  params.minArea = 8.0f;
  // A disc can cover a large part of the image at close range.
  params.maxArea =
      static_cast<float>(gray.total()) / static_cast<float>(std::max(1, target.spec().cols * target.spec().rows / 2));
  params.minDistBetweenBlobs = 3.0f;
  return cv::SimpleBlobDetector::create(params);
}

Detection detectCircles(const Target& target, const cv::Mat& gray, const DetectionOptions& options) {
  const cv::Size pattern(target.spec().cols, target.spec().rows);
  const int grid_flag =
      target.spec().type == TargetType::Circles ? cv::CALIB_CB_SYMMETRIC_GRID : cv::CALIB_CB_ASYMMETRIC_GRID;
  const cv::Ptr<cv::FeatureDetector> blobs = circleBlobDetector(gray, target);
  std::vector<cv::Point2f> centres;
  bool found = cv::findCirclesGrid(gray, pattern, centres, grid_flag, blobs);
  if (!found) found = cv::findCirclesGrid(gray, pattern, centres, grid_flag | cv::CALIB_CB_CLUSTERING, blobs);
  if (!found) {
    Detection failed;
    failed.reason = targetTypeName(target.spec().type) + " grid " + std::to_string(pattern.width) + "x" +
                    std::to_string(pattern.height) + " not found";
    return failed;
  }
  Detection detection = detail::orderGrid(target, gray, centres);
  if (detection.found && options.subpixel) detail::refineCircleCentres(gray, target, &detection);
  return detection;
}

}  // namespace

Detection detectTarget(const Target& target, const cv::Mat& image, const DetectionOptions& options) {
  const cv::Mat gray = toGray(image);
  switch (target.spec().type) {
    case TargetType::Chessboard:
      return detectChessboard(target, gray, options);
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      return detectCircles(target, gray, options);
    case TargetType::AprilTag:
      return detail::detectAprilTagGrid(target, gray, options);
    case TargetType::Charuco:
      return detail::detectCharuco(target, gray, options);
    case TargetType::ArucoGrid:
      return detail::detectArucoGridCandidates(target, gray, options).front();
  }
  return {};
}

Detection refineDetection(const Target& target, const cv::Mat& image, const Detection& initial,
                          const DetectionOptions& options) {
  const cv::Mat gray = toGray(image);
  if (!initial.found || initial.ids.empty()) return initial;
  switch (target.spec().type) {
    case TargetType::Chessboard:
      return refineChessboard(target, gray, initial, options);
    case TargetType::Circles:
    case TargetType::AsymmetricCircles: {
      Detection result = initial;
      detail::refineCircleCentres(gray, target, &result);
      result.found = !result.ids.empty();
      return result;
    }
    case TargetType::AprilTag:
    case TargetType::Charuco:
    case TargetType::ArucoGrid: {
      // A full marker detection is cheap enough; keep only the features seen initially.
      const Detection fresh = detectTarget(target, gray, options);
      Detection result;
      std::vector<bool> wanted(target.points().size(), false);
      for (const int id : initial.ids) wanted[id] = true;
      for (std::size_t i = 0; i < fresh.ids.size(); ++i)
        if (wanted[fresh.ids[i]]) result.ids.push_back(fresh.ids[i]), result.pixels.push_back(fresh.pixels[i]);
      result.found = !result.ids.empty();
      result.reason = result.found ? fresh.reason : "no feature of the initial detection found again";
      return result;
    }
  }
  return initial;
}

}  // namespace mire::metrology
