// The leg-by-leg Jacobian of a described mechanism's identification residual
// (described_joint_cost.hpp).
#include "described_joint_cost.hpp"

#include <ceres/jet.h>

#include <stdexcept>
#include <utility>

namespace mire::mechanism::detail {

namespace {

constexpr int kPoseEntries = 12;     // bTe's R (column-major) and t
constexpr int kMaxLegValues = 14;    // base 3, tilt 2, arm 3, rod, platform 3, offset, gain
constexpr int kExternalStride = 12;  // ξe's derivatives per pass (one pass for every form today)
// The actuation s_i(w, tilt, arm, rod) is differentiated over its own 9 inputs, in fixed slots;
// base, platform, bTe, offset and gain enter through w = t + R·p − A and q̄ = (s − q0)/g, whose
// derivatives are plain products (doc/mechanisms.md, "Described mechanisms").
constexpr int kSlotW = 0, kSlotTilt = 3, kSlotArm = 5, kSlotRod = 8, kActuationInputs = 9;
using ActuationJet = ceres::Jet<double, kActuationInputs>;
using ExternalJet = ceres::Jet<double, kExternalStride>;

// Appends `count` values from global index `first` (−1: absent) and returns their local index.
int gather(int first, int count, std::vector<int>* global) {
  if (first < 0) return -1;
  const int local = static_cast<int>(global->size());
  for (int k = 0; k < count; ++k) global->push_back(first + k);
  return local;
}

DescribedJointCost::LocalLeg localLeg(const DescribedLeg& leg) {
  DescribedJointCost::LocalLeg out;
  out.leg = leg;
  out.local.base = gather(leg.base, 3, &out.global);
  out.local.tilt = gather(leg.tilt, 2, &out.global);
  out.local.arm = gather(leg.arm, 3, &out.global);
  out.local.rod = gather(leg.rod, 1, &out.global);
  out.local.platform = gather(leg.platform, 3, &out.global);
  out.local.offset = gather(leg.offset, 1, &out.global);
  out.local.gain = gather(leg.gain, 1, &out.global);
  out.actuation = leg;
  out.actuation.tilt = leg.tilt >= 0 ? kSlotTilt : -1;
  out.actuation.arm = leg.arm >= 0 ? kSlotArm : -1;
  out.actuation.rod = leg.rod >= 0 ? kSlotRod : -1;
  return out;
}

}  // namespace

DescribedJointCost::DescribedJointCost(const DescribedKinematics& kinematics, int geometric_count,
                                       ExternalParameterization external, const PoseVector& cTm,
                                       Eigen::VectorXd measured_joints, Eigen::MatrixXd whitening)
    : external_(std::move(external)),
      pose_(external_.prepare(cTm)),
      joints_(std::move(measured_joints)),
      whitening_(std::move(whitening)),
      translation_(!kinematics.full) {
  for (const DescribedLeg& leg : kinematics.legs) legs_.push_back(localLeg(leg));
  set_num_residuals(static_cast<int>(joints_.size()));
  mutable_parameter_block_sizes()->push_back(geometric_count);
  mutable_parameter_block_sizes()->push_back(external_.size());
}

bool DescribedJointCost::legDerivatives(const LocalLeg& leg, const double* g, const double* R, const double* t,
                                        double* q, double* d_pose, double* d_local) const {
  const DescribedLeg& at = leg.leg;
  const double* A = g + at.base;
  const double* p = g + at.platform;
  ActuationJet inputs[kActuationInputs];
  for (int k = 0; k < 3; ++k)
    inputs[kSlotW + k] = ActuationJet(t[k] + R[k] * p[0] + R[3 + k] * p[1] + R[6 + k] * p[2] - A[k], kSlotW + k);
  if (at.tilt >= 0)
    for (int k = 0; k < 2; ++k) inputs[kSlotTilt + k] = ActuationJet(g[at.tilt + k], kSlotTilt + k);
  if (at.arm >= 0)
    for (int k = 0; k < 3; ++k) inputs[kSlotArm + k] = ActuationJet(g[at.arm + k], kSlotArm + k);
  if (at.rod >= 0) inputs[kSlotRod] = ActuationJet(g[at.rod], kSlotRod);
  ActuationJet s;
  if (!DescribedKinematics::actuation(leg.actuation, inputs, inputs + kSlotW, &s)) return false;
  // q̄ = (s − q0)/g: ∂q̄/∂s = 1/g, ∂q̄/∂q0 = −1/g, ∂q̄/∂g = −q̄/g.
  const double gain = at.gain >= 0 ? g[at.gain] : 1.0;
  *q = (s.a - g[at.offset]) / gain;
  const double dq_ds = 1.0 / gain;
  double dq_dw[3];
  for (int k = 0; k < 3; ++k) dq_dw[k] = dq_ds * s.v[kSlotW + k];
  // w = t + R·p − A: ∂w_k/∂t_k = 1, ∂w_k/∂R(k, m) = p_m, ∂w/∂p = R, ∂w/∂A = −I.
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 3; ++k) d_pose[3 * m + k] = dq_dw[k] * p[m];
  for (int k = 0; k < 3; ++k) d_pose[9 + k] = dq_dw[k];
  const LocalLeg::Slots& local = leg.local;
  for (int k = 0; k < 3; ++k) {
    d_local[local.base + k] = -dq_dw[k];
    d_local[local.platform + k] = R[3 * k] * dq_dw[0] + R[3 * k + 1] * dq_dw[1] + R[3 * k + 2] * dq_dw[2];
  }
  if (local.tilt >= 0)
    for (int k = 0; k < 2; ++k) d_local[local.tilt + k] = dq_ds * s.v[kSlotTilt + k];
  if (local.arm >= 0)
    for (int k = 0; k < 3; ++k) d_local[local.arm + k] = dq_ds * s.v[kSlotArm + k];
  if (local.rod >= 0) d_local[local.rod] = dq_ds * s.v[kSlotRod];
  d_local[local.offset] = -dq_ds;
  if (local.gain >= 0) d_local[local.gain] = -*q / gain;
  return true;
}

void DescribedJointCost::effectorDerivatives(const double* external, double* Rt, double* d_external) const {
  const int size = external_.size();
  std::vector<ExternalJet> values(static_cast<std::size_t>(size));
  for (int first = 0; first < size; first += kExternalStride) {
    for (int k = 0; k < size; ++k)
      values[k] =
          k >= first && k < first + kExternalStride ? ExternalJet(external[k], k - first) : ExternalJet(external[k]);
    ExternalJet entries[kPoseEntries];
    external_.effectorInBase(values.data(), pose_, entries, entries + 9);
    for (int m = 0; m < kPoseEntries; ++m) {
      Rt[m] = entries[m].a;
      for (int k = first; k < size && k < first + kExternalStride; ++k)
        d_external[m * size + k] = entries[m].v[k - first];
    }
  }
}

bool DescribedJointCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* g = parameters[0];
  const int n = static_cast<int>(joints_.size());
  const int geometric = parameter_block_sizes()[0], external = parameter_block_sizes()[1];
  const bool derivatives = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  double Rt[kPoseEntries];
  // Derivative buffers sized only when asked for: Ceres evaluates each trial step for its cost alone.
  Eigen::Matrix<double, kPoseEntries, Eigen::Dynamic, Eigen::RowMajor> d_external(kPoseEntries,
                                                                                  derivatives ? external : 0);
  if (derivatives)
    effectorDerivatives(parameters[1], Rt, d_external.data());
  else
    external_.effectorInBase(parameters[1], pose_, Rt, Rt + 9);
  if (translation_) {  // the plate never turns: X's rotation does not move the joints (R = I)
    for (int k = 0; k < 9; ++k) Rt[k] = k % 4 == 0 ? 1.0 : 0.0;
    if (derivatives) d_external.topRows(9).setZero();
  }

  Eigen::VectorXd q(n);
  Eigen::Matrix<double, Eigen::Dynamic, kPoseEntries, Eigen::RowMajor> d_pose(derivatives ? n : 0, kPoseEntries);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> d_geometric =
      Eigen::MatrixXd::Zero(derivatives ? n : 0, geometric);
  for (int i = 0; i < n; ++i) {
    const LocalLeg& leg = legs_[i];
    if (!derivatives) {
      if (!DescribedKinematics::legJoint(leg.leg, g, Rt, Rt + 9, &q[i])) return false;
      continue;
    }
    double d_local[kMaxLegValues];
    if (!legDerivatives(leg, g, Rt, Rt + 9, &q[i], d_pose.row(i).data(), d_local)) return false;
    for (std::size_t k = 0; k < leg.global.size(); ++k) d_geometric(i, leg.global[k]) = d_local[k];
  }
  Eigen::Map<Eigen::VectorXd>(residuals, n) = whitening_ * (joints_ - q);
  if (!derivatives) return true;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  if (jacobians[0] != nullptr) Eigen::Map<RowMajor>(jacobians[0], n, geometric) = -whitening_ * d_geometric;
  if (jacobians[1] != nullptr) Eigen::Map<RowMajor>(jacobians[1], n, external) = -whitening_ * (d_pose * d_external);
  return true;
}

}  // namespace mire::mechanism::detail
