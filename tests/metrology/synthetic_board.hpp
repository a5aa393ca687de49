#pragma once
// A small, exact renderer for detector tests: a pinhole camera (no distortion) looking at a
// target, area-sampled (supersampling then box filter), blurred and noisy. Ground truth is
// the projection of Target::points() with OpenCV's pixel convention. (The project's full
// renderer lives in datasets/; this one only has to be exact, not fast or realistic.)
#include "mire/metrology/target.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <opencv2/imgproc.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

namespace mire::test {

// A chessboard target of cols × rows inner corners of square_m.
inline metrology::Target chessboard(int cols, int rows, double square_m) {
  metrology::TargetSpec spec;
  spec.type = metrology::TargetType::Chessboard;
  spec.cols = cols;
  spec.rows = rows;
  spec.square_size_m = square_m;
  return metrology::Target(spec);
}

struct SyntheticView {
  int width = 640;
  int height = 480;
  double f = 600.0;
  Eigen::Isometry3d camera_T_target = Eigen::Isometry3d::Identity();
  int supersample = 4;
  double blur_sigma_px = 0.6;
  double noise_sigma = 1.0;  // grey levels
  unsigned seed = 1;
  double dark = 30.0;
  double light = 220.0;

  Eigen::Matrix3d intrinsics() const {
    Eigen::Matrix3d k;
    k << f, 0, 0.5 * (width - 1) + 3.3, 0, f, 0.5 * (height - 1) - 2.1, 0, 0, 1;
    return k;
  }
  // Target plane (x, y) in metres -> pixel (OpenCV convention).
  Eigen::Matrix3d homography() const {
    Eigen::Matrix3d rt;
    rt.col(0) = camera_T_target.linear().col(0);
    rt.col(1) = camera_T_target.linear().col(1);
    rt.col(2) = camera_T_target.translation();
    return intrinsics() * rt;
  }
  Eigen::Vector2d project(const Eigen::Vector3d& point_m) const {
    const Eigen::Vector3d p = homography() * Eigen::Vector3d(point_m.x(), point_m.y(), 1.0);
    return p.hnormalized();
  }
};

// Grey level printed at (x, y) of frame M (paper is white; dark features).
class SyntheticAlbedo {
 public:
  explicit SyntheticAlbedo(const metrology::Target& target) : spec_(target.spec()) {
    if (spec_.type == metrology::TargetType::AprilTag) {
      family_.reset(tag36h11_create());
      for (int k = 0; k < spec_.cols * spec_.rows; ++k) {
        image_u8_t* image = apriltag_to_image(family_.get(), spec_.first_id + k);
        std::vector<unsigned char> cells(image->width * image->height);
        for (int y = 0; y < image->height; ++y)
          for (int x = 0; x < image->width; ++x) cells[y * image->width + x] = image->buf[y * image->stride + x];
        total_ = image->width;
        bitmaps_.push_back(std::move(cells));
        // libapriltag exports no image_u8_destroy; this is what it does.
        std::free(image->buf);
        std::free(image);
      }
    }
  }
  // Fraction of ink at (x, y): 1 dark, 0 paper.
  double ink(double x, double y) const {
    using metrology::TargetType;
    switch (spec_.type) {
      case TargetType::Chessboard: {
        const double s = spec_.square_size_m;
        if (x < -s || y < -s || x > spec_.cols * s || y > spec_.rows * s) return 0.0;
        const long i = static_cast<long>(std::floor(x / s));
        const long j = static_cast<long>(std::floor(y / s));
        return ((i + j) % 2 == 0) ? 1.0 : 0.0;  // the square (-1, -1) is dark
      }
      case TargetType::Circles:
      case TargetType::AsymmetricCircles: {
        const double s = spec_.spacing_m;
        const double r2 = 0.25 * spec_.diameter_m * spec_.diameter_m;
        const long row = std::lround(y / s);
        for (long rr = row - 1; rr <= row + 1; ++rr) {
          if (rr < 0 || rr >= spec_.rows) continue;
          const double offset = spec_.type == TargetType::Circles ? 0.0 : static_cast<double>(rr % 2);
          const double pitch = spec_.type == TargetType::Circles ? 1.0 : 2.0;
          const long col = std::lround((x / s - offset) / pitch);
          for (long cc = col - 1; cc <= col + 1; ++cc) {
            if (cc < 0 || cc >= spec_.cols) continue;
            const double dx = x - (pitch * cc + offset) * s, dy = y - rr * s;
            if (dx * dx + dy * dy <= r2) return 1.0;
          }
        }
        return 0.0;
      }
      case TargetType::AprilTag: {
        const double pitch = spec_.tag_spacing_m;
        const long c = static_cast<long>(std::floor(x / pitch)), r = static_cast<long>(std::floor(y / pitch));
        if (c < 0 || r < 0 || c >= spec_.cols || r >= spec_.rows) return 0.0;
        const double cell = spec_.tag_size_m / family_->width_at_border;
        const int border = (total_ - family_->width_at_border) / 2;
        const double lx = (x - c * pitch) / cell + border, ly = (y - r * pitch) / cell + border;
        const int ix = static_cast<int>(std::floor(lx)), iy = static_cast<int>(std::floor(ly));
        if (ix < 0 || iy < 0 || ix >= total_ || iy >= total_) return 0.0;
        return bitmaps_[r * spec_.cols + c][iy * total_ + ix] < 128 ? 1.0 : 0.0;
      }
      case TargetType::Charuco:  // rendered by datasets' TargetAlbedo
      case TargetType::ArucoGrid:
        break;
    }
    return 0.0;
  }

 private:
  struct FamilyDeleter {
    void operator()(apriltag_family_t* family) const { tag36h11_destroy(family); }
  };
  metrology::TargetSpec spec_;
  std::unique_ptr<apriltag_family_t, FamilyDeleter> family_;
  std::vector<std::vector<unsigned char>> bitmaps_;
  int total_ = 0;
};

inline cv::Mat renderSynthetic(const metrology::Target& target, const SyntheticView& view) {
  const SyntheticAlbedo albedo(target);
  const int s = view.supersample;
  const Eigen::Matrix3d inverse = view.homography().inverse();
  cv::Mat fine(view.height * s, view.width * s, CV_32FC1);
  for (int y = 0; y < fine.rows; ++y) {
    for (int x = 0; x < fine.cols; ++x) {
      // Centre of the fine pixel in coarse pixel coordinates (OpenCV convention).
      const Eigen::Vector3d pixel((x + 0.5) / s - 0.5, (y + 0.5) / s - 0.5, 1.0);
      const Eigen::Vector3d plane = inverse * pixel;
      const double ink = albedo.ink(plane.x() / plane.z(), plane.y() / plane.z());
      fine.at<float>(y, x) = static_cast<float>(view.light + ink * (view.dark - view.light));
    }
  }
  cv::Mat coarse;
  cv::resize(fine, coarse, cv::Size(view.width, view.height), 0, 0, cv::INTER_AREA);
  if (view.blur_sigma_px > 0) cv::GaussianBlur(coarse, coarse, cv::Size(0, 0), view.blur_sigma_px);
  std::mt19937 random(view.seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(view.noise_sigma));
  for (int y = 0; y < coarse.rows; ++y)
    for (int x = 0; x < coarse.cols; ++x) coarse.at<float>(y, x) += noise(random);
  cv::Mat gray;
  coarse.convertTo(gray, CV_8UC1);
  return gray;
}

// A view of the target's centre from `distance_m`, tilted by (tilt_x, tilt_y) rad and
// turned by `roll` rad about the optical axis.
inline Eigen::Isometry3d lookAtTarget(const metrology::Target& target, double distance_m, double tilt_x, double tilt_y,
                                      double roll, const Eigen::Vector2d& offset_m = Eigen::Vector2d::Zero()) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : target.points()) centre += p;
  centre /= static_cast<double>(target.points().size());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(offset_m.x(), offset_m.y(), distance_m) - pose.linear() * centre;
  return pose;
}

}  // namespace mire::test
