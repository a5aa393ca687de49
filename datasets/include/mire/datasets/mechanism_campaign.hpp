#pragma once
// Exact-model simulated campaigns for every registered mechanism: a true geometry (nominal
// perturbed by 1 mm / 0.5° on its free parameters), true mountings, the protocol poses
// (doc/mechanisms.md) and measured cTm with noise 0.2 mm / 0.03° and its covariance.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

#include <Eigen/Geometry>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace mire::datasets {

using namespace mire::mechanism;

constexpr double kCampaignDeg = support::kPi / 180.0;

inline Eigen::Isometry3d makeTransform(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (rotation_vector.norm() > 0)
    T.linear() = Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// The translating protocol's positions at `scale`: 27 on a 300 × 300 × 150 mm grid (scale 1)
// around the reference pose.
inline std::vector<Eigen::Vector3d> translationGrid(const Eigen::VectorXd& reference_pose, double scale) {
  std::vector<Eigen::Vector3d> grid;
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz)
        grid.emplace_back(0.15 * scale * ix, 0.15 * scale * iy, reference_pose[2] + 0.075 * scale * iz);
  return grid;
}

// The largest scale (0.05 steps up to 2) at which a translating platform reaches the whole grid
// 1.25 times as large, within its strokes.
inline double translationReach(const Mechanism& mechanism, const Eigen::VectorXd& g, const Eigen::VectorXd& ref) {
  double reach = 0.0;
  for (int step = 1; step <= 40; ++step) {
    const double scale = 0.05 * step;
    for (const Eigen::Vector3d& t : translationGrid(ref, 1.25 * scale)) {
      Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
      bTe.translation() = t;
      const IkmResult ikm = mechanism.inverseKinematics(g, bTe);
      if (!ikm.reachable() || !ikm.withinStroke()) return reach;
    }
    reach = scale;
  }
  return reach;
}

// Protocol poses bTe at `size` (protocolScale()): H4 27 positions × 3 angles; Delta 27 positions on
// a 300×300×150 mm grid around its reference pose (z = −0.65 m for the built-in one); Gough–Stewart
// 27 positions (±40 mm, ±30 mm in z) × 3 orientations.
inline std::vector<Eigen::Isometry3d> protocolPosesAt(MotionType motion, const Eigen::VectorXd& ref, double size) {
  std::vector<Eigen::Isometry3d> out;
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz) {
        if (motion == MotionType::Translation) {
          out.push_back(makeTransform(Eigen::Vector3d::Zero(),
                                      Eigen::Vector3d(0.15 * size * ix, 0.15 * size * iy, ref[2] + 0.075 * size * iz)));
          continue;
        }
        for (int k = -1; k <= 1; ++k) {
          if (motion == MotionType::Schoenflies) {
            out.push_back(makeTransform(Eigen::Vector3d(0, 0, 20 * kCampaignDeg * k),
                                        Eigen::Vector3d(ref[0] + 0.1 * ix, ref[1] + 0.1 * iy, ref[2] + 0.075 * iz)));
          } else {
            // A different tilt axis per position, ±6° plus a yaw; scaled with the home height for a
            // platform of another size than the built-in hexapod's (0.40 m).
            const double a = 2.1 * (ix + 3 * iy + 9 * iz);
            const Eigen::Vector3d axis(std::cos(a), std::sin(a), 0.5 * k);
            out.push_back(makeTransform(
                size * (6 * kCampaignDeg * k * axis.normalized() + Eigen::Vector3d(0, 0, 4 * kCampaignDeg * ix * k)),
                Eigen::Vector3d(ref[0] + 0.04 * size * ix, ref[1] + 0.04 * size * iy, ref[2] + 0.03 * size * iz)));
          }
        }
      }
  return out;
}

// The largest of `size`, size − 0.05, … at which every protocol pose is reachable and within the
// joints' strokes (a description's `stroke`); `size` itself when none is.
inline double fittingProtocolSize(const Mechanism& mechanism, const Eigen::VectorXd& g,
                                  const Eigen::VectorXd& reference_pose, double size) {
  const auto within = [&](double at) {
    for (const Eigen::Isometry3d& bTe : protocolPosesAt(mechanism.motionType(), reference_pose, at)) {
      const IkmResult ikm = mechanism.inverseKinematics(g, bTe);
      if (!ikm.reachable() || !ikm.withinStroke()) return false;
    }
    return true;
  };
  for (double at = size; at > 0.025; at -= 0.05)
    if (within(at)) return at;
  return size;  // not even a small protocol fits: the campaign names the pose at fault
}

// The protocol's size relative to the built-in robots', made smaller (fittingProtocolSize) until
// every pose is within the joints' strokes: a 6-DoF platform's with its home height up to the
// built-in hexapod's 0.40 m; a translating platform's with the depth of its home below the base
// (0.65 m for the built-in Delta), but at least 0.4 of what it reaches (translationReach, at most
// 2: the built-in Delta keeps its depth; a linear delta's base frame sits on its bed, so its
// home's depth says nothing of its size); 1 for the H4.
inline double protocolScale(const Mechanism& mechanism, const Eigen::VectorXd& g, const Eigen::VectorXd& reference_pose) {
  switch (mechanism.motionType()) {
    case MotionType::Translation: {
      const double depth = std::abs(reference_pose[2]) / 0.65;
      const double reach = translationReach(mechanism, g, reference_pose);
      return fittingProtocolSize(mechanism, g, reference_pose, std::max(depth, 0.4 * reach));
    }
    case MotionType::Spatial:
      return fittingProtocolSize(mechanism, g, reference_pose, std::min(1.0, std::abs(reference_pose[2]) / 0.40));
    default:
      return 1.0;
  }
}

// Protocol poses bTe (protocolPosesAt()), robots of other sizes scaled by protocolScale().
inline std::vector<Eigen::Isometry3d> protocolPoses(const Mechanism& mechanism, const Eigen::VectorXd& g) {
  const Eigen::VectorXd ref = mechanism.referencePose(g);
  return protocolPosesAt(mechanism.motionType(), ref, protocolScale(mechanism, g, ref));
}

// `metre` / `radian` × U(−1, 1) on every free parameter (reproducible for a seed).
inline ParameterSet perturbedBy(const ParameterSet& nominal, unsigned seed, double metre, double radian) {
  ParameterSet truth = nominal;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i].fixed) continue;
    truth.setValue(truth[i].name, truth[i].value + (truth[i].unit == Unit::Radian ? radian : metre) * u(rng));
  }
  return truth;
}

// 1 mm / 0.5° on every free parameter.
inline ParameterSet perturbed(const ParameterSet& nominal, unsigned seed) {
  return perturbedBy(nominal, seed, 1e-3, 0.5 * kCampaignDeg);
}

// The camera and target mountings (bTc, mTe) of the simulated campaigns: a hexapod's camera above
// looking down, the others' below looking up; generic rotations, so that no parameter is
// accidentally aligned with an axis.
inline std::pair<Eigen::Isometry3d, Eigen::Isometry3d> campaignMountings(const Mechanism& m) {
  const bool up = m.motionType() == MotionType::Spatial;
  const Eigen::Isometry3d bTc = up ? makeTransform(Eigen::Vector3d(3.1, 0.1, 0.2), Eigen::Vector3d(0.03, -0.02, 1.3))
                                   : makeTransform(Eigen::Vector3d(0.05, -0.04, 0.3), Eigen::Vector3d(0.03, -0.02, -1.9));
  const Eigen::Isometry3d mTe = makeTransform(up ? Eigen::Vector3d(0.02, -0.03, 0.4) : Eigen::Vector3d(3.1, 0.05, 0.0),
                                              Eigen::Vector3d(0.012, -0.008, 0.005));
  return {bTc, mTe};
}

struct Campaign {
  RegisteredModel model;
  ParameterSet truth;
  Eigen::Isometry3d bTc, mTe;
  std::vector<PoseObservation> poses;
  std::vector<Eigen::Isometry3d> bTe;  // true effector poses
};

// A robot of `model` with the geometry `truth` measured at the protocol poses. `extra` random
// poses inside the protocol volume are appended (held-out checks); with `count` > 0 the campaign
// has `count` random poses instead of the protocol.
inline Campaign simulateCampaign(const RegisteredModel& model, const ParameterSet& truth, unsigned seed,
                                 double noise_t = 0.2e-3, double noise_r = 0.03 * kCampaignDeg, int extra = 0,
                                 int count = 0) {
  Campaign c;
  c.model = model;
  c.truth = truth;
  const Mechanism& m = *c.model.mechanism;
  std::tie(c.bTc, c.mTe) = campaignMountings(m);
  std::mt19937 rng(seed + 1000);
  std::normal_distribution<double> normal;
  PoseCovariance cov = PoseCovariance::Zero();
  cov.diagonal() << noise_t * noise_t, noise_t * noise_t, noise_t * noise_t, noise_r * noise_r, noise_r * noise_r,
      noise_r * noise_r;
  c.bTe = protocolPoses(m, c.truth.values());
  {
    // Random poses drawn inside the protocol's box of positions and orientations.
    std::vector<Eigen::Isometry3d> grid = c.bTe;
    std::mt19937 draw(seed + 2000);
    std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
    std::uniform_real_distribution<double> w(0.0, 1.0);
    const auto randomPose = [&] {
      const Eigen::Isometry3d& a = grid[pick(draw)];
      const Eigen::Isometry3d& b = grid[pick(draw)];
      const double s = w(draw);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Eigen::Quaterniond(a.linear()).slerp(s, Eigen::Quaterniond(b.linear())).toRotationMatrix();
      T.translation() = (1 - s) * a.translation() + s * b.translation();
      return T;
    };
    if (count > 0) {
      c.bTe.clear();
      for (int k = 0; k < count; ++k) c.bTe.push_back(randomPose());
    }
    for (int k = 0; k < extra; ++k) c.bTe.push_back(randomPose());
  }
  for (const Eigen::Isometry3d& bTe : c.bTe) {
    PoseObservation p;
    p.id = std::to_string(c.poses.size() + 1);
    const IkmResult ikm = m.inverseKinematics(c.truth.values(), bTe);
    // The protocol stays inside the joints' strokes (a simulator never drives past an end stop).
    if (!ikm.reachable() || !ikm.withinStroke())
      throw std::logic_error(m.name() + " campaign: pose " + std::to_string(c.poses.size() + 1) +
                             " is unreachable or outside the joints' strokes");
    p.joints = ikm.joints;
    p.cTm = toPoseVector(c.bTc.inverse() * bTe * c.mTe.inverse());
    for (int k = 0; k < 3; ++k) p.cTm[k] += noise_t * normal(rng);
    for (int k = 3; k < 6; ++k) p.cTm[k] += noise_r * normal(rng);
    if (noise_t > 0) p.covariance = cov;
    c.poses.push_back(p);
  }
  return c;
}

// A robot of `model`: its nominal geometry perturbed by 1 mm / 0.5° (perturbed()).
inline Campaign simulateCampaign(const RegisteredModel& model, unsigned seed, double noise_t = 0.2e-3,
                                 double noise_r = 0.03 * kCampaignDeg, int extra = 0, int count = 0) {
  return simulateCampaign(model, perturbed(model.nominal, seed), seed, noise_t, noise_r, extra, count);
}

// The registered model `name` at its built-in nominal geometry.
inline Campaign simulateCampaign(const std::string& name, unsigned seed, double noise_t = 0.2e-3,
                                 double noise_r = 0.03 * kCampaignDeg, int extra = 0, int count = 0) {
  return simulateCampaign(makeRegisteredModel(name), seed, noise_t, noise_r, extra, count);
}

// Writes poses [first, first + count) as poses.csv (σ columns from the noise) and joints.csv
// (the mechanism's q<i>_rad / q<i>_m columns) in `dir`, under the given file names.
inline void writeCampaignFiles(const Campaign& c, const std::filesystem::path& dir, std::size_t first,
                               std::size_t count, const std::string& poses_name = "poses.csv",
                               const std::string& joints_name = "joints.csv", double noise_t = 0.2e-3,
                               double noise_r = 0.03 * kCampaignDeg) {
  std::ostringstream poses;
  poses << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,"
           "sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  std::vector<std::string> ids;
  std::vector<Eigen::VectorXd> joints;
  for (std::size_t j = first; j < first + count && j < c.poses.size(); ++j) {
    const PoseObservation& p = c.poses[j];
    poses << p.id << ",10,10";
    for (int k = 0; k < 6; ++k) poses << ',' << support::formatNumber(p.cTm[k]);
    for (int k = 0; k < 3; ++k) poses << ',' << support::formatNumber(noise_t * 1e3);
    for (int k = 0; k < 3; ++k) poses << ',' << support::formatNumber(noise_r / kCampaignDeg);
    poses << ",0.1\n";
    ids.push_back(p.id);
    joints.push_back(p.joints);
  }
  support::writeFileAtomically(dir / poses_name, poses.str());
  writeJointsCsv(dir / joints_name, ids, joints, c.model.mechanism->jointColumnNames());
}

}  // namespace mire::datasets
