// The pose chain bTe = bTc · cTm · mTe (eq. 3) in its three forms: the prepared (autodiff)
// path agrees with the transform path, and valuesFrom() inverts baseFromCamera/targetFromEffector.
#include <gtest/gtest.h>

#include <random>

#include "mire/mechanism/external.hpp"

namespace mire::mechanism {
namespace {

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

TEST(External, PreparedChainMatchesTransforms) {
  std::mt19937 rng(21);
  std::normal_distribution<double> n;
  const AxisAlignment alignment{randomRotation(rng), randomRotation(rng), Eigen::Matrix4d::Zero()};
  for (ExternalForm form : {ExternalForm::AxisAligned, ExternalForm::Full, ExternalForm::CameraFrame}) {
    const ExternalParameterization chain(form, alignment);
    for (int trial = 0; trial < 10; ++trial) {
      Eigen::VectorXd e(chain.size());
      for (Eigen::Index k = 0; k < e.size(); ++k) e[k] = 0.3 * n(rng);
      PoseVector cTm;
      cTm << n(rng), n(rng), n(rng), n(rng), n(rng), n(rng);
      const Eigen::Isometry3d expected = chain.baseFromCamera(e) * toIsometry(cTm) * chain.targetFromEffector(e);
      const Eigen::Isometry3d direct = chain.effectorInBase(e, cTm);
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      chain.effectorInBase(e.data(), chain.prepare(cTm), R.data(), t.data());
      EXPECT_LT((direct.matrix() - expected.matrix()).norm(), 1e-12) << externalFormName(form);
      EXPECT_LT((R - expected.linear()).norm(), 1e-12) << externalFormName(form);
      EXPECT_LT((t - expected.translation()).norm(), 1e-12) << externalFormName(form);
      if (form == ExternalForm::Full) {
        const Eigen::VectorXd back = chain.valuesFrom(chain.baseFromCamera(e), chain.targetFromEffector(e));
        const ExternalParameterization& c = chain;
        EXPECT_LT((c.effectorInBase(back, cTm).matrix() - expected.matrix()).norm(), 1e-12);
      }
    }
  }
}

TEST(External, RejectsNonRotationAlignment) {
  AxisAlignment bad;
  bad.camera(0, 0) = 2.0;
  EXPECT_THROW(ExternalParameterization(ExternalForm::AxisAligned, bad), std::invalid_argument);
}

TEST(External, AxisNeedsRotation) {
  std::vector<PoseObservation> poses(3);
  for (std::size_t j = 0; j < poses.size(); ++j) {
    poses[j].id = std::to_string(j);
    poses[j].cTm << 0.01 * j, 0.0, 0.6, 0.0, 0.0, 0.001 * j;  // < 2° of rotation
  }
  EXPECT_THROW(estimateAxisAlignment(poses), std::invalid_argument);
}

}  // namespace
}  // namespace mire::mechanism
