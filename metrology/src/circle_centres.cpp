// Sub-pixel centres of dark discs.
//
// OpenCV's blob centres are centroids of binary contours averaged over thresholds, quantised
// by the pixel grid. Here each disc's centre is the centroid of its *coverage*: with the
// paper level `bg` and the ink level `fg` of the disc's own neighbourhood, a pixel's
// w = (bg − I)/(bg − fg) ∈ [0, 1] is the fraction of it covered by ink (exact for an
// area-sampling sensor; a symmetric blur moves ink around without moving its centroid).
// The centroid of the covered area is the centre of the imaged ellipse. (The image of the
// disc's centre differs from the ellipse's centre by a perspective term, which is the
// pose estimator's business, not the detector's.)
#include "detection_internal.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mire::metrology::detail {
namespace {

struct CentreResult {
  bool ok = false;
  Eigen::Vector2d centre;
};

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

// Refines one disc centre; `others` are the neighbouring centres bounding its cell.
CentreResult refineOne(const cv::Mat& gray, Eigen::Vector2d centre, const std::vector<Eigen::Vector2d>& others,
                       double radius_px) {
  CentreResult result;
  double cell = std::numeric_limits<double>::infinity();  // distance to the nearest neighbour
  for (const Eigen::Vector2d& other : others) cell = std::min(cell, (other - centre).norm());
  if (!std::isfinite(cell)) cell = 4.0 * radius_px;
  const double reach = std::max(radius_px * 2.5, cell);  // box half-size
  for (int iteration = 0; iteration < 3; ++iteration) {
    const int u0 = std::max(0, static_cast<int>(std::floor(centre.x() - reach)));
    const int u1 = std::min(gray.cols - 1, static_cast<int>(std::ceil(centre.x() + reach)));
    const int v0 = std::max(0, static_cast<int>(std::floor(centre.y() - reach)));
    const int v1 = std::min(gray.rows - 1, static_cast<int>(std::ceil(centre.y() + reach)));
    const cv::Point seed(static_cast<int>(std::lround(centre.x())) - u0, static_cast<int>(std::lround(centre.y())) - v0);
    if (seed.x < 1 || seed.y < 1 || seed.x >= u1 - u0 || seed.y >= v1 - v0) return result;
    // The Voronoi cell of this centre among its neighbours: no other disc's ink in it.
    cv::Mat in_cell = cv::Mat::zeros(v1 - v0 + 1, u1 - u0 + 1, CV_8UC1);
    std::vector<double> levels;
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        const Eigen::Vector2d p(u, v);
        const double own = (p - centre).squaredNorm();
        if (own > reach * reach) continue;
        bool closest = true;
        for (const Eigen::Vector2d& other : others)
          if ((p - other).squaredNorm() < own) {
            closest = false;
            break;
          }
        if (!closest) continue;
        in_cell.at<unsigned char>(v - v0, u - u0) = 1;
        levels.push_back(gray.at<unsigned char>(v, u));
      }
    }
    if (levels.size() < 16) return result;
    const double background = percentile(levels, 0.9);
    const double ink = percentile(levels, 0.02);
    if (background - ink < 10.0) return result;  // no contrast: not a disc
    // The disc: the dark connected region around the centre (so that dark things elsewhere
    // in the cell, e.g. beyond the paper's edge, do not count), grown by the blur width.
    const double middle = 0.5 * (background + ink);
    cv::Mat dark = cv::Mat::zeros(in_cell.size(), CV_8UC1);
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u)
        if (in_cell.at<unsigned char>(v - v0, u - u0) && gray.at<unsigned char>(v, u) < middle)
          dark.at<unsigned char>(v - v0, u - u0) = 255;
    if (!dark.at<unsigned char>(seed)) return result;  // the centre is not on ink
    cv::Mat disc = cv::Mat::zeros(dark.rows + 2, dark.cols + 2, CV_8UC1);
    cv::floodFill(dark, disc, seed, cv::Scalar(0), nullptr, cv::Scalar(0), cv::Scalar(0),
                  4 | cv::FLOODFILL_MASK_ONLY | (255 << 8));
    disc = disc(cv::Rect(1, 1, dark.cols, dark.rows)).clone();
    // A disc touching the box's edge is cut by the image border or merged with something.
    if (cv::countNonZero(disc.row(0)) || cv::countNonZero(disc.row(disc.rows - 1)) || cv::countNonZero(disc.col(0)) ||
        cv::countNonZero(disc.col(disc.cols - 1)))
      return result;
    cv::dilate(disc, disc, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
    double sum_w = 0.0, sum_u = 0.0, sum_v = 0.0;
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        if (!disc.at<unsigned char>(v - v0, u - u0) || !in_cell.at<unsigned char>(v - v0, u - u0)) continue;
        const double w = std::clamp((background - gray.at<unsigned char>(v, u)) / (background - ink), 0.0, 1.0);
        sum_w += w;
        sum_u += w * u;
        sum_v += w * v;
      }
    }
    if (sum_w < 3.0) return result;
    const Eigen::Vector2d updated(sum_u / sum_w, sum_v / sum_w);
    const double moved = (updated - centre).norm();
    centre = updated;
    if (moved > radius_px + 2.0) return result;  // ran off the disc
    if (moved < 1e-3) break;
  }
  result.ok = true;
  result.centre = centre;
  return result;
}

}  // namespace

std::vector<bool> refineCircleCentres(const cv::Mat& gray, const Target& target, Detection* detection) {
  const std::size_t n = detection->pixels.size();
  std::vector<bool> ok(n, false);
  const double ratio = target.spec().diameter_m / target.featureSpacing();  // disc size / nearest spacing
  Detection refined;
  refined.found = false;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Eigen::Vector2d> others;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) nearest = std::min(nearest, (detection->pixels[j] - detection->pixels[i]).norm());
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && (detection->pixels[j] - detection->pixels[i]).norm() < 3.0 * nearest)
        others.push_back(detection->pixels[j]);
    const double radius_px = std::isfinite(nearest) ? 0.5 * ratio * nearest : 5.0;
    const CentreResult centre = refineOne(gray, detection->pixels[i], others, radius_px);
    if (!centre.ok) continue;
    ok[i] = true;
    refined.ids.push_back(detection->ids[i]);
    refined.pixels.push_back(centre.centre);
  }
  refined.found = detection->found && !refined.ids.empty();
  const std::size_t dropped = n - refined.ids.size();
  refined.reason =
      dropped == 0 ? detection->reason : std::to_string(dropped) + " circles dropped in sub-pixel refinement";
  *detection = refined;
  return ok;
}

}  // namespace mire::metrology::detail
