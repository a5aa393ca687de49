// External parameters (paper §4; doc/mechanisms.md): forms of bTc, mTe, the rotation-axis
// pre-alignment and the closed-form initial estimate from the data.
#include "mire/mechanism/external.hpp"

#include <ceres/autodiff_cost_function.h>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using support::kPi;

Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

double angleAboutZ(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// A rotation whose third column is `axis`; its x column is the camera/target x (or y)
// axis projected on the plane normal to `axis` (Gram–Schmidt: well conditioned even when
// the axis is anti-parallel to z, unlike a minimal-rotation quaternion).
Eigen::Matrix3d alignZ(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d seed = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = (seed - seed.dot(z) * z).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return R;
}

Parameter length(const std::string& name, const std::string& description, bool fixed = false) {
  return Parameter{name, 0.0, Unit::Metre, fixed, description};
}
Parameter angle(const std::string& name, const std::string& description) {
  return Parameter{name, 0.0, Unit::Radian, false, description};
}

// A rigid transform as six parameters: its translation ("tx_<suffix>": `origin` in metres), then
// its rotation vector ("rx_<suffix>"), both named after the transform `name` (e.g. cTb).
void addTransform(ParameterSet& set, const std::string& suffix, const std::string& origin, const std::string& name) {
  for (const char axis : {'x', 'y', 'z'})
    set.add(length(std::string("t") + axis + "_" + suffix, origin + ", " + axis + " (" + name + ")"));
  for (const char axis : {'x', 'y', 'z'})
    set.add(angle(std::string("r") + axis + "_" + suffix, name + " rotation vector, " + axis));
}

// The transform stored as (translation, rotation vector) at e[offset..offset+5].
Eigen::Isometry3d transformAt(const Eigen::VectorXd& e, int offset) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = fromRotationVector(e.segment<3>(offset + 3));
  T.translation() = e.segment<3>(offset);
  return T;
}

// Maximum-likelihood refinement of the axis alignment: cRm(j) = Ac·Rz(φ_j)·Amᵀ·exp(noise).
// Unknowns: small tilts of Ac and Am about their x, y axes, and one angle per pose. The
// residual is the rotation vector of (Ac·Rz(φ)·Amᵀ)ᵀ·cRm.
template <class T>
void axisResidual(const Eigen::Matrix3d& Ac0, const Eigen::Matrix3d& Am0, const T* tilt_c, const T* tilt_m,
                  const T* phi, const Eigen::Matrix<T, 3, 3>& cRm, T* residual) {
  T rc[3] = {tilt_c[0], tilt_c[1], T(0)}, rm[3] = {tilt_m[0], tilt_m[1], T(0)};
  Eigen::Matrix<T, 3, 3> Dc, Dm;
  ceres::AngleAxisToRotationMatrix(rc, ceres::ColumnMajorAdapter3x3(Dc.data()));
  ceres::AngleAxisToRotationMatrix(rm, ceres::ColumnMajorAdapter3x3(Dm.data()));
  const Eigen::Matrix<T, 3, 3> Ac = Ac0.cast<T>() * Dc, Am = Am0.cast<T>() * Dm;
  Eigen::Matrix<T, 3, 3> Rz;
  using std::cos;
  using std::sin;
  Rz << cos(phi[0]), -sin(phi[0]), T(0), sin(phi[0]), cos(phi[0]), T(0), T(0), T(0), T(1);
  const Eigen::Matrix<T, 3, 3> E = (Ac * Rz * Am.transpose()).transpose() * cRm;
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(E.data()), residual);
}

struct AxisResidual {
  // Pointers into the caller's arrays (they outlive the solve): 10⁵ poses must not copy the
  // shared Ac0, Am0 10⁵ times, and the per-pose data stays contiguous.
  const Eigen::Matrix3d* Ac0;
  const Eigen::Matrix3d* Am0;
  const Eigen::Matrix3d* cRm;
  const Eigen::Matrix3d* whitening;
  template <class T>
  bool operator()(const T* tilt_c, const T* tilt_m, const T* phi, T* residual) const {
    T e[3];
    axisResidual(*Ac0, *Am0, tilt_c, tilt_m, phi, Eigen::Matrix<T, 3, 3>(cRm->cast<T>()), e);
    const Eigen::Matrix3d& W = *whitening;
    for (int r = 0; r < 3; ++r) residual[r] = W(r, 0) * e[0] + W(r, 1) * e[1] + W(r, 2) * e[2];
    return true;
  }
};

// The same residual as a function of the measured rotation vector (to map its covariance).
struct AxisResidualWrtMeasurement {
  Eigen::Matrix3d Ac0, Am0;
  double phi;
  template <class T>
  bool operator()(const T* rotation_vector, T* residual) const {
    Eigen::Matrix<T, 3, 3> cRm;
    ceres::AngleAxisToRotationMatrix(rotation_vector, ceres::ColumnMajorAdapter3x3(cRm.data()));
    const T zero[2] = {T(0), T(0)};
    const T angle[1] = {T(phi)};
    axisResidual(Ac0, Am0, zero, zero, angle, cRm, residual);
    return true;
  }
};

Eigen::Matrix3d tiltXY(double x, double y) { return fromRotationVector(Eigen::Vector3d(x, y, 0.0)); }

}  // namespace

// Translation-only and 6-DoF mechanisms: the Full form from a data-driven mounting
// (external_mounting.cpp).
ParameterSet estimateMountingExternal(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                      const std::vector<PoseObservation>& poses, ExternalForm form,
                                      ExternalParameterization& parameterization);

std::string externalFormName(ExternalForm form) {
  switch (form) {
    case ExternalForm::AxisAligned:
      return "axis-aligned";
    case ExternalForm::Full:
      return "full";
    case ExternalForm::CameraFrame:
      return "camera-frame";
    case ExternalForm::CameraOnEffector:
      return "camera-on-effector";
  }
  return "?";
}

std::string mountingName(ExternalForm form) {
  return form == ExternalForm::CameraOnEffector ? "camera-on-effector" : "camera-fixed";
}

ExternalParameterization::ExternalParameterization(ExternalForm form, AxisAlignment alignment)
    : form_(form), alignment_(std::move(alignment)) {
  for (const Eigen::Matrix3d* m : {&alignment_.camera, &alignment_.target})
    if (!m->allFinite() || !(m->transpose() * *m).isApprox(Eigen::Matrix3d::Identity(), 1e-9) || m->determinant() < 0.0)
      throw std::invalid_argument("axis alignment is not a rotation matrix");
  Eigen::Map<Eigen::Matrix3d>{camera_} = alignment_.camera;
  Eigen::Map<Eigen::Matrix3d>{target_} = alignment_.target;
}

int ExternalParameterization::size(ExternalForm form) {
  switch (form) {
    case ExternalForm::AxisAligned:
      return 8;
    case ExternalForm::Full:
    case ExternalForm::CameraOnEffector:
      return 12;
    case ExternalForm::CameraFrame:
      return 4;
  }
  return 0;
}

ParameterSet ExternalParameterization::parameters() const {
  ParameterSet set;
  const auto addTargetPart = [&set] {
    set.add(length("x_ME", "effector origin in the axis-aligned target frame, x"));
    set.add(length("y_ME", "effector origin in the axis-aligned target frame, y"));
    set.add(length("z_ME", "effector origin along the rotation axis (fixed: eq. 24)", true));
    set.add(angle("psi_ME", "target -> effector rotation about the rotation axis"));
  };
  switch (form_) {
    case ExternalForm::AxisAligned:
      set.add(length("x_BC", "camera centre in the base frame, x"));
      set.add(length("y_BC", "camera centre in the base frame, y"));
      set.add(length("z_BC", "camera centre in the base frame, z"));
      set.add(angle("psi_BC", "base <- axis-aligned camera rotation about z_B"));
      addTargetPart();
      break;
    case ExternalForm::Full:
      addTransform(set, "CB", "base origin in the camera frame", "cTb");
      addTransform(set, "EM", "target origin in the effector frame", "eTm");
      break;
    case ExternalForm::CameraFrame:
      addTargetPart();
      break;
    case ExternalForm::CameraOnEffector:  // doc/mechanisms.md, "Camera on the effector"
      addTransform(set, "EC", "camera origin in the effector frame", "eTc");
      addTransform(set, "BM", "target origin in the base frame", "bTm");
      break;
  }
  return set;
}

Eigen::Isometry3d ExternalParameterization::baseFromCamera(const Eigen::VectorXd& e) const {
  if (e.size() != size()) throw std::invalid_argument("external parameter vector has the wrong size");
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity();
  switch (form_) {
    case ExternalForm::AxisAligned:
      bTc.linear() = rotZ(e[3]) * alignment_.camera.transpose();
      bTc.translation() = e.head<3>();
      break;
    case ExternalForm::Full:
      bTc = transformAt(e, 0).inverse();  // cTb
      break;
    case ExternalForm::CameraFrame:
      bTc.linear() = alignment_.camera.transpose();
      break;
    case ExternalForm::CameraOnEffector:
      bTc = transformAt(e, 6);  // bTm
      break;
  }
  return bTc;
}

Eigen::Isometry3d ExternalParameterization::targetFromEffector(const Eigen::VectorXd& e) const {
  if (e.size() != size()) throw std::invalid_argument("external parameter vector has the wrong size");
  Eigen::Isometry3d mTe = Eigen::Isometry3d::Identity();
  if (form_ == ExternalForm::Full) return transformAt(e, 6).inverse();              // eTm⁻¹
  if (form_ == ExternalForm::CameraOnEffector) return transformAt(e, 0).inverse();  // cTe = eTc⁻¹
  const Eigen::Vector4d me =
      form_ == ExternalForm::AxisAligned ? Eigen::Vector4d(e.segment<4>(4)) : Eigen::Vector4d(e.head<4>());
  mTe.linear() = alignment_.target * rotZ(me[3]);
  mTe.translation() = alignment_.target * me.head<3>();
  return mTe;
}

Eigen::Isometry3d ExternalParameterization::effectorInBase(const Eigen::VectorXd& e, const PoseVector& cTm) const {
  if (e.size() != size()) throw std::invalid_argument("external parameter vector has the wrong size");
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  effectorInBase(e.data(), cTm.data(), R.data(), t.data());
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
  bTe.linear() = R;
  bTe.translation() = t;
  return bTe;
}

Eigen::Isometry3d ExternalParameterization::targetInCamera(const Eigen::VectorXd& e, const Eigen::Isometry3d& bTe) const {
  // bTe = B · cTm^s · E with s = +1 (camera fixed) or −1 (camera on the effector).
  const Eigen::Isometry3d B = baseFromCamera(e), E = targetFromEffector(e);
  const Eigen::Isometry3d chained = B.inverse() * bTe * E.inverse();
  return form_ == ExternalForm::CameraOnEffector ? chained.inverse() : chained;
}

ExternalParameterization::PreparedPose ExternalParameterization::prepare(const PoseVector& cTm) const {
  const Eigen::Isometry3d measured = toIsometry(cTm);
  PreparedPose pose;
  pose.cRm = measured.linear();
  pose.ctm = measured.translation();
  pose.M = alignment_.camera.transpose() * pose.cRm * alignment_.target;
  pose.v = alignment_.camera.transpose() * pose.ctm;
  return pose;
}

Eigen::VectorXd ExternalParameterization::valuesFrom(const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe) const {
  Eigen::VectorXd e(size());
  if (form_ == ExternalForm::Full) {
    const Eigen::Isometry3d cTb = bTc.inverse(), eTm = mTe.inverse();
    e << cTb.translation(), rotationVector(cTb.linear()), eTm.translation(), rotationVector(eTm.linear());
    return e;
  }
  if (form_ == ExternalForm::CameraOnEffector) {  // bTc is bTm, mTe is cTe
    const Eigen::Isometry3d eTc = mTe.inverse();
    e << eTc.translation(), rotationVector(eTc.linear()), bTc.translation(), rotationVector(bTc.linear());
    return e;
  }
  const Eigen::Vector3d me = alignment_.target.transpose() * mTe.translation();
  const double psi_me = angleAboutZ(alignment_.target.transpose() * mTe.linear());
  if (form_ == ExternalForm::AxisAligned) {
    e << bTc.translation(), angleAboutZ(bTc.linear() * alignment_.camera), me, psi_me;
  } else {
    e << me, psi_me;
  }
  return e;
}

AxisAlignment tiltAlignment(const AxisAlignment& alignment, const Eigen::Vector4d& delta) {
  AxisAlignment out = alignment;
  out.camera = alignment.camera * tiltXY(delta[0], delta[1]);
  out.target = alignment.target * tiltXY(delta[2], delta[3]);
  return out;
}

namespace {

// Every relative rotation is about the common axis: principal direction of their rotation
// vectors (small rotations weigh little). Relative to a bounded number of reference poses
// spread over the list, so the cost is linear in the pose count (the maximum-likelihood
// refinement removes the dependence on that choice).
Eigen::Vector3d principalRotationAxis(const std::vector<Eigen::Matrix3d>& R) {
  constexpr std::size_t kReferences = 16;
  const std::size_t stride = std::max<std::size_t>(1, R.size() / kReferences);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double largest = 0.0;
  for (std::size_t i = 0; i < R.size(); i += stride)
    for (std::size_t j = 0; j < R.size(); ++j) {
      if (j == i) continue;
      const Eigen::Vector3d w = rotationVector(R[j] * R[i].transpose());
      scatter += w * w.transpose();
      largest = std::max(largest, w.norm());
    }
  if (largest < 2.0 * kPi / 180.0)
    throw std::invalid_argument("the measured orientations span less than 2 deg: the rotation axis is undetermined");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  return eigen.eigenvectors().col(2);
}

// W_j = L⁻¹ with Cj = Jr·Σr·Jrᵀ = L Lᵀ, from each pose's rotation-vector covariance; the
// identity for every pose (and *weighted = false) when one lacks a usable covariance.
std::vector<Eigen::Matrix3d> axisResidualWhitening(const std::vector<PoseObservation>& poses,
                                                   const Eigen::Matrix3d& Ac0, const Eigen::Matrix3d& Am0,
                                                   const std::vector<double>& phi, bool* weighted) {
  const std::size_t n = poses.size();
  *weighted = true;
  for (const PoseObservation& p : poses) *weighted = *weighted && p.covariance.has_value();
  std::vector<Eigen::Matrix3d> whitening(n, Eigen::Matrix3d::Identity());
  if (!*weighted) return whitening;
  for (std::size_t j = 0; j < n; ++j) {
    ceres::AutoDiffCostFunction<AxisResidualWrtMeasurement, 3, 3> cost(new AxisResidualWrtMeasurement{Ac0, Am0, phi[j]});
    const double* parameters[1] = {poses[j].cTm.data() + 3};
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Jr;
    double* jacobians[1] = {Jr.data()};
    Eigen::Vector3d e;
    cost.Evaluate(parameters, e.data(), jacobians);
    const Eigen::Matrix3d C = Jr * poses[j].covariance->bottomRightCorner<3, 3>() * Jr.transpose();
    const Eigen::LLT<Eigen::Matrix3d> llt(C);
    if (llt.info() != Eigen::Success) {
      *weighted = false;
      return std::vector<Eigen::Matrix3d>(n, Eigen::Matrix3d::Identity());
    }
    whitening[j] = llt.matrixL().solve(Eigen::Matrix3d::Identity());
  }
  return whitening;
}

// Information of the 4 tilts: Schur complement of the per-pose angles in JᵀJ; also χ².
Eigen::Matrix4d tiltInformation(const std::vector<ceres::CostFunction*>& costs, const double* tilt_c,
                                const double* tilt_m, const std::vector<double>& phi, double* chi2) {
  Eigen::Matrix4d information = Eigen::Matrix4d::Zero();
  *chi2 = 0.0;
  for (std::size_t j = 0; j < costs.size(); ++j) {
    const double* parameters[3] = {tilt_c, tilt_m, &phi[j]};
    Eigen::Matrix<double, 3, 2, Eigen::RowMajor> Jc, Jm;
    Eigen::Vector3d Jp, e;
    double* jacobians[3] = {Jc.data(), Jm.data(), Jp.data()};
    costs[j]->Evaluate(parameters, e.data(), jacobians);
    *chi2 += e.squaredNorm();
    Eigen::Matrix<double, 3, 4> Jt;
    Jt << Jc, Jm;
    information += Jt.transpose() * Jt - Jt.transpose() * Jp * Jp.transpose() * Jt / Jp.squaredNorm();
  }
  return information;
}

// Maximum-likelihood refinement (axisResidual) of the tilts of Ac0, Am0 and the per-pose
// angles φ (eliminated by the Schur complement), and the tilts' covariance.
AxisAlignment refineAxisAlignment(const Eigen::Matrix3d& Ac0, const Eigen::Matrix3d& Am0,
                                  const std::vector<Eigen::Matrix3d>& R, const std::vector<Eigen::Matrix3d>& whitening,
                                  bool weighted, std::vector<double> phi) {
  const std::size_t n = R.size();
  double tilt_c[2] = {0.0, 0.0}, tilt_m[2] = {0.0, 0.0};
  ceres::Problem problem;
  std::vector<ceres::CostFunction*> costs;
  for (std::size_t j = 0; j < n; ++j) {
    costs.push_back(
        new ceres::AutoDiffCostFunction<AxisResidual, 3, 2, 2, 1>(new AxisResidual{&Ac0, &Am0, &R[j], &whitening[j]}));
    problem.AddResidualBlock(costs.back(), nullptr, tilt_c, tilt_m, &phi[j]);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.logging_type = ceres::SILENT;
  options.max_num_iterations = 30;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  double chi2 = 0.0;
  const Eigen::Matrix4d information = tiltInformation(costs, tilt_c, tilt_m, phi, &chi2);
  AxisAlignment alignment;
  alignment.camera = Ac0 * tiltXY(tilt_c[0], tilt_c[1]);
  alignment.target = Am0 * tiltXY(tilt_m[0], tilt_m[1]);
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(information);
  if (lu.isInvertible()) {
    alignment.covariance = lu.inverse();
    const int dof = static_cast<int>(3 * n) - static_cast<int>(n) - 4;
    if (!weighted && dof > 0) alignment.covariance *= chi2 / dof;  // σ² from the fit
  }
  return alignment;
}

}  // namespace

AxisAlignment estimateAxisAlignment(const std::vector<PoseObservation>& poses) {
  if (poses.size() < 2) throw std::invalid_argument("the rotation axis needs at least 2 poses");
  std::vector<Eigen::Matrix3d> R;
  R.reserve(poses.size());
  for (const PoseObservation& p : poses) R.emplace_back(toIsometry(p.cTm).linear());
  const Eigen::Vector3d axis_c = principalRotationAxis(R);
  Eigen::Vector3d axis_m = Eigen::Vector3d::Zero();
  for (const Eigen::Matrix3d& r : R) axis_m += r.transpose() * axis_c;

  const Eigen::Matrix3d Ac0 = alignZ(axis_c), Am0 = alignZ(axis_m);
  std::vector<double> phi(R.size());
  for (std::size_t j = 0; j < R.size(); ++j) phi[j] = angleAboutZ(Ac0.transpose() * R[j] * Am0);
  bool weighted = false;
  const std::vector<Eigen::Matrix3d> whitening = axisResidualWhitening(poses, Ac0, Am0, phi, &weighted);
  return refineAxisAlignment(Ac0, Am0, R, whitening, weighted, std::move(phi));
}

// Largest joint mismatch (rad or m) of a least-squares FKM pose still taken as a starting
// point: the nominal geometry of a robot not yet calibrated (offsets of a few degrees) often
// reproduces no joint reading exactly, but its best pose is close (0.001–0.053 rad on rendered
// H4 chains with 5° offsets), and the identification then refines it. A reading further off
// (a wrong column, a wrong unit) is reported.
constexpr double kStartingPoseJointMismatch = 0.1;

std::vector<Eigen::Isometry3d> effectorPosesByFkm(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                  const std::vector<PoseObservation>& poses) {
  const Eigen::VectorXd start = mechanism.referencePose(geometric);
  std::vector<Eigen::Isometry3d> bTe;
  std::string failed;
  for (const PoseObservation& p : poses) {
    const FkmResult fkm = mechanism.forwardKinematics(geometric, p.joints, start);
    if (!fkm.converged && !(fkm.max_joint_error <= kStartingPoseJointMismatch))
      failed += (failed.empty() ? "" : ", ") + p.id + " (" + fkm.message + ")";
    bTe.push_back(fkm.bTe);
  }
  if (!failed.empty())
    throw std::runtime_error("initial external parameters: the FKM did not converge for pose(s) " + failed);
  return bTe;
}

namespace {

using cd = std::complex<double>;

// φ_j: the measured rotation about the aligned axis.
std::vector<double> measuredAxisAngles(const AxisAlignment& alignment, const std::vector<PoseObservation>& poses) {
  std::vector<double> phi(poses.size());
  for (std::size_t j = 0; j < poses.size(); ++j)
    phi[j] = angleAboutZ(alignment.camera.transpose() * toIsometry(poses[j].cTm).linear() * alignment.target);
  return phi;
}

// Orients the axis so that the measured rotation φ follows the FKM's θ (z_B up); returns φ
// in the (possibly flipped) alignment.
std::vector<double> orientAxisAlongTheta(AxisAlignment& alignment, const std::vector<PoseObservation>& poses,
                                         const std::vector<double>& theta) {
  std::vector<double> phi = measuredAxisAngles(alignment, poses);
  double agreement = 0.0;
  for (std::size_t j = 0; j < poses.size(); ++j) agreement += wrap(phi[j] - phi[0]) * wrap(theta[j] - theta[0]);
  if (agreement >= 0.0) return phi;
  const Eigen::Matrix3d flip = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  alignment.camera = alignment.camera * flip;
  alignment.target = alignment.target * flip;
  // Tilts about the flipped frames: (δx, δy) -> (δx, −δy).
  const Eigen::Matrix4d G = Eigen::Vector4d(1.0, -1.0, 1.0, -1.0).asDiagonal();
  alignment.covariance = G * alignment.covariance * G;
  return measuredAxisAngles(alignment, poses);
}

// The aligned mounting's translations and ψ_BC: positions p_j = Rz(ψ_BC)(Rz(φ_j) u + v_j) + t_bc
// with v_j = Acᵀ·c t_m(j).
struct PlanarMounting {
  double psi_bc = 0.0;
  cd u{0.0, 0.0}, t{0.0, 0.0};
  double t_z = 0.0, u_z = 0.0;
};

// Base = axis-aligned camera frame: p_j − v_j = Rz(φ_j)·u.
PlanarMounting cameraFrameMounting(const std::vector<double>& phi, const std::vector<Eigen::Vector3d>& v,
                                   const std::vector<Eigen::Vector3d>& p) {
  const std::size_t n = phi.size();
  PlanarMounting m;
  for (std::size_t j = 0; j < n; ++j) m.u += std::polar(1.0, -phi[j]) * cd(p[j].x() - v[j].x(), p[j].y() - v[j].y());
  m.u /= static_cast<double>(n);
  double sum = 0.0;
  for (std::size_t j = 0; j < n; ++j) sum += p[j].z() - v[j].z();
  m.u_z = sum / static_cast<double>(n);
  return m;
}

// Linear complex least squares P_j = e^{iφ_j}·B + A·V_j + T, A = e^{iψ_BC}, B = A·u.
PlanarMounting axisAlignedMounting(const std::vector<double>& phi, const std::vector<Eigen::Vector3d>& v,
                                   const std::vector<Eigen::Vector3d>& p, double z_ME) {
  const std::size_t n = phi.size();
  Eigen::MatrixXcd M(static_cast<Eigen::Index>(n), 3);
  Eigen::VectorXcd rhs(static_cast<Eigen::Index>(n));
  for (std::size_t j = 0; j < n; ++j) {
    const auto r = static_cast<Eigen::Index>(j);
    M(r, 0) = std::polar(1.0, phi[j]);
    M(r, 1) = cd(v[j].x(), v[j].y());
    M(r, 2) = 1.0;
    rhs[r] = cd(p[j].x(), p[j].y());
  }
  const Eigen::VectorXcd x = M.colPivHouseholderQr().solve(rhs);
  PlanarMounting m;
  m.u_z = z_ME;
  m.psi_bc = std::arg(x[1]);
  m.u = x[0] * std::polar(1.0, -m.psi_bc);
  m.t = x[2];
  double sum = 0.0;
  for (std::size_t j = 0; j < n; ++j) sum += p[j].z() - v[j].z() - m.u_z;
  m.t_z = sum / static_cast<double>(n);
  return m;
}

}  // namespace

// Schönflies mechanisms (paper §4): the axis alignment, then ψ and the translations in closed
// form from the FKM effector poses at the nominal geometry.
ParameterSet estimateExternal(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                              const std::vector<PoseObservation>& poses, ExternalForm form,
                              ExternalParameterization& parameterization, double z_ME) {
  validatePoses(poses, mechanism.jointCount());
  if (!std::isfinite(z_ME)) throw std::invalid_argument("z_ME is not finite");
  if (mechanism.motionType() != MotionType::Schoenflies || form == ExternalForm::CameraOnEffector)
    return estimateMountingExternal(mechanism, geometric, poses, form, parameterization);
  AxisAlignment alignment = estimateAxisAlignment(poses);
  const std::vector<Eigen::Isometry3d> bTe = effectorPosesByFkm(mechanism, geometric, poses);

  const std::size_t n = poses.size();
  std::vector<double> theta(n);
  for (std::size_t j = 0; j < n; ++j) theta[j] = angleAboutZ(bTe[j].linear());
  const std::vector<double> phi = orientAxisAlongTheta(alignment, poses, theta);
  std::complex<double> psi_sum(0.0, 0.0);
  for (std::size_t j = 0; j < n; ++j) psi_sum += std::polar(1.0, theta[j] - phi[j]);
  const double psi_total = std::arg(psi_sum);  // ψ_BC + ψ_ME

  std::vector<Eigen::Vector3d> v(n), p(n);
  for (std::size_t j = 0; j < n; ++j) {
    v[j] = alignment.camera.transpose() * poses[j].cTm.head<3>();
    p[j] = bTe[j].translation();
  }
  PlanarMounting planar =
      form == ExternalForm::CameraFrame ? cameraFrameMounting(phi, v, p) : axisAlignedMounting(phi, v, p, z_ME);
  const double psi_me = wrap(psi_total - planar.psi_bc);

  parameterization = ExternalParameterization(form, alignment);
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity();
  bTc.linear() = rotZ(planar.psi_bc) * alignment.camera.transpose();
  bTc.translation() = Eigen::Vector3d(planar.t.real(), planar.t.imag(), planar.t_z);
  Eigen::Isometry3d mTe = Eigen::Isometry3d::Identity();
  mTe.linear() = alignment.target * rotZ(psi_me);
  mTe.translation() = alignment.target * Eigen::Vector3d(planar.u.real(), planar.u.imag(), planar.u_z);

  ParameterSet set = parameterization.parameters();
  set.setValues(parameterization.valuesFrom(bTc, mTe));
  return set;
}

}  // namespace mire::mechanism
