#pragma once
// What a user applies from the end-to-end σ studies (doc/studies/, the chain studies): the camera-
// frame position `mire fkm --frame camera` predicts from the true joints with the identified
// model, against the true position, and its error over the σ `fkm` prints (the parameters'
// covariance propagated; benchmarks/bench_chain.cpp).
#include "chain_statistics.hpp"

#include "mire/mechanism/prediction.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace mire::bench {

struct PredictionScores {
  Samples z;                        // tx ty tz: predicted − true position over its σ
  std::vector<double> mahalanobis;  // per pose: 3-D Mahalanobis / 3
  std::vector<double> largest_mm;   // per chain: the largest position error
};

// One chain: `joints[j]` the true encoder readings of pose j, `cTm[j]` its true target pose.
inline void scorePredictions(const mechanism::PredictionModel& model, const std::vector<Eigen::VectorXd>& joints,
                             const std::vector<Eigen::Isometry3d>& cTm, PredictionScores& scores) {
  static const char* const components[3] = {"tx", "ty", "tz"};
  double largest = 0.0;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const mechanism::PosePrediction predicted = mechanism::predictPose(model, joints[j]);
    if (!predicted.converged) {
      largest = std::numeric_limits<double>::infinity();
      continue;
    }
    const Eigen::Vector3d error = predicted.cTm.head<3>() - cTm[j].translation();
    const Eigen::Matrix3d covariance = predicted.cTm_covariance.topLeftCorner<3, 3>();
    largest = std::max(largest, 1e3 * error.norm());
    for (int k = 0; k < 3; ++k) scores.z[components[k]].push_back(error[k] / std::sqrt(covariance(k, k)));
    scores.mahalanobis.push_back(mahalanobis(error, covariance) / 3.0);
  }
  scores.largest_mm.push_back(largest);
}

inline void printPredictionScores(const PredictionScores& s) {
  std::printf(
      "  camera-frame position predicted from the true joints (mire fkm): largest error per chain median %.3f mm, "
      "worst %.3f mm; error/sigma RMS tx %.3f, ty %.3f, tz %.3f; 3-D Mahalanobis / 3 mean %.3f (1 if honest)\n",
      median(s.largest_mm), *std::max_element(s.largest_mm.begin(), s.largest_mm.end()), rms(s.z.at("tx")),
      rms(s.z.at("ty")), rms(s.z.at("tz")), mean(s.mahalanobis));
}

}  // namespace mire::bench
