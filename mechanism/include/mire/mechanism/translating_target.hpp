#pragma once
// A plate that only translates (the Delta, doc/mechanisms.md "`mire fkm` and `mire ikm`"): its orientation
// seen by the camera, cRm = cRb·eRm, is not a function of the joints. The identification
// leaves the target's rotation on the effector eRm where the initialisation put it (it has
// no influence on the joints); alignTranslatingTarget() sets it from the measured
// orientations, eRm = cRbᵀ·R̄ with R̄ the mean measured orientation, so the model predicts
// cRm = R̄ whatever the error of cRb. The prediction's σ must then be R̄'s, not cRb's.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::mechanism {

// alignTranslatingTarget() (gauge.hpp) on an identification result: sets eRm = cRbᵀ·R̄ (the
// effector origin in the target frame kept), turns the covariance rows of the target offset
// tx_EM..tz_EM with the target frame (camera on the effector: eRc and tx_EC..tz_EC), and
// returns the covariance of R̄'s rotation vector (from the poses' covariances, else from the
// scatter of their orientations). std::nullopt (and no change) for other motions or forms.
std::optional<Eigen::Matrix3d> alignTranslatingTarget(IdentificationResult& result,
                                                      const std::vector<PoseObservation>& poses);

// The 12 full-form mounting values `e` with the target's rotation on the effector set so that
// cRb·eRm = cRm, the effector origin in the target frame (−eRmᵀ·t_EM) kept.
Eigen::VectorXd mountingWithTargetOrientation(const Eigen::VectorXd& e, const Eigen::Matrix3d& cRm);

// With the camera on the effector (ExternalForm::CameraOnEffector) the same for the camera's
// rotation on the effector: eRc = bRm·R̄ with R̄ the mean of mRc = cRm⁻¹, the camera origin in
// the effector frame (−eRcᵀ·t_EC) kept.
Eigen::VectorXd mountingWithCameraOrientation(const Eigen::VectorXd& e, const Eigen::Matrix3d& mRc);
// The one of the two above that belongs to `form` (Full or CameraOnEffector).
Eigen::VectorXd mountingWithMeanOrientation(ExternalForm form, const Eigen::VectorXd& e, const Eigen::Matrix3d& R);

// predictionModelFrom() (prediction.hpp) of a result aligned by the function above, given the
// covariance it returned: eRm is carried as cRbᵀ·R̄ (it follows the camera rotation) and R̄'s
// covariance joins the mounting's, so the predicted orientation has R̄'s σ. With
// std::nullopt, the same as the two-argument form.
PredictionModel predictionModelFrom(const std::string& model_name, const IdentificationResult& result,
                                    const std::optional<Eigen::Matrix3d>& mean_orientation_covariance);

}  // namespace mire::mechanism
