// The printed target's grey level at a point of its plane (see target_albedo.hpp).
#include "target_albedo.hpp"

// The tag-family table is metrology's (one list of AprilTag families in the project).
#include "mire/metrology/apriltag_family.hpp"
#include "mire/metrology/aruco_boards.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_types.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace mire::datasets {
namespace {

// image_u8_destroy lives in libapriltag-utils, which the apriltag pkg-config entry does not
// link; apriltag_to_image allocates the image and its buffer with calloc, so free both.
struct ImageDeleter {
  void operator()(image_u8_t* image) const {
    if (image == nullptr) return;
    std::free(image->buf);
    std::free(image);
  }
};

}  // namespace

TargetAlbedo::TargetAlbedo(const metrology::Target& target, float dark_level, float light_level)
    : spec_(target.spec()), dark_(dark_level), light_(light_level) {
  using metrology::TargetType;
  const auto& points = target.points();
  double min_x = points.front().x(), max_x = min_x, min_y = points.front().y(), max_y = min_y;
  for (const auto& point : points) {
    min_x = std::min(min_x, point.x()), max_x = std::max(max_x, point.x());
    min_y = std::min(min_y, point.y()), max_y = std::max(max_y, point.y());
  }
  double margin = 0.0;
  switch (spec_.type) {
    case TargetType::Chessboard:
      // Squares run from -s to cols·s (inner corners at 0..(cols-1)·s); then a white margin
      // of one square, the quiet zone corner finders expect.
      margin = 2.0 * spec_.square_size_m;
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles: {
      margin = std::max(spec_.spacing_m, spec_.diameter_m);
      for (const auto& point : points)
        discs_.push_back({point.x(), point.y(), 0.25 * spec_.diameter_m * spec_.diameter_m});
      bucket_size_ = spec_.diameter_m;
      break;
    }
    case TargetType::AprilTag:
      margin = addAprilTags(target, &min_x, &min_y, &max_x, &max_y);
      break;
    case TargetType::Charuco:
    case TargetType::ArucoGrid:
      margin = addArucoMarkers(target, &min_x, &min_y, &max_x, &max_y);
      break;
  }
  paper_min_x_ = min_x - margin, paper_max_x_ = max_x + margin;
  paper_min_y_ = min_y - margin, paper_max_y_ = max_y + margin;

  if (!discs_.empty() || !tags_.empty()) fillBuckets();
}

double TargetAlbedo::addAprilTags(const metrology::Target& target, double* min_x, double* min_y, double* max_x,
                                  double* max_y) {
  const auto& points = target.points();
  const metrology::detail::TagFamilyPtr family = metrology::detail::createTagFamily(spec_.family);
  if (!family) throw std::invalid_argument("unknown AprilTag family '" + spec_.family + "'");
  // tag_size_m is the edge of the width_at_border square (where the detector puts the
  // corners); the bitmap (total_width cells) is centred on it.
  tag_cell_ = spec_.tag_size_m / family->width_at_border;
  const int border_start = (family->total_width - family->width_at_border) / 2;
  const int count = static_cast<int>(target.tagLayout().size());
  for (int k = 0; k < count; ++k) {
    const std::unique_ptr<image_u8_t, ImageDeleter> image(
        apriltag_to_image(family.get(), static_cast<uint32_t>(target.tagLayout()[static_cast<std::size_t>(k)].id)));
    Bitmap bitmap;
    bitmap.size = image->width;
    bitmap.dark.resize(static_cast<std::size_t>(bitmap.size) * bitmap.size);
    for (int row = 0; row < bitmap.size; ++row)
      for (int col = 0; col < bitmap.size; ++col)
        bitmap.dark[static_cast<std::size_t>(row) * bitmap.size + col] = image->buf[row * image->stride + col] < 128;
    bitmaps_.push_back(std::move(bitmap));
    const Eigen::Vector3d& top_left = points[4 * static_cast<std::size_t>(k)];
    tags_.push_back({top_left.x() - border_start * tag_cell_, top_left.y() - border_start * tag_cell_, k});
  }
  const double outside = border_start * tag_cell_;
  *min_x -= outside, *min_y -= outside;
  *max_x += outside, *max_y += outside;
  bucket_size_ = family->total_width * tag_cell_;
  return 2.0 * tag_cell_;
}

// Each disc or tag goes into every bucket its bounding box touches.
void TargetAlbedo::fillBuckets() {
  bucket_cols_ = static_cast<int>(std::ceil((paper_max_x_ - paper_min_x_) / bucket_size_)) + 1;
  bucket_rows_ = static_cast<int>(std::ceil((paper_max_y_ - paper_min_y_) / bucket_size_)) + 1;
  buckets_.resize(static_cast<std::size_t>(bucket_cols_) * bucket_rows_);
  const auto insert = [&](int item, double x0, double y0, double x1, double y1) {
    const int c0 = std::max(0, static_cast<int>((x0 - paper_min_x_) / bucket_size_));
    const int c1 = std::min(bucket_cols_ - 1, static_cast<int>((x1 - paper_min_x_) / bucket_size_));
    const int r0 = std::max(0, static_cast<int>((y0 - paper_min_y_) / bucket_size_));
    const int r1 = std::min(bucket_rows_ - 1, static_cast<int>((y1 - paper_min_y_) / bucket_size_));
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) buckets_[static_cast<std::size_t>(r) * bucket_cols_ + c].push_back(item);
  };
  for (std::size_t i = 0; i < discs_.size(); ++i) {
    const double radius = std::sqrt(discs_[i].radius2);
    insert(static_cast<int>(i), discs_[i].cx - radius, discs_[i].cy - radius, discs_[i].cx + radius,
           discs_[i].cy + radius);
  }
  for (std::size_t i = 0; i < tags_.size(); ++i) {
    const double extent = bitmaps_[static_cast<std::size_t>(tags_[i].bitmap)].size * tag_cell_;
    insert(static_cast<int>(i), tags_[i].x0, tags_[i].y0, tags_[i].x0 + extent, tags_[i].y0 + extent);
  }
}

double TargetAlbedo::addArucoMarkers(const metrology::Target& target, double* min_x, double* min_y, double* max_x,
                                     double* max_y) {
  // The marker bits are OpenCV's own (cv::aruco::drawMarker, one pixel per cell, one-cell black
  // border); the marker corners are the boards' object points, which agree with
  // Target::points() (OpenCV's CharucoBoard / GridBoard layouts, doc/targets.md).
  const bool charuco = spec_.type == metrology::TargetType::Charuco;
  const cv::Ptr<cv::aruco::Board> board = charuco ? cv::Ptr<cv::aruco::Board>(metrology::charucoBoard(target))
                                                  : cv::Ptr<cv::aruco::Board>(metrology::arucoGridBoard(target));
  const int cells = board->dictionary->markerSize + 2;
  tag_cell_ = spec_.marker_size_m / cells;
  for (std::size_t k = 0; k < board->ids.size(); ++k) {
    cv::Mat image;
    cv::aruco::drawMarker(board->dictionary, board->ids[k], cells, image, 1);
    Bitmap bitmap;
    bitmap.size = cells;
    bitmap.dark.resize(static_cast<std::size_t>(cells) * cells);
    for (int row = 0; row < cells; ++row)
      for (int col = 0; col < cells; ++col)
        bitmap.dark[static_cast<std::size_t>(row) * cells + col] = image.at<unsigned char>(row, col) < 128;
    bitmaps_.push_back(std::move(bitmap));
    const cv::Point3f& top_left = board->objPoints[k][0];
    tags_.push_back({top_left.x, top_left.y, static_cast<int>(k)});
  }
  bucket_size_ = spec_.marker_size_m;
  if (charuco) {  // the squares run from 0 to cols·s (features are the inner corners)
    *min_x = 0.0, *min_y = 0.0;
    *max_x = spec_.cols * spec_.square_size_m, *max_y = spec_.rows * spec_.square_size_m;
    return spec_.square_size_m;
  }
  // aruco_grid: the feature points already span the markers' outer corners.
  return std::max(spec_.marker_spacing_m, 2.0 * tag_cell_);
}

float TargetAlbedo::printed(double x, double y) const {
  if (spec_.type == metrology::TargetType::Chessboard) return chessboard(x, y);
  if (spec_.type == metrology::TargetType::Charuco) {
    const double s = spec_.square_size_m;
    const int ix = static_cast<int>(std::floor(x / s));
    const int iy = static_cast<int>(std::floor(y / s));
    if (ix < 0 || ix >= spec_.cols || iy < 0 || iy >= spec_.rows) return light_;  // margin
    // OpenCV's board: square (0, 0) is dark, markers sit in the light squares.
    if (((ix + iy) & 1) == 0) return dark_;
  }
  return items(x, y);
}

float TargetAlbedo::chessboard(double x, double y) const {
  const double s = spec_.square_size_m;
  const int ix = static_cast<int>(std::floor(x / s));
  const int iy = static_cast<int>(std::floor(y / s));
  if (ix < -1 || ix > spec_.cols - 1 || iy < -1 || iy > spec_.rows - 1) return light_;  // margin
  // Square (-1, -1), just outside the origin, is dark (doc/file-formats.md, "Target frame M"): dark when ix + iy
  // is even.
  return ((ix + iy) & 1) == 0 ? dark_ : light_;
}

float TargetAlbedo::items(double x, double y) const {
  const int c = static_cast<int>((x - paper_min_x_) / bucket_size_);
  const int r = static_cast<int>((y - paper_min_y_) / bucket_size_);
  if (c < 0 || c >= bucket_cols_ || r < 0 || r >= bucket_rows_) return light_;
  for (const int item : buckets_[static_cast<std::size_t>(r) * bucket_cols_ + c]) {
    if (!discs_.empty()) {
      const Disc& disc = discs_[static_cast<std::size_t>(item)];
      const double dx = x - disc.cx, dy = y - disc.cy;
      if (dx * dx + dy * dy <= disc.radius2) return dark_;
    } else {
      const Tag& tag = tags_[static_cast<std::size_t>(item)];
      const Bitmap& bitmap = bitmaps_[static_cast<std::size_t>(tag.bitmap)];
      const double u = (x - tag.x0) / tag_cell_, v = (y - tag.y0) / tag_cell_;
      if (u < 0.0 || v < 0.0 || u >= bitmap.size || v >= bitmap.size) continue;
      const int col = static_cast<int>(u), row = static_cast<int>(v);
      return bitmap.dark[static_cast<std::size_t>(row) * bitmap.size + col] ? dark_ : light_;
    }
  }
  return light_;
}

}  // namespace mire::datasets
