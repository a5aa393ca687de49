#pragma once
// Hand-eye calibration of a robot that reports its own effector pose (doc/mechanisms.md,
// "Hand-eye calibration"): no kinematic model, only the reported poses bTe_j and the measured
// target poses cTm_j. Two mountings (doc/conventions.md):
//   camera on the effector:  cTm_j = eTc⁻¹ · bTe_j⁻¹ · bTm   (AX = XB; unknowns eTc, bTm)
//   camera fixed:            cTm_j = cTb · bTe_j · eTm        (AX = ZB; unknowns cTb, eTm)
// The two transforms are estimated jointly by least squares on both the camera's pose errors
// (whitened by each pose's 6×6 covariance) and the robot's (each reported pose is a nuisance
// pose with a Gaussian prior of the robot's σ: errors in variables), started from OpenCV's
// closed form. The covariance of the two transforms is the marginal of the Gauss-Newton
// covariance over the nuisance poses. The estimate is a function of the set of poses, not of
// their order.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/identifiability.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

enum class HandEyeMounting { CameraOnEffector, CameraFixed };

std::string handEyeMountingName(HandEyeMounting mounting);  // "camera-on-effector", "camera-fixed"
// Throws std::invalid_argument naming the accepted values.
HandEyeMounting parseHandEyeMounting(const std::string& text);

// The robot's pose error, per component (each of x, y, z): σ of the position [m] and of the
// orientation [rad] (a small rotation of the reported pose about each axis).
struct RobotPoseSigma {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};

// One row of robot_poses.csv (doc/file-formats.md): the reported bTe, and its σ when the row
// gives one.
struct RobotPoseRow {
  std::string id;
  PoseVector bTe = PoseVector::Zero();
  std::optional<RobotPoseSigma> sigma;
  int line = 0;
};
// Header pose_id,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad[,sigma_t_mm,sigma_r_deg] (extra columns
// allowed). Throws std::runtime_error naming path:line on a missing column, a duplicate id, a
// non-finite value or a σ that is not > 0.
std::vector<RobotPoseRow> readRobotPosesCsv(const std::filesystem::path& robot_poses_csv);

// One pose pair. Without a camera covariance the camera's errors are weighted like the robot's
// and the covariance is scaled by the residuals (HandEyeResult::sigma_from_residuals).
struct HandEyeObservation {
  std::string id;
  PoseVector bTe = PoseVector::Zero();  // reported by the robot
  RobotPoseSigma robot_sigma;           // > 0
  PoseVector cTm = PoseVector::Zero();  // measured
  std::optional<PoseCovariance> cTm_covariance;
};

struct HandEyeOptions {
  // A pose whose share of χ² exceeds this (χ² with 6 dof; 27.86 is its 1 − 10⁻⁴ quantile)
  // is an outlier: the worst one is removed and the fit repeated.
  double outlier_chi2 = 27.86;
  bool remove_outliers = true;
};

struct HandEyePoseScore {
  std::string id;
  double chi2 = 0.0;           // whitened squared residuals of the pose (camera + robot), scaled
  Eigen::Vector3d camera_t_m;  // measured − predicted cTm translation
  double camera_r_rad = 0.0;   // angle of measured vs predicted cTm rotation
  Eigen::Vector3d robot_t_m;   // estimated − reported bTe translation
  double robot_r_rad = 0.0;    // angle of estimated vs reported bTe rotation
};

struct HandEyeResult {
  HandEyeMounting mounting = HandEyeMounting::CameraOnEffector;
  // X = eTc and Z = bTm (camera on the effector), or X = cTb and Z = eTm (camera fixed).
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d Z = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_closed_form = Eigen::Isometry3d::Identity();  // OpenCV's start
  Eigen::Isometry3d Z_closed_form = Eigen::Isometry3d::Identity();
  std::string closed_form_method;
  ParameterSet parameters;     // tx_EC..rz_EC, tx_BM..rz_BM or tx_CB..rz_CB, tx_EM..rz_EM (SI)
  Eigen::MatrixXd covariance;  // 12×12 over `parameters`, SI
  Eigen::VectorXd sigma;       // sqrt of its diagonal
  double chi2 = 0.0;           // unscaled
  int dof = 0;
  double scale2 = 1.0;  // the covariance factor applied (1: the stated σ are kept)
  bool sigma_from_residuals = false;
  std::vector<HandEyePoseScore> poses;     // the poses kept, in input order
  std::vector<HandEyePoseScore> outliers;  // removed, in removal order (their score then)
  IdentifiabilityReport identifiability;   // of the 12 unknowns (nuisance poses marginalised)
  // Singular values (rad) of the robot's relative rotation axes ×angles, descending: a second
  // one near zero means rotations about one axis only.
  Eigen::Vector3d rotation_spread = Eigen::Vector3d::Zero();
  bool converged = false;
};

// Joint least squares (see the file comment). Throws std::invalid_argument when fewer than 3
// poses, a σ ≤ 0, repeated ids, or data that do not determine the transforms: the message names
// the unobservable combination (e.g. rotations about one axis leave the camera's position
// along it free) and the rotation axis.
HandEyeResult solveHandEye(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                           const HandEyeOptions& options = {});

// OpenCV's closed-form solutions, for the start and for comparison: cv::calibrateHandEye with
// `method` ∈ {"tsai", "park", "horaud", "andreff", "daniilidis"} (camera on the effector: X = eTc;
// camera fixed: X = cTb by inverted robot poses); Z from the mean of the per-pose Z.
// "shah" / "li": cv::calibrateRobotWorldHandEye.
struct HandEyeTransforms {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d Z = Eigen::Isometry3d::Identity();
};
HandEyeTransforms handEyeClosedForm(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                                    const std::string& method);

// ---- experiment design: which robot poses to visit (doc/mechanisms.md, "Hand-eye calibration") ----
// A guess of the two transforms and the noise expected at every pose.
struct HandEyeDesignModel {
  HandEyeMounting mounting = HandEyeMounting::CameraOnEffector;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d Z = Eigen::Isometry3d::Identity();
  RobotPoseSigma robot_sigma;
  PoseCovariance camera_covariance = PoseCovariance::Identity();  // of each cTm, (m, rad)
};

// The information (12×12, over handEyeParameterNames) one robot pose bTe brings, its nuisance
// pose marginalised: the poses' informations add, and the covariance of a set is the inverse
// of their sum (the solve's covariance with the stated σ).
Eigen::Matrix<double, 12, 12> handEyePoseInformation(const HandEyeDesignModel& model, const Eigen::Isometry3d& bTe);

struct HandEyePlan {
  std::vector<std::size_t> chosen;  // indices into the candidates, in choice order
  Eigen::MatrixXd covariance;       // 12×12 predicted for the chosen set
  Eigen::VectorXd sigma;            // its sqrt(diagonal)
};
// Greedy choice of `count` candidate poses minimising Σ σ²(eTc or cTb component) / σ_ref², with
// σ_ref the robot's σ (translation, rotation): each step adds the candidate that lowers it most.
// Throws std::invalid_argument when count < 3 or exceeds the candidates.
HandEyePlan planHandEye(const HandEyeDesignModel& model, const std::vector<Eigen::Isometry3d>& candidates,
                        std::size_t count);

// Parameter names of a mounting: {"tx_EC",...,"rz_EC","tx_BM",...,"rz_BM"} or the CB/EM ones.
std::vector<std::string> handEyeParameterNames(HandEyeMounting mounting);

// The predicted cTm of pose bTe given X and Z (the mounting's chain).
Eigen::Isometry3d handEyePredictedTarget(HandEyeMounting mounting, const Eigen::Isometry3d& X,
                                         const Eigen::Isometry3d& Z, const Eigen::Isometry3d& bTe);

}  // namespace mire::mechanism
