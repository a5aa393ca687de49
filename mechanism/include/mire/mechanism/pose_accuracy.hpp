#pragma once
// ISO 9283 pose characteristics from measured attained poses (doc/accuracy.md): pose accuracy and
// repeatability per commanded position (§7.2.1 AP, §7.2.2 RP), distance accuracy and repeatability
// between positions (§7.4 AD, RD), and the straightness of straight-line motions (the paper's V3,
// §6.1). Poses only: the attained poses come from any measurement, with their covariance.
//
// Every figure carries the part of it that the measurement's own uncertainty explains: the
// first-order σ of the accuracy figures (what the measurement noise moves them by, against the
// figure computed from the true attained poses), and the figure a perfectly accurate and
// repeatable robot would show through the same measurement (noise only: mean and 95th percentile,
// drawn from the poses' covariances). A figure at or below that 95th percentile is not resolved
// by the measurement and carries a warning.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

// (x, y, z) [m] then the ISO 9283 orientation angles (a, b, c) [rad] about x, y, z:
// R = Rz(c)·Ry(b)·Rx(a).
using IsoPose = Eigen::Matrix<double, 6, 1>;
using IsoPoseCovariance = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d isoAngles(const Eigen::Matrix3d& rotation);
IsoPose isoPose(const Eigen::Isometry3d& transform);
// attained − commanded, the angle differences wrapped to (−π, π].
IsoPose isoDeviation(const Eigen::Isometry3d& commanded, const Eigen::Isometry3d& attained);

// The attained effector pose bTe = cTb⁻¹·cTm·eTm⁻¹ of a measured target pose, and the
// covariance of its isoPose() from cTm's (first order, central differences); zero without one.
struct AttainedPose {
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
  IsoPoseCovariance covariance = IsoPoseCovariance::Zero();
};
AttainedPose attainedPose(const Eigen::Isometry3d& cTb, const Eigen::Isometry3d& eTm, const PoseVector& cTm,
                          const std::optional<PoseCovariance>& cTm_covariance);

// One cycle at one commanded position (ISO 9283 §7.2: the j-th attained pose of position P).
struct AccuracySample {
  std::string id;        // pose id, in messages
  std::string position;  // the commanded position's name (ISO's P1..P5)
  Eigen::Isometry3d commanded = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d attained = Eigen::Isometry3d::Identity();
  IsoPoseCovariance covariance = IsoPoseCovariance::Zero();  // of isoPose(attained)
};

// A figure that a perfect robot shows through the measurement noise alone.
struct NoiseOnly {
  double mean = 0.0;
  double p95 = 0.0;
};

struct PositionAccuracy {
  std::string position;
  int cycles = 0;
  IsoPose commanded = IsoPose::Zero();
  IsoPose barycentre = IsoPose::Zero();  // commanded + mean deviation
  // §7.2.1: AP_p = |barycentre − commanded position|, AP_x/y/z its components, AP_a/b/c the mean
  // angle deviations.
  double ap_p = 0.0;
  Eigen::Vector3d ap_xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3d ap_abc = Eigen::Vector3d::Zero();
  double sigma_ap_p = 0.0;
  Eigen::Vector3d sigma_ap_xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_ap_abc = Eigen::Vector3d::Zero();
  NoiseOnly noise_ap_p;
  std::array<NoiseOnly, 3> noise_ap_abc;
  // §7.2.2: l_j = |attained_j − barycentre|, RP_l = l̄ + 3·S_l; RP_a/b/c = 3·S_a/b/c.
  double l_mean = 0.0, s_l = 0.0, rp_l = 0.0;
  Eigen::Vector3d s_abc = Eigen::Vector3d::Zero();
  Eigen::Vector3d rp_abc = Eigen::Vector3d::Zero();
  NoiseOnly noise_rp_l;
  std::array<NoiseOnly, 3> noise_rp_abc;
  std::vector<std::string> warnings;
};

// §7.4 between two positions, cycle j of one paired with cycle j of the other.
struct DistanceAccuracy {
  std::string from, to;
  int cycles = 0;
  double d_commanded = 0.0, d_mean = 0.0;
  double ad_p = 0.0, sigma_ad_p = 0.0;  // AD_p = D̄ − D_c
  double s_d = 0.0, rd = 0.0;           // RD = 3·S_D
  NoiseOnly noise_ad_p, noise_rd;
  std::vector<std::string> warnings;
};

// Straightness of the attained positions of one straight-line motion: RMS distance to their
// least-squares line (the paper's R, §6.1) and the largest distance.
struct LineStraightness {
  std::string line;
  int points = 0;
  double rms = 0.0, max = 0.0;
  // sqrt(rms² − noise-only mean²), 0 when the noise explains it all.
  double rms_beyond_noise = 0.0;
  NoiseOnly noise_rms, noise_max;
  std::vector<std::string> warnings;
};

struct AccuracyOptions {
  int noise_draws = 2000;  // Monte Carlo draws of the noise-only figures
  unsigned seed = 9283;    // reproducible reports
};

// Positions in their first-appearance order. Throws std::invalid_argument naming the position
// when it has fewer than 2 cycles, or when a sample's commanded pose differs from the position's
// first one by more than 1 µm / 1 µrad.
std::vector<PositionAccuracy> poseAccuracy(const std::vector<AccuracySample>& samples,
                                           const AccuracyOptions& options = {});
// Every pair of positions (first-appearance order), over the cycles both have.
std::vector<DistanceAccuracy> distanceAccuracy(const std::vector<AccuracySample>& samples,
                                               const AccuracyOptions& options = {});
// `covariances` may be empty (no noise-only part) or one per point (of the position, 3×3 block).
// Throws std::invalid_argument with fewer than 3 points.
LineStraightness lineStraightness(const std::string& line, const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<Eigen::Matrix3d>& covariances, const AccuracyOptions& options = {});

}  // namespace mire::mechanism
