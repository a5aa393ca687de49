#include "mire/datasets/mechanism_image_campaign.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/datasets/campaign_images.hpp"
#include "mire/datasets/campaign_legs.hpp"
#include "mire/datasets/data_dir.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/yaml.hpp"

#include <algorithm>
#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace mire::datasets {
namespace fs = std::filesystem;

namespace {

// The simulated robot's defects (registry.hpp); throws std::invalid_argument naming an unknown
// mechanism. A description file has its own (makeDefectiveDescribed).
SimulatedDefects defectsOf(const std::string& mechanism) { return mechanismFamily(mechanism).defects; }

// Where the camera looks from: below the platform (the H4's and the Delta's: the legs hang from
// above) or above it (the hexapod's), turned by `yaw_deg` about z_B, and the platform's home it
// is placed around. A described robot is seen from the side away from its legs' base points.
struct Stage {
  bool below = false;
  Eigen::Vector3d camera = Eigen::Vector3d::Zero();  // the camera's position in B
  bool translates = false;
  double yaw_deg = 0.0;
};

Stage stageOf(const std::string& mechanism) {
  if (!isDescriptionFile(mechanism)) {
    switch (defectsOf(mechanism)) {
      case SimulatedDefects::H4Parallelograms:  // ≈0.8 m below the target (doc/mechanisms.md)
        return {true, Eigen::Vector3d(0.03, -0.02, -1.46), false, 25.0};
      case SimulatedDefects::PlateTilt:
        return {true, Eigen::Vector3d(0.03, -0.02, -1.33), true, -12.0};
      default:
        return {false, Eigen::Vector3d(0.02, -0.01, 0.85), false, 25.0};
    }
  }
  const MechanismDescription description = readMechanismDescription(mechanism);
  const RegisteredModel model = makeDescribedModel(description);
  const Mechanism& m = *model.mechanism;
  const Eigen::Vector3d home = m.poseToTransform(m.referencePose(model.nominal.values())).translation();
  double base_z = 0.0;
  for (const LegDescription& leg : description.legs)
    base_z += leg.base.z() / static_cast<double>(description.legs.size());
  const bool below = base_z > home.z(), translates = m.motionType() == MotionType::Translation;
  const double distance = translates ? 0.68 : 0.45;  // as the built-in Delta's and hexapod's
  return {below, home + (below ? Eigen::Vector3d(0.03, -0.02, -distance) : Eigen::Vector3d(0.02, -0.01, distance)),
          translates, below ? -12.0 : 25.0};
}

Eigen::Isometry3d isometry(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = rotation;
  transform.translation() = translation;
  return transform;
}

SimulationSpec campaignSimulation(const MechanismImageCampaignSpec& spec, const calibration::Camera& camera,
                                  const metrology::Target& target, const MechanismImageCampaign& campaign) {
  SimulationSpec simulation = campaignSimulationBase(spec, camera, target);
  for (std::size_t i = 0; i < campaign.bTe.size(); ++i) {
    SimulatedPose pose;
    pose.id = campaign.pose_ids[i];
    pose.camera_T_target = campaign.trueCameraTMarker(pose.id);
    // Pose coordinates (x, y, z, θ): the simulator's truth records them (simulation.hpp).
    pose.has_effector = campaign.commanded[i].size() == 4;
    if (pose.has_effector) pose.effector = campaign.commanded[i];
    if (spec.leg_radius_m) pose.rods = legRods(campaign.robot, campaign.commanded[i], campaign.bTc, *spec.leg_radius_m);
    simulation.poses.push_back(pose);
  }
  return simulation;
}

// Encoder readings of the true robot (its defects included) plus encoder noise: at the poses,
// then along the lines (one random stream).
void writeEncoderReadings(const MechanismImageCampaignSpec& spec, const MechanismImageCampaign& campaign) {
  const Mechanism& mechanism = campaign.robot.mechanism();
  const std::vector<Unit> units = mechanism.jointUnits();
  std::mt19937_64 rng(spec.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto read = [&](const Eigen::VectorXd& X, const std::string& where) {
    Eigen::VectorXd q = campaign.robot.joints(X);
    if (q.size() == 0) throw std::runtime_error("simulated " + spec.mechanism + ": " + where + " is unreachable");
    for (Eigen::Index k = 0; k < q.size(); ++k)
      q[k] += (units[static_cast<std::size_t>(k)] == Unit::Radian ? spec.encoder_noise_rad : spec.encoder_noise_m) *
              normal(rng);
    return q;
  };
  std::vector<Eigen::VectorXd> joints;
  for (std::size_t i = 0; i < campaign.commanded.size(); ++i)
    joints.push_back(read(campaign.commanded[i], "pose " + campaign.pose_ids[i]));
  const std::vector<std::string> columns = mechanism.jointColumnNames();
  mechanism::writeJointsCsv(campaign.joints_file(), campaign.pose_ids, joints, columns);

  std::vector<mechanism::LineRecord> lines;
  for (std::size_t line = 0; line < campaign.lines.size(); ++line) {
    mechanism::LineRecord record{"line" + std::to_string(line + 1), {}};
    for (const Eigen::VectorXd& X : campaign.lines[line]) record.joints.push_back(read(X, record.line_id));
    lines.push_back(std::move(record));
  }
  mechanism::writeLinesCsv(campaign.lines_file(), lines, columns);
}

// The true robot: the H4's legs and nacelle (h4_true_robot.hpp); the others' geometry in the
// `delta-legs` / `gough-stewart` parameters and their defects; and the mountings.
std::string truthYaml(const MechanismImageCampaign& campaign) {
  const TrueRobot& robot = campaign.robot;
  if (robot.h4)
    return trueGeometryYaml(robot.h4->geometry()) + isometryYaml("bTc", campaign.bTc) + isometryYaml("mTe", campaign.mTe);
  std::ostringstream out;
  out << "model: " << robot.geometry_model.name << "\ngeometry:\n";
  for (std::size_t i = 0; i < robot.geometry.size(); ++i)
    out << "  " << robot.geometry[i].name << ": " << support::formatYamlNumber(robot.geometry[i].value) << "\n";
  out << "plate_tilt_rad_per_m: " << support::formatYamlNumber(robot.tilt_per_m) << "\n";
  out << "eccentricity_m: " << support::formatYamlNumber(robot.eccentricity) << "\nencoder_gain: [";
  for (std::size_t i = 0; i < robot.encoder_gain.size(); ++i)
    out << (i ? ", " : "") << support::formatYamlNumber(robot.encoder_gain[i]);
  out << "]\n";
  if (!robot.encoder_curvature.empty()) {
    out << "encoder_curvature: [";
    for (std::size_t i = 0; i < robot.encoder_curvature.size(); ++i)
      out << (i ? ", " : "") << support::formatYamlNumber(robot.encoder_curvature[i]);
    out << "]  # per m or per rad: q_read = q + c (q - q_home)^2\n";
  }
  if (campaign.camera_on_effector) {
    out << "mounting: camera-on-effector\n" << isometryYaml("eTc", campaign.eTc) << isometryYaml("bTm", campaign.bTm);
  } else {
    out << isometryYaml("bTc", campaign.bTc) << isometryYaml("mTe", campaign.mTe);
  }
  return out.str();
}

}  // namespace

// The true robot of the spec's draw, with or without its unmodelled defects.
TrueRobot trueRobotOf(const MechanismImageCampaignSpec& spec) {
  const auto seed = static_cast<unsigned>(spec.robot_seed.value_or(spec.seed));
  if (isDescriptionFile(spec.mechanism))
    return makeDefectiveDescribed(makeRegisteredModel(spec.mechanism), seed, spec.unmodelled_defects);
  switch (defectsOf(spec.mechanism)) {
    case SimulatedDefects::H4Parallelograms: {
      H4ErrorSizes sizes = spec.h4_errors;
      if (!spec.unmodelled_defects)
        sizes.leg_length_m = sizes.pivot_height_m = sizes.axis_tilt_rad = sizes.bar_mismatch_m = 0.0;
      const MechanismImageCampaignSpec defaults = MechanismImageCampaignSpec::reference(spec.mechanism);
      const metrology::Target target =
          metrology::Target::fromFile(spec.target_file.empty() ? defaults.target_file : spec.target_file);
      return makeTrueH4(sizes, spec.robot_seed.value_or(spec.seed),
                        spec.base_T_camera.value_or(mechanismBaseTCamera(spec.mechanism)),
                        mechanismMarkerTEffector(spec.mechanism, target));
    }
    case SimulatedDefects::PlateTilt:
      return spec.unmodelled_defects ? makeDefectiveDelta(seed, spec.delta_legs_differ)
                                     : makeDefectiveDelta(seed, spec.delta_legs_differ, 0.0);
    default:
      return spec.unmodelled_defects ? makeDefectiveHexapod(seed) : makeDefectiveHexapod(seed, 0.0, 0.0);
  }
}

MechanismImageCampaignSpec MechanismImageCampaignSpec::reference(const std::string& mechanism) {
  stageOf(mechanism);
  MechanismImageCampaignSpec spec;
  spec.mechanism = mechanism;
  spec.camera_file = specPath("reference_camera.yaml");
  spec.target_file = specPath("target_h4.yaml");
  // A real 3.8 mm lens at f/4 is slightly soft, and an 8-bit sensor is noisy (paper §5).
  spec.render.blur_sigma_px = 0.6;
  spec.noise.gaussian_sigma = 1.5;
  spec.noise.shot_noise_gain = 20.0;
  if (!isDescriptionFile(mechanism) && defectsOf(mechanism) == SimulatedDefects::H4Parallelograms) {
    // The paper's robot was far from its nominal model: square sides 4–7 mm off and V3 1.8 mm
    // before identification, a 25 mm / 1° change of base frame after (paper §6.4). Errors of a
    // few millimetres and degrees reproduce those magnitudes; the unmodelled defects keep their
    // defaults (≈0.1° nacelle tilt, as measured on the real H4).
    spec.h4_errors.length_m = 5e-3;
    spec.h4_errors.angle_rad = 2.0 * kH4Degree;
    spec.h4_errors.joint_offset_rad = 5.0 * kH4Degree;
    spec.line_points = 20;
  }
  return spec;
}

// H4: the camera ≈0.8 m below the target looking up (z_C ≈ z_B), turned by ψ_BC = 25° with a
// 1–2° tilt like a real bracket (doc/mechanisms.md, "The simulated true H4").
// Delta: the camera 0.68 m below the workspace centre (z = −0.65 m) looking up, turned so that
// the board's edges run nearly along the image's (2°): the 300 × 300 × 150 mm protocol then
// keeps the whole board in view with 18–23 px squares (a board turned by 35° at 0.9 m was
// not found by the chessboard detector). Hexapod: 0.45 m above the platform's home looking
// down (its protocol spans ±40 mm). Both slightly tilted. A described robot: as the built-in
// robot of its platform, from the side away from its legs.
Eigen::Isometry3d mechanismBaseTCamera(const std::string& mechanism) {
  const Stage stage = stageOf(mechanism);
  const double degree = kCampaignDeg;
  const double yaw = stage.yaw_deg;
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(yaw * degree, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(1.5 * degree, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(-1.0 * degree, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  if (stage.below) return isometry(tilt, stage.camera);
  const Eigen::Matrix3d down = tilt * Eigen::AngleAxisd(180.0 * degree, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return isometry(down, stage.camera);
}

// The board centred on the effector, 40 mm from it along the board's normal, facing the camera
// (the board's z axis points away from the camera, OpenCV's convention).
Eigen::Isometry3d mechanismMarkerTEffector(const std::string& mechanism, const metrology::Target& target) {
  const bool below = stageOf(mechanism).below;
  const Eigen::Vector3d centroid = targetCentroid(target);
  Eigen::Matrix3d rotation = Eigen::AngleAxisd(10.0 * kCampaignDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (!below) rotation = Eigen::AngleAxisd(kCampaignDeg * 180.0, Eigen::Vector3d::UnitX()) * rotation;
  return isometry(rotation, Eigen::Vector3d(centroid.x(), centroid.y(), 0.04));
}

Eigen::Isometry3d MechanismImageCampaign::trueCameraTMarker(const std::string& pose_id) const {
  const auto index = std::find(pose_ids.begin(), pose_ids.end(), pose_id) - pose_ids.begin();
  const Eigen::Isometry3d& effector = bTe.at(static_cast<std::size_t>(index));
  if (camera_on_effector) return eTc.inverse() * effector.inverse() * bTm;
  return bTc.inverse() * effector * mTe.inverse();
}

std::pair<Eigen::Isometry3d, Eigen::Isometry3d> eyeInHandMounting(const Eigen::Isometry3d& bTc,
                                                                  const Eigen::Isometry3d& mTe,
                                                                  const Eigen::Isometry3d& bTe_home) {
  const Eigen::Isometry3d cTm_home = bTc.inverse() * bTe_home * mTe.inverse();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(180.0 * kCampaignDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d eRc = bTe_home.linear().transpose() * turn * bTc.linear();
  const Eigen::Isometry3d eTc = isometry(eRc, eRc * Eigen::Vector3d(0.02, -0.015, -0.03));
  return {eTc, bTe_home * eTc * cTm_home};
}

// Stages: the true robot and its protocol, the view check, the images, the encoder readings,
// the truth.
MechanismImageCampaign generateMechanismImageCampaign(const MechanismImageCampaignSpec& spec, const fs::path& directory,
                                                      const ProgressCallback& progress) {
  const MechanismImageCampaignSpec defaults = MechanismImageCampaignSpec::reference(spec.mechanism);
  const calibration::Camera camera =
      calibration::readCamera(spec.camera_file.empty() ? defaults.camera_file : spec.camera_file);
  const metrology::Target target =
      metrology::Target::fromFile(spec.target_file.empty() ? defaults.target_file : spec.target_file);
  MechanismImageCampaign campaign{trueRobotOf(spec),
                                  camera,
                                  spec.base_T_camera.value_or(mechanismBaseTCamera(spec.mechanism)),
                                  mechanismMarkerTEffector(spec.mechanism, target),
                                  {},
                                  {},
                                  {},
                                  {},
                                  directory,
                                  false,
                                  Eigen::Isometry3d::Identity(),
                                  Eigen::Isometry3d::Identity()};
  const Mechanism& mechanism = campaign.robot.mechanism();
  if (spec.camera_on_effector && campaign.robot.h4)
    throw std::invalid_argument("simulated H4: its campaign has the camera fixed only");
  if (spec.leg_radius_m && (spec.camera_on_effector || !campaignDrawsLegs(spec.mechanism)))
    throw std::invalid_argument("simulated legs: the hexapod's and the Delta's, with the camera fixed, only");
  if (spec.camera_on_effector) {
    campaign.camera_on_effector = true;
    const Eigen::Isometry3d home = campaign.robot.effector(mechanism.referencePose(campaign.robot.geometry.values()));
    std::tie(campaign.eTc, campaign.bTm) = eyeInHandMounting(campaign.bTc, campaign.mTe, home);
  }
  for (const Eigen::VectorXd& X : protocolCoordinates(campaign.robot)) {
    campaign.commanded.push_back(X);
    campaign.bTe.push_back(campaign.robot.effector(X));
    campaign.pose_ids.push_back(campaignPoseId(campaign.pose_ids.size()));
  }
  campaign.lines = straightLinePoses(campaign.robot, spec.line_points);
  const SimulationSpec simulation = campaignSimulation(spec, camera, target, campaign);
  checkTargetInView(simulation, "simulated " + campaign.robot.geometry_model.name);

  fs::create_directories(directory);
  const fs::path truth_dir = directory / "truth";
  support::writeFileAtomically(campaign.target_file(), target.yamlString());
  renderCampaignImages(simulation, campaign.directory, truth_dir, progress);
  writeEncoderReadings(spec, campaign);
  support::writeFileAtomically(truth_dir / "robot.yaml", truthYaml(campaign));
  if (spec.leg_radius_m) {
    constexpr int kSearchPx = 25;
    support::writeFileAtomically(campaign.legs_file(), legsYaml(legsModel(campaign.robot), *spec.leg_radius_m,
                                                                rulerBaseTCamera(campaign.bTc, spec.seed), kSearchPx));
    writeTrueLegs(truth_dir / "legs.csv", campaign.robot, campaign.commanded, campaign.pose_ids, campaign.bTc);
  }
  return campaign;
}

}  // namespace mire::datasets
