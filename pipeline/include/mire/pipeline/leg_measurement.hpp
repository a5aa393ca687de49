#pragma once
// `mire measure --legs`: every observable leg's axis at every pose, from one image folder per pose
// (doc/legs.md "Measuring a leg", doc/file-formats.md "legs.yaml"). The nominal model and the
// pose's joints predict where each leg's rod is (nominal FKM, then the approximate camera
// placement of legs.yaml); its contours are measured in every image and averaged.
#include "mire/calibration/camera_model.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/leg_observation.hpp"
#include "mire/metrology/leg_contours.hpp"

#include <Eigen/Geometry>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::pipeline {

// legs.yaml: the model whose legs are seen, the rods' radius and the camera's approximate place.
struct LegsSpec {
  std::string model;
  double radius_m = 0.0;
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();  // approximate, to predict the search
  double search_px = 25.0;
};

// Throws support::YamlError naming the file, line and key on a missing or unknown key or a value
// out of range (radius 0.1..500 mm, search 2..200 px), and std::invalid_argument naming the file
// and the model when the model is unknown or has no observable legs.
LegsSpec readLegsYaml(const std::filesystem::path& legs_yaml);

struct PoseLegs {
  std::string pose_id;
  std::vector<mechanism::LegObservation> legs;  // the legs measured, in leg order
  std::vector<std::string> problems;            // a leg not measured, or the whole pose: why
  int images = 0;
  std::vector<double> spread_ratios;  // per leg measured (metrology::LegAxis::spread_ratio)
};

// One entry per pose subfolder of `poses_dir`, in pose-id order (pose_id as the folder's name).
// A pose without a row in `joints`, whose FKM fails or whose images cannot be read has no leg and
// says why in `problems`; a leg seen in no image is left out, with the first image's reason.
// `debug_dir` (optional): the first image of each pose with the fitted contours and their edge
// points drawn, <pose_id>.png. Throws std::runtime_error when `poses_dir` holds no pose subfolder.
std::vector<PoseLegs> measureLegFolders(const calibration::Camera& camera, const LegsSpec& spec,
                                        const std::vector<mechanism::JointRow>& joints,
                                        const std::filesystem::path& poses_dir, int threads,
                                        const std::filesystem::path& debug_dir = {});

}  // namespace mire::pipeline
