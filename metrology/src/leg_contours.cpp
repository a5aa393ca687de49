#include "mire/metrology/leg_contours.hpp"

#include "mire/support/constants.hpp"
#include "silhouette_edge.hpp"

#include <opencv2/imgproc.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>

namespace mire::metrology {
namespace {

using Eigen::Vector2d;

double bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const float* row0 = image.ptr<float>(y0);
  const float* row1 = image.ptr<float>(y0 + 1);
  return (1 - fy) * ((1 - fx) * row0[x0] + fx * row0[x0 + 1]) + fy * ((1 - fx) * row1[x0] + fx * row1[x0 + 1]);
}

// A place on a predicted contour where the profile is searched: its pixel, the unit normal
// pointing into the rod, and the rod's apparent radius there [px].
struct SearchSite {
  Vector2d pixel;
  Vector2d inward;
  double radius_px = 0.0;
};

struct Edge {
  Vector2d pixel;
  double offset = 0.0;  // along the inward normal from the predicted contour [px]
  SearchSite site;
};

bool insideImage(const cv::Mat& image, const Vector2d& p) {
  return p.x() >= 1.0 && p.y() >= 1.0 && p.x() <= image.cols - 3.0 && p.y() <= image.rows - 3.0;
}

// The search sites of one predicted contour: its generator (the axis moved by −r·n) projected
// with the lens distortion, `count` of them evenly on the segment's middle part (both contours
// share the grid, so that sites of the same index face each other); none where the band leaves
// the image.
std::vector<std::optional<SearchSite>> searchSites(const EdgeImage& image, const calibration::Camera& camera,
                                                   const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                                   const Eigen::Vector3d& shift, double margin, int count,
                                                   double search_px) {
  std::vector<std::optional<SearchSite>> sites(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double t = margin + (1.0 - 2.0 * margin) * (i + 0.5) / count;
    const Eigen::Vector3d point = from + t * (to - from);
    Vector2d pixel, ahead, centre;
    if (!camera.project(point + shift, &pixel) || !camera.project(point + shift + 1e-3 * (to - from), &ahead) ||
        !camera.project(point, &centre))
      continue;
    Vector2d normal = Vector2d(-(ahead - pixel).y(), (ahead - pixel).x()).normalized();
    if (normal.dot(centre - pixel) < 0.0) normal = -normal;
    const double band = search_px + 6.0;  // the band and the profile fitted beyond it
    if (insideImage(image.grey, pixel + band * normal) && insideImage(image.grey, pixel - band * normal))
      sites[static_cast<std::size_t>(i)] = SearchSite{pixel, normal, (centre - pixel).norm()};
  }
  return sites;
}

// The strongest edge of the given polarity along the profile (sign·gradient·inward maximal), the
// peak interpolated by a parabola through its neighbours; none when the peak is at the band's end
// or the gradient there points more than 30° away from the contour's normal. (On a shaded rod this
// lies a little outside the silhouette; silhouetteShift corrects the fitted line.)
std::optional<Edge> findEdge(const EdgeImage& image, const SearchSite& site, double search_px, double sign) {
  const int half = static_cast<int>(search_px);
  std::vector<double> profile;
  for (int s = -half; s <= half; ++s) {
    const Vector2d p = site.pixel + s * site.inward;
    profile.push_back(sign * (bilinear(image.gx, p.x(), p.y()) * site.inward.x() +
                              bilinear(image.gy, p.x(), p.y()) * site.inward.y()));
  }
  const auto peak = std::max_element(profile.begin() + 1, profile.end() - 1);
  const auto k = static_cast<std::size_t>(peak - profile.begin());
  if (!(*peak > 0.0) || *peak < profile[k - 1] || *peak < profile[k + 1]) return std::nullopt;
  const double curvature = profile[k - 1] - 2.0 * profile[k] + profile[k + 1];
  const double offset =
      static_cast<double>(k) - half + (curvature < 0.0 ? 0.5 * (profile[k - 1] - profile[k + 1]) / curvature : 0.0);
  const Vector2d pixel = site.pixel + offset * site.inward;
  const Vector2d g(bilinear(image.gx, pixel.x(), pixel.y()), bilinear(image.gy, pixel.x(), pixel.y()));
  if (sign * g.dot(site.inward) < std::cos(30.0 * support::kPi / 180.0) * g.norm()) return std::nullopt;
  return Edge{pixel, offset, site};
}

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// Weighted total least squares: the line through the weighted centroid along the scatter's
// principal direction.
ContourLine weightedLine(const std::vector<Vector2d>& points, const std::vector<double>& weights) {
  Vector2d centroid = Vector2d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    centroid += weights[i] * points[i];
    total += weights[i];
  }
  centroid /= total;
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i)
    scatter += weights[i] * (points[i] - centroid) * (points[i] - centroid).transpose();
  const Vector2d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(0);
  return {std::atan2(normal.y(), normal.x()), normal.dot(centroid)};
}

double residual(const ContourLine& line, const Vector2d& p) {
  return std::cos(line.theta) * p.x() + std::sin(line.theta) * p.y() - line.rho;
}

constexpr double kMaxTurn = 5.0 * support::kPi / 180.0;

// RANSAC on pairs (deterministic draws) for a start that ignores where the target or another leg
// crosses, then Tukey's biweight by iteratively reweighted least squares. The covariance of
// (θ, ρ) is σ²·(Σ w·J·Jᵀ)⁻¹ with J = ∂residual/∂(θ, ρ) and σ² the weighted residual variance.
std::optional<ContourFit> fitContour(const std::vector<Vector2d>& points, double pixel_size, int min_points,
                                     const ContourLine& predicted) {
  const std::size_t n = points.size();
  if (static_cast<int>(n) < min_points) return std::nullopt;
  std::mt19937 random(1);
  std::uniform_int_distribution<std::size_t> draw(0, n - 1);
  ContourLine line;
  std::size_t best = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t i = draw(random), j = draw(random);
    if (i == j) continue;
    const Vector2d normal = Vector2d(-(points[j] - points[i]).y(), (points[j] - points[i]).x()).normalized();
    const ContourLine candidate{std::atan2(normal.y(), normal.x()), normal.dot(points[i])};
    // A ruler's camera placement predicts the contour's direction within a degree or two: a line
    // further off is something else's edge (the target's border, a square).
    if (std::abs(std::cos(candidate.theta - predicted.theta)) < std::cos(kMaxTurn)) continue;
    std::size_t support = 0;
    for (const Vector2d& p : points) support += std::abs(residual(candidate, p)) < 1.0 * pixel_size ? 1 : 0;
    if (support > best) {
      best = support;
      line = candidate;
    }
  }
  std::vector<double> weights(n, 0.0);
  for (int iteration = 0; iteration < 20; ++iteration) {
    std::vector<double> inlier_residuals;
    for (const Vector2d& p : points)
      if (std::abs(residual(line, p)) < 3.0 * pixel_size) inlier_residuals.push_back(std::abs(residual(line, p)));
    if (static_cast<int>(inlier_residuals.size()) < min_points) return std::nullopt;
    const double scale = std::max(1.4826 * median(inlier_residuals), 0.01 * pixel_size);
    const double c = 4.685 * scale;
    for (std::size_t i = 0; i < n; ++i) {
      const double u = residual(line, points[i]) / c;
      weights[i] = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
    const ContourLine next = weightedLine(points, weights);
    const bool settled = std::abs(next.theta - line.theta) < 1e-12 && std::abs(next.rho - line.rho) < 1e-14;
    line = std::cos(next.theta - line.theta) < 0 ? ContourLine{next.theta + support::kPi, -next.rho} : next;
    if (settled) break;
  }
  ContourFit fit;
  // Oriented as the prediction (the rod's inside positive) before the covariance, whose (θ, ρ)
  // correlation changes sign with the orientation.
  fit.line = std::cos(line.theta - predicted.theta) < 0.0 ? ContourLine{line.theta + support::kPi, -line.rho} : line;
  line = fit.line;
  double sum_w = 0.0, sum_we2 = 0.0;
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (weights[i] <= 0.0) continue;
    const double e = residual(line, points[i]);
    const Vector2d jacobian(-std::sin(line.theta) * points[i].x() + std::cos(line.theta) * points[i].y(), -1.0);
    information += weights[i] * jacobian * jacobian.transpose();
    sum_w += weights[i];
    sum_we2 += weights[i] * e * e;
    ++fit.edge_points;
  }
  if (fit.edge_points < min_points) return std::nullopt;
  fit.covariance = sum_we2 / (sum_w - 2.0) * information.inverse();
  return fit;
}

// Where the silhouette lies from the fitted contour line [px, along the inward normal] on a stretch
// of the contour: the image's levels at the pixel centres next to its kept edge points, by their
// distance u to the line (an edge spread function sampled at every sub-pixel phase), fitted by the
// silhouette's profile model (silhouette_edge.hpp) from 5 px outside to the rod's middle. Each kept
// edge point lends the pixels within half a sample spacing along the contour, a profile with its
// own levels. Also returns the
// stretch's middle on the line [px].
struct Shift {
  Vector2d middle;  // of the stretch, on the fitted line [px]
  SilhouetteEdge edge;
};
std::optional<Shift> silhouetteShift(const EdgeImage& image, const calibration::Camera& camera, const ContourLine& line,
                                     const std::vector<Edge>& kept, double spacing_px) {
  std::vector<std::vector<double>> positions, levels;
  Vector2d middle = Vector2d::Zero();
  std::size_t samples = 0;
  double radius_px = 0.0;
  for (const Edge& edge : kept) {
    Vector2d normalized;
    if (!camera.unproject(edge.pixel, &normalized)) return std::nullopt;
    const Vector2d& n = edge.site.inward;
    const Vector2d along(-n.y(), n.x());
    const Vector2d on_line = edge.pixel - residual(line, normalized) * camera.fx() * n;
    middle += on_line / static_cast<double>(kept.size());
    radius_px += edge.site.radius_px / static_cast<double>(kept.size());
    const double inside = edge.site.radius_px;
    const double reach = std::max(inside, 5.0) + spacing_px;
    positions.emplace_back();
    levels.emplace_back();
    for (int y = static_cast<int>(on_line.y() - reach); y <= static_cast<int>(on_line.y() + reach) + 1; ++y)
      for (int x = static_cast<int>(on_line.x() - reach); x <= static_cast<int>(on_line.x() + reach) + 1; ++x) {
        if (x < 0 || y < 0 || x >= image.grey.cols || y >= image.grey.rows) continue;
        const Vector2d d = Vector2d(x, y) - on_line;
        const double u = d.dot(n);
        if (std::abs(d.dot(along)) > 0.5 * spacing_px || u < -5.0 || u > inside) continue;
        positions.back().push_back(u);
        levels.back().push_back(image.grey.at<float>(y, x));
        ++samples;
      }
  }
  if (samples < 50) return std::nullopt;
  const std::optional<SilhouetteEdge> edge = silhouetteEdge(positions, levels, 0.0, radius_px);
  if (!edge) return std::nullopt;
  return Shift{middle, *edge};
}

// The fitted line moved onto the silhouette: its shift found on each half of the contour (the
// gradient's offset from the silhouette changes with the rod's apparent radius along it), the
// line through the two moved middles; `noise` the covariance of (θ, ρ) from the two shifts' σ,
// `systematic` for an error of `silhouette_px` at each middle, independently.
std::optional<ContourLine> onSilhouette(const EdgeImage& image, const calibration::Camera& camera,
                                        const ContourLine& line, const std::vector<Edge>& kept, double spacing_px,
                                        double silhouette_px, Eigen::Matrix2d* noise, Eigen::Matrix2d* systematic) {
  const auto half = static_cast<long>(kept.size() / 2);
  const std::vector<Edge> first(kept.begin(), kept.begin() + half), second(kept.begin() + half, kept.end());
  const auto a = silhouetteShift(image, camera, line, first, spacing_px);
  const auto b = silhouetteShift(image, camera, line, second, spacing_px);
  if (!a || !b) return std::nullopt;
  const Vector2d inward_a = first[first.size() / 2].site.inward, inward_b = second[second.size() / 2].site.inward;
  Vector2d p, q;
  if (!camera.unproject(a->middle + a->edge.position * inward_a, &p) ||
      !camera.unproject(b->middle + b->edge.position * inward_b, &q))
    return std::nullopt;
  const Vector2d normal = Vector2d(-(q - p).y(), (q - p).x()).normalized();
  ContourLine moved{std::atan2(normal.y(), normal.x()), normal.dot(p)};
  if (std::cos(moved.theta - line.theta) < 0.0) moved = {moved.theta + support::kPi, -moved.rho};
  // Errors e_a, e_b [normalised] at the two middles: θ moves by (e_b − e_a)/|q − p|, ρ at their
  // midpoint by (e_a + e_b)/2, and ρ at the origin by that plus (t·midpoint)·δθ.
  const Vector2d mid = 0.5 * (p + q), tangent(-std::sin(moved.theta), std::cos(moved.theta));
  Eigen::Matrix2d to_line;
  to_line << -1.0 / (q - p).norm(), 1.0 / (q - p).norm(), 0.5, 0.5;
  Eigen::Matrix2d to_origin;
  to_origin << 1.0, 0.0, tangent.dot(mid), 1.0;
  const Eigen::Matrix2d jacobian = to_origin * to_line;
  const auto covariance = [&](double sigma_a, double sigma_b) {
    const Eigen::Vector2d variance(sigma_a * sigma_a, sigma_b * sigma_b);
    return Eigen::Matrix2d(jacobian * variance.asDiagonal() * jacobian.transpose() / (camera.fx() * camera.fx()));
  };
  *noise = covariance(a->edge.sigma, b->edge.sigma);
  *systematic = covariance(silhouette_px, silhouette_px);
  return moved;
}

}  // namespace

EdgeImage EdgeImage::of(const cv::Mat& grey) {
  EdgeImage image;
  grey.convertTo(image.grey, CV_32F);
  cv::Mat smooth;
  cv::GaussianBlur(image.grey, smooth, cv::Size(7, 7), 1.0);
  cv::Sobel(smooth, image.gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(smooth, image.gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  return image;
}

LegContours measureLegContours(const EdgeImage& image, const calibration::Camera& camera, const Eigen::Vector3d& from,
                               const Eigen::Vector3d& to, double radius, const LegContourOptions& options) {
  LegContours result;
  std::array<ContourLine, 2> predicted;
  try {
    predicted = cylinderContours(support::Line3d::throughPoints(from, to), radius);
  } catch (const std::invalid_argument& e) {
    result.error = e.what();
    return result;
  }
  // The sites: every spacing_px along the longer projected contour, the rod's ends left out
  // (end_margin of the segment, at least 3 radii: the end caps, the joints).
  Vector2d a, b;
  if (!camera.project(from, &a) || !camera.project(to, &b)) {
    result.error = "the leg is behind the camera";
    return result;
  }
  const double margin = std::max(options.end_margin, 3.0 * radius / (to - from).norm());
  const int count = static_cast<int>((1.0 - 2.0 * margin) * (b - a).norm() / options.spacing_px) + 1;
  std::array<std::vector<std::optional<SearchSite>>, 2> sites;
  for (int k = 0; k < 2; ++k) {
    sites[k] =
        searchSites(image, camera, from, to, -radius * predicted[k].planeNormal(), margin, count, options.search_px);
    const auto inside = std::count_if(sites[k].begin(), sites[k].end(), [](const auto& s) { return s.has_value(); });
    if (inside < options.min_edge_points) {
      result.error = "the leg is outside the image or too short in it (" + std::to_string(inside) +
                     " search sites on a contour, at least " + std::to_string(options.min_edge_points) + " needed)";
      return result;
    }
  }
  // Both polarities, and at each pair of facing sites both edges or neither: the two edges must
  // keep the rod's predicted apparent width (their inward offsets cancel, within a tenth of the
  // width or 1.5 px), which the target's border, its squares and the other legs do not. With the
  // wrong polarity each contour's search finds the other contour; the polarity with more pairs wins.
  std::array<std::vector<Edge>, 2> chosen;
  for (const double sign : {1.0, -1.0}) {
    std::array<std::vector<Edge>, 2> edges;
    for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
      if (!sites[0][i] || !sites[1][i]) continue;
      const auto first = findEdge(image, *sites[0][i], options.search_px, sign);
      const auto second = findEdge(image, *sites[1][i], options.search_px, sign);
      if (!first || !second) continue;
      const double width = sites[0][i]->radius_px + sites[1][i]->radius_px;
      if (std::abs(first->offset + second->offset) > std::max(1.5, 0.1 * width)) continue;
      edges[0].push_back(*first);
      edges[1].push_back(*second);
    }
    if (edges[0].size() > chosen[0].size()) chosen = edges;
  }
  for (int k = 0; k < 2; ++k) {
    std::vector<Vector2d> points;
    for (const Edge& edge : chosen[k]) {
      Vector2d normalized;
      if (camera.unproject(edge.pixel, &normalized)) points.push_back(normalized);
    }
    auto fit = fitContour(points, 1.0 / camera.fx(), options.min_edge_points, predicted[static_cast<std::size_t>(k)]);
    if (!fit) {
      result.error = "too few edge points on contour " + std::to_string(k + 1) + " (" + std::to_string(points.size()) +
                     " found, at least " + std::to_string(options.min_edge_points) + " needed on one line)";
      return result;
    }
    std::vector<Edge> kept;
    for (const Edge& edge : chosen[k]) {
      Vector2d normalized;
      if (camera.unproject(edge.pixel, &normalized) && std::abs(residual(fit->line, normalized)) < 1.0 / camera.fx()) {
        kept.push_back(edge);
        fit->inliers_px.push_back(edge.pixel);
      }
    }
    Eigen::Matrix2d shift_noise;
    const std::optional<ContourLine> moved = onSilhouette(image, camera, fit->line, kept, options.spacing_px,
                                                          options.silhouette_px, &shift_noise, &fit->systematic);
    if (!moved) {
      result.error = "the edge profile of contour " + std::to_string(k + 1) + " does not fit a rod's silhouette";
      return result;
    }
    fit->line = *moved;
    fit->covariance += shift_noise;
    result.contours[static_cast<std::size_t>(k)] = *fit;
  }
  result.ok = true;
  return result;
}

}  // namespace mire::metrology
