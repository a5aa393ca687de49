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
using LegJet = ceres::Jet<double, kPoseEntries + kMaxLegValues>;
using ExternalJet = ceres::Jet<double, kExternalStride>;

// Appends `count` values from global index `first` (−1: absent) and returns their local index.
int gather(int first, int count, std::vector<int>* global) {
  if (first < 0) return -1;
  const int local = static_cast<int>(global->size());
  for (int k = 0; k < count; ++k) global->push_back(first + k);
  return local;
}

DescribedJointCost::LocalLeg localLeg(const DescribedLeg& leg) {
  DescribedJointCost::LocalLeg out{leg, leg, {}};
  out.local.base = gather(leg.base, 3, &out.global);
  out.local.tilt = gather(leg.tilt, 2, &out.global);
  out.local.arm = gather(leg.arm, 3, &out.global);
  out.local.rod = gather(leg.rod, 1, &out.global);
  out.local.platform = gather(leg.platform, 3, &out.global);
  out.local.offset = gather(leg.offset, 1, &out.global);
  out.local.gain = gather(leg.gain, 1, &out.global);
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
  LegJet values[kMaxLegValues], Rj[9], tj[3];
  const int count = static_cast<int>(leg.global.size());
  for (int k = 0; k < count; ++k) values[k] = LegJet(g[leg.global[k]], kPoseEntries + k);
  for (int k = 0; k < 9; ++k) Rj[k] = LegJet(R[k], k);
  for (int k = 0; k < 3; ++k) tj[k] = LegJet(t[k], 9 + k);
  LegJet reading;
  if (!DescribedKinematics::legJoint(leg.local, values, Rj, tj, &reading)) return false;
  *q = reading.a;
  for (int k = 0; k < kPoseEntries; ++k) d_pose[k] = reading.v[k];
  for (int k = 0; k < count; ++k) d_local[k] = reading.v[kPoseEntries + k];
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
