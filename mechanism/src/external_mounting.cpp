// Data-driven mountings for mechanisms without a single rotation axis (doc/mechanisms.md):
// a translating plate (rotation fit of the displacements) and full 6-DoF motion
// (robot-world hand-eye solve).
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <cmath>
#include <stdexcept>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

void checkSizes(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm, std::size_t minimum) {
  if (bTe.size() != cTm.size()) throw std::invalid_argument("mounting: effector and target pose counts differ");
  if (bTe.size() < minimum)
    throw std::invalid_argument("mounting: at least " + std::to_string(minimum) + " poses are needed");
}

Eigen::Matrix3d projectToRotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

}  // namespace

Mounting mountingFromTranslations(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm) {
  checkSizes(bTe, cTm, 4);
  const auto n = static_cast<Eigen::Index>(bTe.size());
  Eigen::Matrix3Xd camera(3, n), base(3, n);
  Eigen::Matrix3d mean_rotation = Eigen::Matrix3d::Zero();
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Isometry3d measured = toIsometry(cTm[static_cast<std::size_t>(j)]);
    camera.col(j) = measured.translation();
    base.col(j) = bTe[static_cast<std::size_t>(j)].translation();
    mean_rotation += measured.linear();
  }
  // The second singular value of the centred positions tells whether they span a plane.
  const Eigen::Matrix3Xd centred = camera.colwise() - camera.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> spread(centred);
  if (!(spread.singularValues()[1] > 1e-6 * std::sqrt(static_cast<double>(n))))
    throw std::invalid_argument(
        "mounting: the measured positions are (nearly) collinear: the camera rotation is undetermined");
  Mounting m;
  m.bTc.matrix() = Eigen::umeyama(camera, base, false);
  // bRe = I = bRc · cRm · mRe.
  m.mTe.linear() = (m.bTc.linear() * projectToRotation(mean_rotation)).transpose();
  m.mTe.translation().setZero();
  return m;
}

Mounting mountingFromHandEye(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm) {
  checkSizes(bTe, cTm, 3);
  // OpenCV: cam_T_world · world_T_base = cam_T_gripper · gripper_T_base, with cam = M (target),
  // world = C (camera), base = B, gripper = E: mTc_j · cTb = mTe · eTb_j.
  std::vector<cv::Mat> R_world2cam, t_world2cam, R_base2gripper, t_base2gripper;
  double largest = 0.0;
  const Eigen::Matrix3d R0 = toIsometry(cTm.front()).linear();
  for (std::size_t j = 0; j < bTe.size(); ++j) {
    const Eigen::Isometry3d mTc = toIsometry(cTm[j]).inverse(), eTb = bTe[j].inverse();
    largest = std::max(largest, Eigen::AngleAxisd(mTc.linear() * R0).angle());
    cv::Mat R, t, Rb, tb;
    cv::eigen2cv(Eigen::Matrix3d(mTc.linear()), R);
    cv::eigen2cv(Eigen::Vector3d(mTc.translation()), t);
    cv::eigen2cv(Eigen::Matrix3d(eTb.linear()), Rb);
    cv::eigen2cv(Eigen::Vector3d(eTb.translation()), tb);
    R_world2cam.push_back(R);
    t_world2cam.push_back(t);
    R_base2gripper.push_back(Rb);
    t_base2gripper.push_back(tb);
  }
  if (largest < 2.0 * support::kPi / 180.0)
    throw std::invalid_argument(
        "mounting: the measured orientations span less than 2 deg: the hand-eye solve is undetermined");
  cv::Mat R_base2world, t_base2world, R_gripper2cam, t_gripper2cam;
  cv::calibrateRobotWorldHandEye(R_world2cam, t_world2cam, R_base2gripper, t_base2gripper, R_base2world, t_base2world,
                                 R_gripper2cam, t_gripper2cam, cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH);
  Eigen::Matrix3d Rcb, Rme;
  Eigen::Vector3d tcb, tme;
  cv::cv2eigen(R_base2world, Rcb);
  cv::cv2eigen(t_base2world, tcb);
  cv::cv2eigen(R_gripper2cam, Rme);
  cv::cv2eigen(t_gripper2cam, tme);
  Eigen::Isometry3d cTb = Eigen::Isometry3d::Identity();
  cTb.linear() = projectToRotation(Rcb);
  cTb.translation() = tcb;
  Mounting m;
  m.bTc = cTb.inverse();
  m.mTe.linear() = projectToRotation(Rme);
  m.mTe.translation() = tme;
  return m;
}

Eigen::VectorXd mountingWithTargetOrientation(const Eigen::VectorXd& e, const Eigen::Matrix3d& cRm) {
  const ExternalParameterization form(ExternalForm::Full);
  const Eigen::Matrix3d cRb = form.baseFromCamera(e).linear().transpose();
  const Eigen::Matrix3d eRm_old = form.targetFromEffector(e).linear().transpose();
  const Eigen::Matrix3d eRm_new = projectToRotation(cRb.transpose() * cRm);
  // The joints see only the effector origin in M, −eRmᵀ·t_EM: keep it while turning eRm.
  const Eigen::Vector3d t_new = eRm_new * (eRm_old.transpose() * Eigen::Vector3d(e.segment<3>(6)));
  Eigen::VectorXd out = e;
  out.segment<3>(6) = t_new;
  out.segment<3>(9) = rotationVector(eRm_new);
  return out;
}

Eigen::VectorXd mountingWithCameraOrientation(const Eigen::VectorXd& e, const Eigen::Matrix3d& mRc) {
  const ExternalParameterization form(ExternalForm::CameraOnEffector);
  const Eigen::Matrix3d bRm = form.baseFromCamera(e).linear();
  const Eigen::Matrix3d eRc_old = fromRotationVector(e.segment<3>(3));
  // bRe = bRm · mRc · cRe = I.
  const Eigen::Matrix3d eRc_new = projectToRotation(bRm * mRc);
  // The joints see only the effector origin in C, −eRcᵀ·t_EC: keep it while turning eRc.
  Eigen::VectorXd out = e;
  out.head<3>() = eRc_new * (eRc_old.transpose() * Eigen::Vector3d(e.head<3>()));
  out.segment<3>(3) = rotationVector(eRc_new);
  return out;
}

Eigen::VectorXd mountingWithMeanOrientation(ExternalForm form, const Eigen::VectorXd& e, const Eigen::Matrix3d& R) {
  return form == ExternalForm::CameraOnEffector ? mountingWithCameraOrientation(e, R)
                                                : mountingWithTargetOrientation(e, R);
}

namespace {

bool alignsOnMeanOrientation(const Mechanism& mechanism, ExternalForm form) {
  return mechanism.motionType() == MotionType::Translation &&
         (form == ExternalForm::Full || form == ExternalForm::CameraOnEffector);
}

// The measured rotation the chain uses: cTm with the camera fixed, mTc = cTm⁻¹ with the camera on
// the effector (the rotation block of the covariance keeps its value: r(mRc) = −r(cRm)).
std::vector<PoseObservation> chainedPoses(ExternalForm form, const std::vector<PoseObservation>& poses) {
  if (form != ExternalForm::CameraOnEffector) return poses;
  std::vector<PoseObservation> out = poses;
  for (PoseObservation& p : out) p.cTm = toPoseVector(toIsometry(p.cTm).inverse());
  return out;
}

}  // namespace

void alignTranslatingTarget(const Mechanism& mechanism, ExternalParameterization const& form, ParameterSet& parameters,
                            const std::vector<PoseObservation>& poses) {
  if (!alignsOnMeanOrientation(mechanism, form.form()) || poses.empty()) return;
  const bool on_effector = form.form() == ExternalForm::CameraOnEffector;
  Eigen::VectorXd e(12);
  const std::vector<std::string> names = form.parameters().names();
  for (int k = 0; k < 12; ++k) e[k] = parameters.value(names[static_cast<std::size_t>(k)]);
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  for (const PoseObservation& p : poses)
    mean += on_effector ? Eigen::Matrix3d(toIsometry(p.cTm).linear().transpose()) : toIsometry(p.cTm).linear();
  const Eigen::VectorXd aligned = mountingWithMeanOrientation(form.form(), e, projectToRotation(mean));
  // The rotation not seen by the joints: eTm's (the last six) or eTc's (the first six).
  const int first = on_effector ? 0 : 6;
  for (int k = first; k < first + 6; ++k) parameters.setValue(names[static_cast<std::size_t>(k)], aligned[k]);
}

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// Left Jacobian of SO(3): exp(r + δ) ≈ exp(Jl(r)·δ)·exp(r).
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& r) {
  const double theta = r.norm();
  const Eigen::Matrix3d S = skew(r);
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * S;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / (theta * theta) * S +
         (theta - std::sin(theta)) / (theta * theta * theta) * S * S;
}

// Covariance of the rotation vector of R̄ = proj(mean_j cRm_j), to first order in the spread:
// in the left tangent at R̄, ω̄ = mean_j ω_j with ω_j = Jl(r_j)·δr_j, so
// Σ_ω = (1/N²)·Σ_j Jl(r_j)·Σ_r,j·Jl(r_j)ᵀ (the poses' covariances), or the scatter of the
// ω_j = log(cRm_j·R̄ᵀ) over N(N−1) when the poses carry none; then Σ_r̄ = Jl(r̄)⁻¹·Σ_ω·Jl(r̄)⁻ᵀ.
Eigen::Matrix3d meanOrientationCovariance(const std::vector<PoseObservation>& poses, const Eigen::Matrix3d& mean) {
  bool measured = true;
  for (const PoseObservation& p : poses) measured = measured && p.covariance.has_value();
  const auto n = static_cast<double>(poses.size());
  Eigen::Matrix3d omega = Eigen::Matrix3d::Zero();
  for (const PoseObservation& p : poses) {
    if (measured) {
      const Eigen::Matrix3d Jl = leftJacobian(p.cTm.tail<3>());
      omega += Jl * p.covariance->bottomRightCorner<3, 3>() * Jl.transpose() / (n * n);
    } else if (poses.size() > 1) {
      const Eigen::Vector3d w = rotationVector(toIsometry(p.cTm).linear() * mean.transpose());
      omega += w * w.transpose() / (n * (n - 1.0));
    }
  }
  const Eigen::Matrix3d Jl_inverse = leftJacobian(rotationVector(mean)).inverse();
  return Jl_inverse * omega * Jl_inverse.transpose();
}

// The offset's rows of every covariance term follow t → Q·t (t_EM, or t_EC with the camera on
// the effector); the total and σ are summed again from the turned terms.
void turnTargetOffsetCovariance(IdentificationResult& result, const Eigen::Matrix3d& Q,
                                const std::vector<std::string>& offset) {
  const std::vector<std::string>& free = result.free_names;
  std::vector<Eigen::Index> rows;
  for (const std::string& name : offset)
    for (std::size_t f = 0; f < free.size(); ++f)
      if (free[f] == name) rows.push_back(static_cast<Eigen::Index>(f));
  if (rows.size() != 3 || result.covariance.rows() != static_cast<Eigen::Index>(free.size())) return;
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(result.covariance.rows(), result.covariance.cols());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(j)]) = Q(i, j);
  std::vector<CovarianceTerm> terms = result.covariance_terms;
  for (CovarianceTerm& term : terms) {
    term.covariance = P * term.covariance * P.transpose();
    if (term.columns.size() > 0) term.columns = P * term.columns;
  }
  setCovarianceTerms(result, std::move(terms));
}

}  // namespace

std::optional<Eigen::Matrix3d> alignTranslatingTarget(IdentificationResult& result,
                                                      const std::vector<PoseObservation>& poses) {
  const IdentificationModel& model = result.model;
  const ExternalParameterization& form = model.external;
  if (!alignsOnMeanOrientation(*model.mechanism, form.form()) || poses.empty()) return std::nullopt;
  const bool on_effector = form.form() == ExternalForm::CameraOnEffector;
  // The turned rotation: eRm (targetFromEffector() is mTe) or eRc (it is cTe).
  const auto turned = [&form](const Eigen::VectorXd& e) {
    return Eigen::Matrix3d(form.targetFromEffector(e).linear().transpose());
  };
  const Eigen::Matrix3d old_rotation = turned(model.externalValues());
  alignTranslatingTarget(*model.mechanism, form, result.model.parameters, poses);
  const Eigen::VectorXd e = result.model.externalValues();
  const Eigen::Matrix3d new_rotation = turned(e);
  turnTargetOffsetCovariance(result, new_rotation * old_rotation.transpose(),
                             on_effector ? std::vector<std::string>{"tx_EC", "ty_EC", "tz_EC"}
                                         : std::vector<std::string>{"tx_EM", "ty_EM", "tz_EM"});
  // R̄ = cRb·eRm (camera fixed) or mRb·eRc (camera on the effector).
  const Eigen::Matrix3d mean = form.baseFromCamera(e).linear().transpose() * new_rotation;
  return meanOrientationCovariance(chainedPoses(form.form(), poses), mean);
}

ParameterSet estimateMountingExternal(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                      const std::vector<PoseObservation>& poses, ExternalForm form,
                                      ExternalParameterization& parameterization) {
  const bool on_effector = form == ExternalForm::CameraOnEffector;
  if (form != ExternalForm::Full && !on_effector)
    throw std::invalid_argument("the " + externalFormName(form) + " external form needs one rotation axis; " +
                                mechanism.name() + " moves in " + motionTypeName(mechanism.motionType()) +
                                ": use the full form");
  if (on_effector && mechanism.motionType() == MotionType::Schoenflies)
    throw std::invalid_argument("camera-on-effector: " + mechanism.name() +
                                " turns about one axis only; its mounting is not initialised from the data yet");
  const std::vector<Eigen::Isometry3d> bTe = effectorPosesByFkm(mechanism, geometric, poses);
  // With the camera on the effector the chain is the same on the inverted measurement:
  // bTe = bTm · mTc · cTe, so the same closed forms give (bTm, cTe) in place of (bTc, mTe).
  std::vector<PoseVector> cTm;
  cTm.reserve(poses.size());
  for (const PoseObservation& p : poses)
    cTm.push_back(on_effector ? PoseVector(toPoseVector(toIsometry(p.cTm).inverse())) : p.cTm);
  const Mounting m = mechanism.motionType() == MotionType::Translation ? mountingFromTranslations(bTe, cTm)
                                                                       : mountingFromHandEye(bTe, cTm);
  parameterization = ExternalParameterization(form);
  ParameterSet set = parameterization.parameters();
  set.setValues(parameterization.valuesFrom(m.bTc, m.mTe));
  return set;
}

}  // namespace mire::mechanism
