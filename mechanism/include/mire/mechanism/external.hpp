#pragma once
// External parameters ξe (paper §4; doc/mechanisms.md): the pose chain bTe = bTc · cTm · mTe (eq. 3)
// that turns the measured target pose cTm into the effector pose X.
//
// Three forms:
//  - AxisAligned (paper §4.1, 8 parameters, z_ME fixed by default -> 7 free):
//      bTc = [Rz(psi_BC) · Acᵀ , (x_BC, y_BC, z_BC)]        (camera centre in B, metres)
//      mTe = [Am · Rz(psi_ME)  , Am · (x_ME, y_ME, z_ME)]    (effector origin in M)
//    Ac, Am (AxisAlignment) are fixed rotations estimated from the data: their third columns
//    are the effector rotation axis z_B seen in the camera frame and in the target frame
//    (all relative rotations cRm(j)·cRm(0)ᵀ share that axis). z_ME is fixed because only
//    z_BC + z_ME is identifiable (eq. 24).
//  - Full (12 parameters, none fixed): both transforms fully parameterised as in eq. 24,
//      cTb = [exp(rx_CB, ry_CB, rz_CB), (tx_CB, ty_CB, tz_CB)],
//      eTm = [exp(rx_EM, ry_EM, rz_EM), (tx_EM, ty_EM, tz_EM)]    (rotation vectors),
//      bTe = cTb⁻¹ · cTm · eTm⁻¹.
//    Left to the identifiability analysis, which names the unidentifiable combinations
//    (for a 1-rotation mechanism: tx_CB + r13·tz_EM, ... (eq. 24) and the effector tilt).
//  - CameraFrame (model 31 rewritten in the camera frame, eq. 25–26; 4 parameters, z_ME
//    fixed -> 3 free): the base frame is the axis-aligned camera frame,
//      bTc = [Acᵀ, 0],  mTe = [Am · Rz(psi_ME), Am · (x_ME, y_ME, z_ME)].
//  - CameraOnEffector (the other mounting, doc/mechanisms.md "Mounting"; 12 parameters, none
//    fixed): the camera rides on the effector and the target is fixed in the workspace,
//      cTm = cTe · eTb(X) · bTm,  eTc = [exp(rx_EC, ry_EC, rz_EC), (tx_EC, ty_EC, tz_EC)],
//      bTm = [exp(rx_BM, ry_BM, rz_BM), (tx_BM, ty_BM, tz_BM)],
//      bTe = bTm · cTm⁻¹ · eTc⁻¹.
//    Like Full, the identifiability analysis names what the motion cannot see.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

class Mechanism;

enum class ExternalForm { AxisAligned, Full, CameraFrame, CameraOnEffector };

// "axis-aligned", "full", "camera-frame", "camera-on-effector"
std::string externalFormName(ExternalForm form);

// The camera mounting of a form: "camera-on-effector" for CameraOnEffector, else "camera-fixed".
std::string mountingName(ExternalForm form);

// Fixed pre-alignment rotations: camera = Ac (columns: aligned frame axes in camera
// coordinates, column 2 = rotation axis), target = Am (same in target coordinates).
struct AxisAlignment {
  Eigen::Matrix3d camera = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d target = Eigen::Matrix3d::Identity();
  // Covariance [rad²] of the estimated tilts (camera about its aligned x, y; target about
  // its aligned x, y), i.e. Ac·exp([δ1, δ2, 0]), Am·exp([δ3, δ4, 0]). Zero when the alignment
  // is exact or unknown. identify() propagates it into the parameter covariance.
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
};

// The alignment tilted by δ (see AxisAlignment::covariance); the covariance is kept.
AxisAlignment tiltAlignment(const AxisAlignment& alignment, const Eigen::Vector4d& delta);

class ExternalParameterization {
 public:
  explicit ExternalParameterization(ExternalForm form, AxisAlignment alignment = {});

  ExternalForm form() const { return form_; }
  const AxisAlignment& alignment() const { return alignment_; }
  static int size(ExternalForm form);  // 8, 12, 4, 12
  int size() const { return size(form_); }

  // Names, units, zero values and default fixed flags (z_ME fixed in AxisAligned and
  // CameraFrame; nothing fixed in Full).
  ParameterSet parameters() const;

  // bTc, mTe and bTe = bTc · cTm · mTe (eq. 3) for the given external values. With the camera
  // on the effector, baseFromCamera() is bTm and targetFromEffector() is cTe (the same chain
  // on the inverted measurement mTc = cTm⁻¹).
  Eigen::Isometry3d baseFromCamera(const Eigen::VectorXd& external) const;
  Eigen::Isometry3d targetFromEffector(const Eigen::VectorXd& external) const;
  Eigen::Isometry3d effectorInBase(const Eigen::VectorXd& external, const PoseVector& cTm) const;
  // The measurement the chain predicts for an effector pose: cTm = cTb · bTe · eTm, or
  // cTe · eTb · bTm with the camera on the effector.
  Eigen::Isometry3d targetInCamera(const Eigen::VectorXd& external, const Eigen::Isometry3d& bTe) const;

  // The values of this form closest to the given transforms (exact for Full and
  // CameraOnEffector, there bTm and cTe; for the aligned forms the rotations are projected onto
  // rotations about the aligned z axis).
  Eigen::VectorXd valuesFrom(const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe) const;

  // Templated chain for autodiff (eq. 3). cTm is a PoseVector-like array of 6 T; R is
  // column-major 3x3 and t a 3-vector of bTe.
  template <class T>
  void effectorInBase(const T* external, const T* cTm, T* R, T* t) const;
  // Same with the measured cTm given as a column-major rotation matrix and a translation
  // (constants: cheaper under autodiff).
  template <class T>
  void effectorInBaseFromMeasured(const T* external, const double* cRm, const double* ctm, T* R, T* t) const;

  // Per-pose constants of the chain, computed once per measured pose: cRm, ctm and, for the
  // aligned forms, M = Acᵀ·cRm·Am and v = Acᵀ·ctm, so that bRe = Rz(psi_BC)·M·Rz(psi_ME) and
  // bte = Rz(psi_BC)·(M·u + v) + (x_BC, y_BC, z_BC) (CameraFrame: psi_BC = 0, no translation).
  struct PreparedPose {
    Eigen::Matrix3d cRm, M;
    Eigen::Vector3d ctm, v;
  };
  PreparedPose prepare(const PoseVector& cTm) const;
  template <class T>
  void effectorInBase(const T* external, const PreparedPose& pose, T* R, T* t) const;

 private:
  template <class T, class S>
  void chain(const T* external, const S* cRm, const S* ctm, T* R, T* t) const;

  ExternalForm form_;
  AxisAlignment alignment_;
  // Column-major copies of Ac, Am for the templated code.
  double camera_[9];
  double target_[9];
};

// The effector rotation axis in the camera and target frames, from the measured
// orientations (least-squares common axis of all relative rotations cRm(j)·cRm(0)ᵀ),
// refined by maximum likelihood over the poses' rotations (weighted by their covariances
// when all poses have one), with the covariance of the tilts (AxisAlignment::covariance).
// The axis sign is arbitrary here; estimateExternal() orients it to agree with θ.
// Throws std::invalid_argument when the poses span less than 2° of rotation.
AxisAlignment estimateAxisAlignment(const std::vector<PoseObservation>& poses);

// Effector poses bTe from the encoder readings through the FKM at `geometric`, started at
// the mechanism's reference pose; where no pose reproduces the joints exactly (a geometry far
// from the robot's), the least-squares pose when its joint mismatch is below 0.1 rad (or m).
// Throws std::runtime_error naming the other pose ids and why the FKM failed there.
std::vector<Eigen::Isometry3d> effectorPosesByFkm(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                  const std::vector<PoseObservation>& poses);

// Mountings (bTc, mTe) with bTe_j = bTc · cTm_j · mTe from effector poses and measured cTm.
struct Mounting {
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d mTe = Eigen::Isometry3d::Identity();
};
// A plate that only translates (bRe = I): the rotation bRc from the displacements
// (Umeyama's least-squares fit, Eigen::umeyama), mRe from the mean measured orientation;
// the target's offset cannot be told from the camera position, so mTe's translation is 0
// and bTc's absorbs it. Throws std::invalid_argument when the positions do not span a
// volume (fewer than 3 non-collinear displacements).
Mounting mountingFromTranslations(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm);
// Full 6-DoF motion: robot-world hand-eye solve (cv::calibrateRobotWorldHandEye, Shah's
// method) of mTc_j · cTb = mTe · eTb_j. Throws std::invalid_argument when the orientations
// span less than 2°.
Mounting mountingFromHandEye(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm);

// Initial external values from the data, never typed by users (doc/mechanisms.md, "Mounting"):
// the effector poses are computed with the FKM at `geometric` (nominal) and the encoder readings, then
// bTc, mTe are solved in closed form (rotation-axis alignment, then a linear least-squares
// fit of ψ_BC and the translations in the plane; z_BC from the mean with z_ME = `z_ME`).
// A mechanism whose effector only translates or moves in 6 DoF takes the Full form only,
// initialised by mountingFromTranslations() / mountingFromHandEye() (z_ME unused).
// Returns the form's ParameterSet with values and default fixed flags. The returned
// parameterisation (with its alignment) is written to `parameterization`.
// Throws std::runtime_error naming the pose ids where the FKM does not converge.
ParameterSet estimateExternal(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                              const std::vector<PoseObservation>& poses, ExternalForm form,
                              ExternalParameterization& parameterization, double z_ME = 0.0);

}  // namespace mire::mechanism

#include "mire/mechanism/detail/external_impl.hpp"
