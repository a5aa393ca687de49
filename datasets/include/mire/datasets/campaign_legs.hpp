#pragma once
// A campaign's legs seen as rods (doc/legs.md; doc/simulation.md, "Legs as rods"): the true robot's
// leg segments, the rods the renderer draws along them, and the files written beside the images:
// legs.yaml (what `mire measure --legs` reads, doc/file-formats.md "legs.yaml") and, for scoring,
// truth/legs.csv (the true axes in the camera frame, doc/file-formats.md "legs.csv").
// The hexapod and the Delta, camera fixed on the base (the paper's mounting).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/datasets/render.hpp"
#include "mire/mechanism/mechanism.hpp"

namespace mire::datasets {

// The rods' radius of the demo and of `mire simulate campaign --legs` by default [m].
constexpr double kReferenceLegRadiusM = 8e-3;

// Whether a campaign of `mechanism` (a family of the table or a description file) can draw its
// legs: the hexapod and the Delta.
bool campaignDrawsLegs(const std::string& mechanism);

// The model of the table whose nominal geometry and Mechanism::legSegments predict the legs of
// the robot's family: `gough-stewart`, `delta`.
std::string legsModel(const TrueRobot& robot);

// The true robot's legs at pose X, in the base frame, legCount() of legsModel() in joint order:
// hexapod: base joint centre (its eccentricity included) → platform joint; Delta: forearm, the
// elbow → the plate joint, each leg's effective pivot and plate joint moved out by the nominal
// plate radius r along the pivot's azimuth (only R − r enters the IKM; the joints follow the
// plate centre, so the plate's tilt does not move them). Throws std::invalid_argument for another
// robot, std::runtime_error at an unreachable pose.
std::vector<mechanism::LegSegment> trueLegSegments(const TrueRobot& robot, const Eigen::VectorXd& X);

// The rods of radius `radius_m` along trueLegSegments(robot, X), in the camera frame of bTc.
std::vector<Rod> legRods(const TrueRobot& robot, const Eigen::VectorXd& X, const Eigen::Isometry3d& bTc, double radius_m);

// The camera placement as a user measures it with a ruler: bTc moved by 5 mm and turned by 1°,
// in directions drawn from `seed`.
Eigen::Isometry3d rulerBaseTCamera(const Eigen::Isometry3d& bTc, std::uint64_t seed);

// legs.yaml: model, radius_mm, base_T_camera (t_mm, r_deg: rotation vector in degrees), search_px.
std::string legsYaml(const std::string& model, double radius_m, const Eigen::Isometry3d& approximate_bTc, int search_px);

// truth/legs.csv: every leg at every pose, the covariance 1e-24 on its diagonal (exact; the
// format needs a positive definite matrix).
void writeTrueLegs(const std::filesystem::path& legs_csv, const TrueRobot& robot,
                   const std::vector<Eigen::VectorXd>& poses, const std::vector<std::string>& pose_ids,
                   const Eigen::Isometry3d& bTc);

}  // namespace mire::datasets
