#pragma once
// The printed target as a function of the point (X, Y) on its plane (frame M, metres):
// what the renderer samples. Layout as in metrology/target.hpp; doc/file-formats.md, "Target frame M" for the colours
// (chessboard: the square at x < 0, y < 0 is dark).
#include "mire/metrology/target.hpp"

#include <cstdint>
#include <vector>

namespace mire::datasets {

class TargetAlbedo {
 public:
  TargetAlbedo(const metrology::Target& target, float dark_level, float light_level);

  // Grey level printed at (x, y), or a negative value off the paper (background shows).
  float operator()(double x, double y) const {
    if (x < paper_min_x_ || x > paper_max_x_ || y < paper_min_y_ || y > paper_max_y_) return -1.0f;
    return printed(x, y);
  }

  // The paper's extent in frame M: the features' layout plus a white margin.
  double paperMinX() const { return paper_min_x_; }
  double paperMaxX() const { return paper_max_x_; }
  double paperMinY() const { return paper_min_y_; }
  double paperMaxY() const { return paper_max_y_; }

 private:
  float printed(double x, double y) const;
  float chessboard(double x, double y) const;
  float items(double x, double y) const;  // discs, tags or markers, through the bucket grid
  // ArUco markers of a charuco / aruco_grid target; sets the paper's extent, returns its margin.
  double addArucoMarkers(const metrology::Target& target, double* min_x, double* min_y, double* max_x, double* max_y);
  // AprilTags of an apriltag target; widens the extent by the tags' outer ring, returns the margin.
  double addAprilTags(const metrology::Target& target, double* min_x, double* min_y, double* max_x, double* max_y);
  // The bucket grid over the paper, once discs or tags and the paper's extent are known.
  void fillBuckets();

  struct Disc {
    double cx, cy, radius2;
  };
  struct Tag {
    double x0, y0;  // top-left corner of the tag's bitmap (AprilTag: outer white ring included)
    int bitmap;     // index into bitmaps_
  };
  struct Bitmap {
    int size = 0;                    // total_width cells per side
    std::vector<std::uint8_t> dark;  // size * size, row-major (rows along +y, columns along +x)
  };

  metrology::TargetSpec spec_;
  float dark_;
  float light_;
  double paper_min_x_ = 0, paper_max_x_ = 0, paper_min_y_ = 0, paper_max_y_ = 0;

  // Discs or tags are found through a uniform bucket grid over the paper.
  double bucket_size_ = 1.0;
  int bucket_cols_ = 0, bucket_rows_ = 0;
  std::vector<std::vector<int>> buckets_;
  std::vector<Disc> discs_;
  std::vector<Tag> tags_;
  std::vector<Bitmap> bitmaps_;
  double tag_cell_ = 0.0;  // AprilTag / ArUco bit cell size (m)
};

}  // namespace mire::datasets
