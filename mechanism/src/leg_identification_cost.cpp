// One pose's residual in the identification with legs (leg_identification_cost.hpp).
#include "leg_identification_cost.hpp"

#include <ceres/dynamic_numeric_diff_cost_function.h>

#include <Eigen/Cholesky>
#include <utility>

namespace mire::mechanism::detail {

namespace {

Eigen::Vector3d rotationLog(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

struct LegPoseFunctor {
  IdentificationModel model;
  std::shared_ptr<const FreeParameterMap> map;
  LegPoseTerms terms;

  bool operator()(double const* const* parameters, double* residuals) const {
    Eigen::VectorXd ambient(map->ambientCount());
    map->expand(parameters[0], ambient.data());
    return evaluateLegPose(model, ambient, parameters[1], terms, residuals);
  }
};

}  // namespace

Eigen::Matrix<double, 6, 6> targetWhitening(const PoseVector& cTm, const PoseCovariance& covariance) {
  // ∂ log(exp(r + δ) exp(r)ᵀ) / ∂δ by central differences (the map is smooth away from |r| = π).
  const Eigen::Vector3d r = cTm.tail<3>();
  const Eigen::Matrix3d R = fromRotationVector(r);
  constexpr double kStep = 1e-7;
  Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d step = kStep * Eigen::Vector3d::Unit(k);
    T.block<3, 1>(3, 3 + k) = (rotationLog(fromRotationVector(r + step) * R.transpose()) -
                               rotationLog(fromRotationVector(r - step) * R.transpose())) /
                              (2.0 * kStep);
  }
  const Eigen::Matrix<double, 6, 6> sigma = T * covariance * T.transpose();
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(sigma);
  return llt.matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
}

bool evaluateLegPose(const IdentificationModel& model, const Eigen::VectorXd& ambient, const double* pose,
                     const LegPoseTerms& terms, double* residuals) {
  const Mechanism& m = *model.mechanism;
  const int G = model.geometricCount();
  const Eigen::VectorXd g = ambient.head(G), e = ambient.tail(model.external.size());
  const Eigen::Isometry3d bTe = m.poseToTransform(Eigen::Map<const Eigen::VectorXd>(pose, m.poseDof()));
  const IkmResult ikm = m.inverseKinematics(g, bTe);
  if (!ikm.reachable()) return false;
  const int J = m.jointCount();
  for (int i = 0; i < J; ++i) residuals[i] = (terms.joints[i] - ikm.joints[i]) / terms.joint_sigma;
  int row = J;
  if (!terms.legs.empty()) {
    const std::vector<LegSegment> segments = m.legSegments(g, bTe);
    if (segments.empty()) return false;
    const Eigen::Isometry3d cTb = model.external.baseFromCamera(e).inverse();
    for (std::size_t k = 0; k < terms.legs.size(); ++k) {
      const LegSegment& s = segments[static_cast<std::size_t>(terms.legs[k].leg)];
      const support::Line3d predicted = support::Line3d::throughPoints(cTb * s.from, cTb * s.to);
      Eigen::Map<Eigen::Vector4d>(residuals + row) =
          terms.leg_whitening[k] * support::lineDifference(predicted, terms.legs[k].line);
      row += 4;
    }
  }
  if (terms.cTm) {
    const Eigen::Isometry3d predicted = model.external.targetInCamera(e, bTe);
    Eigen::Matrix<double, 6, 1> d;
    d << predicted.translation() - terms.cTm->translation(),
        rotationLog(predicted.linear() * terms.cTm->linear().transpose());
    Eigen::Map<Eigen::Matrix<double, 6, 1>>(residuals + row) = terms.target_whitening * d;
  }
  return true;
}

std::unique_ptr<ceres::CostFunction> makeLegPoseCost(const IdentificationModel& model,
                                                     std::shared_ptr<const FreeParameterMap> map, LegPoseTerms terms) {
  const int rows = terms.residualCount(model.mechanism->jointCount());
  const int free_count = map->freeCount();
  auto cost = std::make_unique<ceres::DynamicNumericDiffCostFunction<LegPoseFunctor, ceres::CENTRAL>>(
      new LegPoseFunctor{model, std::move(map), std::move(terms)});
  cost->AddParameterBlock(free_count);
  cost->AddParameterBlock(model.mechanism->poseDof());
  cost->SetNumResiduals(rows);
  return cost;
}

}  // namespace mire::mechanism::detail
