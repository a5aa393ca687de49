// Cross-check of the 6-DoF mounting initialisation (doc/mechanisms.md, "Mounting"): mire's
// robot-world hand-eye solve (mountingFromHandEye: cv::calibrateRobotWorldHandEye, Shah's
// method) against ViSP's vpHandEyeCalibration::calibrate (Tsai's rotation then a nonlinear
// refinement, an AX = XB hand-eye solve), both on the same simulated Gough–Stewart campaigns,
// errors of bTc and eTm against the truth.
// ViSP solves the eye-in-hand chain rMe_j · eMc · cMo_j = rMo (constant); the camera here is
// fixed and the target rides the effector, bTe_j · eTm · mTc_j = bTc, so it is given
// rMe = bTe_j, cMo = mTc_j and returns eMc = eTm; bTc is then the mean of bTe_j · eTm · mTc_j
// (rotations averaged by projecting their sum onto SO(3)).
// Two inputs: the true effector poses (the solvers alone) and the FKM poses at the nominal
// geometry (what identify starts from: 1 mm errors on the 42 parameters).
// Usage: bench_mounting_visp [campaigns=40]
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/vision/vpHandEyeCalibration.h>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/external.hpp"

using namespace mire::mechanism;
using mire::datasets::Campaign;

namespace {

vpHomogeneousMatrix toVisp(const Eigen::Isometry3d& T) {
  vpHomogeneousMatrix M;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) M[r][c] = T.matrix()(r, c);
  return M;
}

Eigen::Isometry3d fromVisp(const vpHomogeneousMatrix& M) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = M[static_cast<unsigned>(r)][static_cast<unsigned>(c)];
  return T;
}

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& A) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() > 0 ? 1 : -1;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// ViSP's hand-eye solve, then bTc from the chain. Returns false when ViSP reports a failure.
bool viaVisp(const std::vector<Eigen::Isometry3d>& bTe, const std::vector<PoseVector>& cTm, Mounting& out) {
  std::vector<vpHomogeneousMatrix> cMo, rMe;
  for (std::size_t j = 0; j < bTe.size(); ++j) {
    cMo.push_back(toVisp(toIsometry(cTm[j]).inverse()));
    rMe.push_back(toVisp(bTe[j]));
  }
  vpHomogeneousMatrix eMc;
  // ViSP prints a line per pose (its rMo check): silenced.
  std::streambuf* const saved = std::cout.rdbuf(nullptr);
  const int status = vpHandEyeCalibration::calibrate(cMo, rMe, eMc);
  std::cout.rdbuf(saved);
  std::cout.clear();
  if (status != 0) return false;
  const Eigen::Isometry3d eTm = fromVisp(eMc);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < bTe.size(); ++j) {
    const Eigen::Isometry3d bTc = bTe[j] * eTm * toIsometry(cTm[j]).inverse();
    sum += bTc.linear();
    t += bTc.translation() / static_cast<double>(bTe.size());
  }
  out.bTc = Eigen::Isometry3d::Identity();
  out.bTc.linear() = nearestRotation(sum);
  out.bTc.translation() = t;
  out.mTe = eTm.inverse();
  return true;
}

struct Errors {
  std::vector<double> bTc_deg, bTc_mm, eTm_deg, eTm_mm, ms;
  int failures = 0;
};

void addErrors(const Mounting& m, const Campaign& c, double ms, Errors& e) {
  e.bTc_deg.push_back(Eigen::AngleAxisd(m.bTc.linear().transpose() * c.bTc.linear()).angle() * 180 / M_PI);
  e.bTc_mm.push_back(1e3 * (m.bTc.translation() - c.bTc.translation()).norm());
  const Eigen::Isometry3d eTm = m.mTe.inverse(), truth = c.mTe.inverse();
  e.eTm_deg.push_back(Eigen::AngleAxisd(eTm.linear().transpose() * truth.linear()).angle() * 180 / M_PI);
  e.eTm_mm.push_back(1e3 * (eTm.translation() - truth.translation()).norm());
  e.ms.push_back(ms);
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? NAN : std::sqrt(s / static_cast<double>(v.size()));
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void print(const char* label, const Errors& e) {
  std::printf("| %s | %.4f | %.3f | %.4f | %.3f | %.2f | %d |\n", label, rms(e.bTc_deg), rms(e.bTc_mm), rms(e.eTm_deg),
              rms(e.eTm_mm), median(e.ms), e.failures);
}

double cpuMs(std::clock_t start) { return 1e3 * double(std::clock() - start) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 40;
  Errors mire_true, visp_true, mire_fkm, visp_fkm;
  for (int k = 0; k < campaigns; ++k) {
    const Campaign c = mire::datasets::simulateCampaign("gough-stewart", 500 + static_cast<unsigned>(k));
    std::vector<PoseVector> cTm;
    for (const PoseObservation& p : c.poses) cTm.push_back(p.cTm);
    const std::vector<Eigen::Isometry3d> fkm = effectorPosesByFkm(*c.model.mechanism, c.model.nominal.values(), c.poses);
    for (const bool truth : {true, false}) {
      const std::vector<Eigen::Isometry3d>& bTe = truth ? c.bTe : fkm;
      std::clock_t t0 = std::clock();
      const Mounting a = mountingFromHandEye(bTe, cTm);
      addErrors(a, c, cpuMs(t0), truth ? mire_true : mire_fkm);
      Mounting b;
      t0 = std::clock();
      if (viaVisp(bTe, cTm, b))
        addErrors(b, c, cpuMs(t0), truth ? visp_true : visp_fkm);
      else
        ++(truth ? visp_true : visp_fkm).failures;
    }
  }
  std::printf("\n%d Gough-Stewart campaigns (81 poses, 0.2 mm / 0.03 deg pose noise): RMS errors against the truth\n",
              campaigns);
  std::printf(
      "| effector poses, solver | bTc rotation [deg] | bTc translation [mm] | eTm rotation [deg] | "
      "eTm translation [mm] | CPU [ms], median | failures |\n|---|---|---|---|---|---|---|\n");
  print("true, mire (cv::calibrateRobotWorldHandEye, Shah)", mire_true);
  print("true, ViSP vpHandEyeCalibration", visp_true);
  print("FKM at nominal, mire (cv::calibrateRobotWorldHandEye, Shah)", mire_fkm);
  print("FKM at nominal, ViSP vpHandEyeCalibration", visp_fkm);
  return 0;
}
