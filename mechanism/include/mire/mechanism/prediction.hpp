#pragma once
// What an identified model predicts, with σ (doc/mechanisms.md "`mire fkm` and `mire ikm`"): from encoder
// readings the effector pose (FKM) in the base frame and the target pose in the camera frame
// cTm = cTb · bTe(FKM(q̄)) · eTm; from desired effector poses the joint commands (IKM).
// σ are propagated from the parameters' covariance by first-order (Jacobian) propagation;
// the Jacobians are central differences of the closed-form IKM (implicit-function theorem
// for the FKM: ∂X/∂ξg = −(∂q/∂X)⁻¹·∂q/∂ξg).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

// Geometry and the mounting in the full form (tx_CB..rz_CB, tx_EM..rz_EM, whatever form the
// identification used; tx_EC..rz_EC, tx_BM..rz_BM with the camera on the effector), with the
// covariance over `covariance_names` (free geometric parameters, tie leaders, then mounting
// names); other parameters have no variance.
struct PredictionModel {
  std::string model_name;
  std::shared_ptr<const Mechanism> mechanism;
  ParameterSet geometric;
  ExternalForm mounting_form = ExternalForm::Full;  // or ExternalForm::CameraOnEffector
  ParameterSet mounting;                            // ExternalParameterization(mounting_form).parameters() values
  std::vector<std::string> covariance_names;
  Eigen::MatrixXd covariance;  // SI; empty: no σ

  // The camera-fixed mounting; throw std::runtime_error with the camera on the effector.
  Eigen::Isometry3d cTb() const;
  Eigen::Isometry3d eTm() const;
};

// From an identification: geometry, mounting converted to the full form, the covariance
// mapped through that conversion (Jacobian by central differences).
PredictionModel predictionModelFrom(const std::string& model_name, const IdentificationResult& result);

// The side file of an identified parameter file (`<stem>_covariance.csv`): the prediction
// parameters (free geometric ones, then the 12 full-form mounting values, whatever form the
// identification used) with their values and full covariance. Header
// `name,value,<n1>,...,<nk>`, one row per name, SI units.
void writePredictionCovarianceCsv(const std::filesystem::path& path, const PredictionModel& model);
// Reads the side file into `model` (its geometric set and mechanism already set): mounting
// values, covariance names and matrix. Throws naming path:line on a bad file (unknown or
// repeated name, not symmetric, negative variance, non-finite value).
void readPredictionCovarianceCsv(const std::filesystem::path& path, PredictionModel& model);

// An identified parameter file (its `model:` key names the registry entry) and, when it
// exists, its side file (default support::covarianceSidePath()). `has_mounting` tells
// whether the camera-frame prediction is possible (full-form keys in the YAML or the side
// file; the camera-on-effector keys when the file's `external_form` is camera-on-effector).
// Errors name the file and line.
struct LoadedPredictionModel {
  PredictionModel model;
  bool has_mounting = false;
  bool has_covariance = false;
};
LoadedPredictionModel loadPredictionModel(const std::filesystem::path& parameters_yaml,
                                          const std::optional<std::filesystem::path>& covariance_csv = {});

struct PosePrediction {
  bool converged = false;
  std::string message;
  Eigen::VectorXd pose;             // X in B (mechanism's components)
  Eigen::MatrixXd pose_covariance;  // of X
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
  PoseVector cTm = PoseVector::Zero();
  PoseCovariance cTm_covariance = PoseCovariance::Zero();
};
PosePrediction predictPose(const PredictionModel& model, const Eigen::VectorXd& joints);

struct JointPrediction {
  IkmResult ikm;
  Eigen::MatrixXd covariance;  // of q (zero rows/cols for unreachable joints)
};
JointPrediction predictJointCommands(const PredictionModel& model, const Eigen::Isometry3d& bTe);

}  // namespace mire::mechanism
