#pragma once
// The identified base frame in the true one: an identification fixes its frame by its gauge (the
// effector point and the base origin trade off on a translating robot), so the tests that compare
// with a simulated true robot align the frames rigidly (Umeyama, no scale) on the identification
// poses: the identified model's FKM of the encoder readings onto the true effector positions.
#include <Eigen/Geometry>

#include <filesystem>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::test {

inline Eigen::Isometry3d identifiedToTrue(const std::filesystem::path& id_yaml, const datasets::Campaign& c,
                                          std::size_t count) {
  const mechanism::LoadedPredictionModel loaded = mechanism::loadPredictionModel(id_yaml);
  Eigen::Matrix3Xd identified(3, static_cast<Eigen::Index>(count)), truth(3, static_cast<Eigen::Index>(count));
  for (std::size_t j = 0; j < count; ++j) {
    const mechanism::PosePrediction p = mechanism::predictPose(loaded.model, c.poses[j].joints);
    identified.col(static_cast<Eigen::Index>(j)) = p.pose.head<3>();
    truth.col(static_cast<Eigen::Index>(j)) = c.bTe[j].translation();
  }
  return Eigen::Isometry3d(Eigen::umeyama(identified, truth, false));
}

}  // namespace mire::test
