#pragma once
// Templated pose chain of ExternalParameterization (eq. 3), usable with ceres::Jet.
#include <ceres/rotation.h>

#include <cmath>

#include "mire/mechanism/detail/matrix3.hpp"

namespace mire::mechanism {

template <class T>
void ExternalParameterization::effectorInBase(const T* external, const T* cTm, T* R, T* t) const {
  T cRm[9];
  ceres::AngleAxisToRotationMatrix(cTm + 3, ceres::ColumnMajorAdapter3x3(cRm));
  chain(external, cRm, cTm, R, t);
}

template <class T>
void ExternalParameterization::effectorInBaseFromMeasured(const T* external, const double* cRm, const double* ctm, T* R,
                                                          T* t) const {
  chain(external, cRm, ctm, R, t);
}

template <class T>
void ExternalParameterization::effectorInBase(const T* external, const PreparedPose& pose, T* R, T* t) const {
  if (form_ == ExternalForm::Full || form_ == ExternalForm::CameraOnEffector) {
    chain(external, pose.cRm.data(), pose.ctm.data(), R, t);
    return;
  }
  using std::cos;
  using std::sin;
  const T* me = form_ == ExternalForm::AxisAligned ? external + 4 : external;
  const Eigen::Matrix3d& M = pose.M;
  // A = M·Rz(psi_ME) (columns 0, 1 mix), a = M·u + v.
  const T cm = cos(me[3]), sm = sin(me[3]);
  T A[9], a[3];
  for (int r = 0; r < 3; ++r) {
    A[r] = M(r, 0) * cm + M(r, 1) * sm;
    A[3 + r] = M(r, 1) * cm - M(r, 0) * sm;
    A[6 + r] = T(M(r, 2));
    a[r] = M(r, 0) * me[0] + M(r, 1) * me[1] + M(r, 2) * me[2] + pose.v[r];
  }
  if (form_ == ExternalForm::CameraFrame) {
    for (int k = 0; k < 9; ++k) R[k] = A[k];
    for (int k = 0; k < 3; ++k) t[k] = a[k];
    return;
  }
  // Rz(psi_BC)·(rows 0, 1 mix).
  const T cb = cos(external[3]), sb = sin(external[3]);
  for (int c = 0; c < 3; ++c) {
    R[3 * c] = cb * A[3 * c] - sb * A[3 * c + 1];
    R[3 * c + 1] = sb * A[3 * c] + cb * A[3 * c + 1];
    R[3 * c + 2] = A[3 * c + 2];
  }
  t[0] = cb * a[0] - sb * a[1] + external[0];
  t[1] = sb * a[0] + cb * a[1] + external[1];
  t[2] = a[2] + external[2];
}

template <class T, class S>
void ExternalParameterization::chain(const T* external, const S* cRm, const S* ctm, T* R, T* t) const {
  // camera_ / target_ hold Ac, Am column-major (see external.cpp).
  if (form_ == ExternalForm::CameraOnEffector) {
    // bTe = bTm · cTm⁻¹ · eTc⁻¹ with eTc = (Rec, tec), bTm = (Rbm, tbm):
    // bRe = Rbm · cRmᵀ · Recᵀ,  bte = Rbm · cRmᵀ · (−Recᵀ·tec − ctm) + tbm.
    T Rec[9], Rbm[9];
    ceres::AngleAxisToRotationMatrix(external + 3, ceres::ColumnMajorAdapter3x3(Rec));
    ceres::AngleAxisToRotationMatrix(external + 9, ceres::ColumnMajorAdapter3x3(Rbm));
    T Rce[9], Rmc[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        Rce[3 * c + r] = Rec[3 * r + c];
        Rmc[3 * c + r] = T(cRm[3 * r + c]);
      }
    T tce[3];
    detail::apply3(Rce, external, tce);
    for (int k = 0; k < 3; ++k) tce[k] = -tce[k] - ctm[k];
    T Rbc[9], tb[3];
    detail::multiply3(Rbm, Rmc, Rbc);
    detail::multiply3(Rbc, Rce, R);
    detail::apply3(Rbc, tce, tb);
    for (int k = 0; k < 3; ++k) t[k] = tb[k] + external[6 + k];
    return;
  }
  if (form_ == ExternalForm::Full) {
    // bTe = cTb⁻¹ · cTm · eTm⁻¹ with cTb = (Rcb, tcb), eTm = (Rem, tem).
    T Rcb[9], Rem[9];
    ceres::AngleAxisToRotationMatrix(external + 3, ceres::ColumnMajorAdapter3x3(Rcb));
    ceres::AngleAxisToRotationMatrix(external + 9, ceres::ColumnMajorAdapter3x3(Rem));
    T Rbc[9], Rme[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        Rbc[3 * c + r] = Rcb[3 * r + c];
        Rme[3 * c + r] = Rem[3 * r + c];
      }
    T tme[3];  // −Remᵀ tem
    detail::apply3(Rme, external + 6, tme);
    for (T& v : tme) v = -v;
    T Rce[9], tce[3];
    detail::multiply3(cRm, Rme, Rce);
    detail::apply3(cRm, tme, tce);
    for (int k = 0; k < 3; ++k) tce[k] += ctm[k] - external[k];  // cTe translation − tcb
    detail::multiply3(Rbc, Rce, R);
    detail::apply3(Rbc, tce, t);
    return;
  }

  // Aligned forms: mTe = [Am·Rz(psi_ME), Am·(x_ME, y_ME, z_ME)].
  const T* me = form_ == ExternalForm::AxisAligned ? external + 4 : external;
  T Rz_me[9], Rme[9], tme[3];
  detail::rotationZ(me[3], Rz_me);
  detail::multiply3(target_, Rz_me, Rme);
  detail::apply3(target_, me, tme);
  T Rce[9], tce[3];
  detail::multiply3(cRm, Rme, Rce);
  detail::apply3(cRm, tme, tce);
  for (int k = 0; k < 3; ++k) tce[k] += ctm[k];

  // bTc rotation: Rz(psi_BC)·Acᵀ (AxisAligned) or Acᵀ (CameraFrame).
  T AcT[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) AcT[3 * c + r] = T(camera_[3 * r + c]);
  if (form_ == ExternalForm::AxisAligned) {
    T Rz_bc[9], Rbc[9];
    detail::rotationZ(external[3], Rz_bc);
    detail::multiply3(Rz_bc, AcT, Rbc);
    detail::multiply3(Rbc, Rce, R);
    detail::apply3(Rbc, tce, t);
    for (int k = 0; k < 3; ++k) t[k] += external[k];
  } else {
    detail::multiply3(AcT, Rce, R);
    detail::apply3(AcT, tce, t);
  }
}

}  // namespace mire::mechanism
