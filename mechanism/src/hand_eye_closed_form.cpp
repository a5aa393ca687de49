// OpenCV's closed-form hand-eye solutions (the start of the joint fit and the field's reference);
// see hand_eye.hpp.
#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <map>
#include <stdexcept>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/hand_eye.hpp"

namespace mire::mechanism {

namespace {

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

Eigen::Isometry3d isometryOf(const cv::Mat& R, const cv::Mat& t) {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  cv::cv2eigen(R, rotation);
  cv::cv2eigen(t, translation);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = nearestRotation(rotation);
  T.translation() = translation;
  return T;
}

void pushPose(const Eigen::Isometry3d& T, std::vector<cv::Mat>& R, std::vector<cv::Mat>& t) {
  cv::Mat r, v;
  cv::eigen2cv(Eigen::Matrix3d(T.linear()), r);
  cv::eigen2cv(Eigen::Vector3d(T.translation()), v);
  R.push_back(r);
  t.push_back(v);
}

// Z from every pose given X: the chordal mean of the rotations, the mean of the translations.
Eigen::Isometry3d meanZ(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                        const Eigen::Isometry3d& X) {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  for (const HandEyeObservation& p : poses) {
    const Eigen::Isometry3d bTe = toIsometry(p.bTe), cTm = toIsometry(p.cTm);
    const Eigen::Isometry3d Z = mounting == HandEyeMounting::CameraOnEffector ? bTe * X * cTm  // bTm
                                                                              : bTe.inverse() * X.inverse() * cTm;  // eTm
    rotation += Z.linear();
    translation += Z.translation();
  }
  Eigen::Isometry3d Z = Eigen::Isometry3d::Identity();
  Z.linear() = nearestRotation(rotation);
  Z.translation() = translation / static_cast<double>(poses.size());
  return Z;
}

cv::HandEyeCalibrationMethod handEyeMethod(const std::string& method) {
  static const std::map<std::string, cv::HandEyeCalibrationMethod> methods{{"tsai", cv::CALIB_HAND_EYE_TSAI},
                                                                           {"park", cv::CALIB_HAND_EYE_PARK},
                                                                           {"horaud", cv::CALIB_HAND_EYE_HORAUD},
                                                                           {"andreff", cv::CALIB_HAND_EYE_ANDREFF},
                                                                           {"daniilidis", cv::CALIB_HAND_EYE_DANIILIDIS}};
  const auto it = methods.find(method);
  if (it == methods.end())
    throw std::invalid_argument("hand-eye method '" + method +
                                "': expected tsai, park, horaud, andreff, daniilidis, shah or li");
  return it->second;
}

// cv::calibrateRobotWorldHandEye solves world2cam_j · base2world = gripper2cam · base2gripper_j.
// Camera fixed: cam = M, world = C, gripper = E, base = B, i.e. mTc_j · cTb = mTe · eTb_j.
// Camera on the effector: the inverted chain mTc_j = mTb · bTe_j · eTc has the same form with
// cam = M, world = C, gripper = B, base = E, i.e. mTc_j · cTe = mTb · bTe_j.
HandEyeTransforms robotWorld(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                             cv::RobotWorldHandEyeCalibrationMethod method) {
  std::vector<cv::Mat> R_world2cam, t_world2cam, R_base2gripper, t_base2gripper;
  for (const HandEyeObservation& p : poses) {
    const Eigen::Isometry3d mTc = toIsometry(p.cTm).inverse(), bTe = toIsometry(p.bTe);
    pushPose(mTc, R_world2cam, t_world2cam);
    pushPose(mounting == HandEyeMounting::CameraFixed ? bTe.inverse() : bTe, R_base2gripper, t_base2gripper);
  }
  cv::Mat R_base2world, t_base2world, R_gripper2cam, t_gripper2cam;
  cv::calibrateRobotWorldHandEye(R_world2cam, t_world2cam, R_base2gripper, t_base2gripper, R_base2world, t_base2world,
                                 R_gripper2cam, t_gripper2cam, method);
  const Eigen::Isometry3d first = isometryOf(R_base2world, t_base2world);     // cTb (fixed) or cTe (on effector)
  const Eigen::Isometry3d second = isometryOf(R_gripper2cam, t_gripper2cam);  // mTe (fixed) or mTb (on effector)
  HandEyeTransforms out;
  if (mounting == HandEyeMounting::CameraFixed) {
    out.X = first;
    out.Z = second.inverse();
  } else {
    out.X = first.inverse();
    out.Z = second.inverse();
  }
  return out;
}

}  // namespace

HandEyeTransforms handEyeClosedForm(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                                    const std::string& method) {
  if (poses.size() < 3) throw std::invalid_argument("hand-eye: at least 3 poses are needed");
  if (method == "shah") return robotWorld(poses, mounting, cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH);
  if (method == "li") return robotWorld(poses, mounting, cv::CALIB_ROBOT_WORLD_HAND_EYE_LI);
  std::vector<cv::Mat> R_gripper2base, t_gripper2base, R_target2cam, t_target2cam;
  for (const HandEyeObservation& p : poses) {
    const Eigen::Isometry3d bTe = toIsometry(p.bTe);
    // Camera fixed: OpenCV's eye-to-hand use passes base→gripper (eTb) and returns cam→base (bTc).
    pushPose(mounting == HandEyeMounting::CameraOnEffector ? bTe : bTe.inverse(), R_gripper2base, t_gripper2base);
    pushPose(toIsometry(p.cTm), R_target2cam, t_target2cam);
  }
  cv::Mat R, t;
  cv::calibrateHandEye(R_gripper2base, t_gripper2base, R_target2cam, t_target2cam, R, t, handEyeMethod(method));
  HandEyeTransforms out;
  const Eigen::Isometry3d solved = isometryOf(R, t);  // eTc, or bTc with the camera fixed
  out.X = mounting == HandEyeMounting::CameraOnEffector ? solved : solved.inverse();
  out.Z = meanZ(poses, mounting, out.X);
  return out;
}

}  // namespace mire::mechanism
