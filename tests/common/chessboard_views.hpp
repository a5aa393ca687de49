#pragma once
// The 9 × 6 chessboard of 30 mm squares that the measure and averaging tests look at, and a view
// of it: tilted 0.2 rad about x, turned about z, its centre at (x, y, z) in the camera frame.
#include <Eigen/Geometry>

#include <cmath>

#include "mire/metrology/target.hpp"

namespace mire::test {

// A chessboard of cols × rows inner corners and squares of `square_m` metres.
inline metrology::Target chessboard(int cols, int rows, double square_m) {
  metrology::TargetSpec spec;
  spec.cols = cols;
  spec.rows = rows;
  spec.square_size_m = square_m;
  return metrology::Target(spec);
}

inline metrology::Target chessboard9x6() { return chessboard(9, 6, 0.03); }

inline Eigen::Isometry3d tiltedBoardPose(double x, double y, double z, double angle_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(angle_deg * M_PI / 180, Eigen::Vector3d::UnitZ()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, z) - pose.linear() * Eigen::Vector3d(0.12, 0.075, 0);
  return pose;
}

}  // namespace mire::test
