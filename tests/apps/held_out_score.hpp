#pragma once
// The held-out check of `fkm --frame camera` against a simulated campaign's truth: the RMS
// position error and its ratio to the RMS predicted σ (doc/mechanisms.md, "Limits").
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

namespace mire::test {

struct HeldOutScore {
  std::size_t rows = 0;
  double rms_m = 0.0;  // RMS position error against the truth
  double ratio = 0.0;  // RMS error / RMS predicted σ
};

struct HeldOutPrediction {
  double rms_m = 0.0;  // RMS camera-frame position error against the truth
  double ratio = 0.0;  // RMS error / RMS predicted σ
};

// predictPose() of `model` at the joints of poses [first, end) against the true cTm of pose j,
// `true_cTm(j)` (a fixed camera's or one on the effector: the campaigns differ only there).
inline HeldOutPrediction heldOutPrediction(const mechanism::PredictionModel& model,
                                           const std::vector<mechanism::PoseObservation>& poses, std::size_t first,
                                           const std::function<Eigen::Isometry3d(std::size_t)>& true_cTm) {
  double err2 = 0, sig2 = 0;
  std::size_t n = 0;
  for (std::size_t j = first; j < poses.size(); ++j, ++n) {
    const mechanism::PosePrediction p = mechanism::predictPose(model, poses[j].joints);
    EXPECT_TRUE(p.converged) << "pose " << j << ": " << p.message;
    err2 += (p.cTm.head<3>() - true_cTm(j).translation()).squaredNorm();
    sig2 += p.cTm_covariance.topLeftCorner<3, 3>().trace();
  }
  return {n ? std::sqrt(err2 / static_cast<double>(n)) : 0.0, sig2 > 0 ? std::sqrt(err2 / sig2) : 0.0};
}

// `predicted_csv`: fkm --frame camera output whose pose ids are the campaign's (1-based).
inline HeldOutScore scoreHeldOutPositions(const std::filesystem::path& predicted_csv, const datasets::Campaign& c) {
  const support::CsvTable table = support::readCsv(predicted_csv);
  double err2 = 0, sig2 = 0;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const std::size_t j = std::stoul(table.rows[r][table.column("pose_id")]) - 1;
    const Eigen::Isometry3d truth = c.bTc.inverse() * c.bTe.at(j) * c.mTe.inverse();
    const Eigen::Vector3d t(table.number(r, table.column("tx_m")), table.number(r, table.column("ty_m")),
                            table.number(r, table.column("tz_m")));
    err2 += (t - truth.translation()).squaredNorm();
    for (const char* s : {"sigma_tx_mm", "sigma_ty_mm", "sigma_tz_mm"})
      sig2 += std::pow(table.number(r, table.column(s)) * 1e-3, 2);
  }
  HeldOutScore score;
  score.rows = table.rows.size();
  score.rms_m = score.rows ? std::sqrt(err2 / static_cast<double>(score.rows)) : 0.0;
  score.ratio = sig2 > 0 ? std::sqrt(err2 / sig2) : 0.0;
  return score;
}

// `mire fkm` of `held_joints.csv` in `dir` (base frame) with `id.yaml`, then `mire ikm` of those
// poses: the joints come back to 1e-8 (GoogleTest assertions).
inline void expectFkmIkmRoundTrip(const TempDir& dir, std::size_t rows) {
  const std::filesystem::path d = dir.path();
  ASSERT_EQ(runMireIn(dir, "fkm --params " + (d / "id.yaml").string() + " --joints " +
                               (d / "held_joints.csv").string() + " -o " + (d / "effector.csv").string()),
            0)
      << readText(d / "stderr.txt");
  ASSERT_EQ(runMireIn(dir, "ikm --params " + (d / "id.yaml").string() + " --poses " + (d / "effector.csv").string() +
                               " -o " + (d / "commands.csv").string()),
            0)
      << readText(d / "stderr.txt");
  const support::CsvTable commands = support::readCsv(d / "commands.csv");
  const support::CsvTable held = support::readCsv(d / "held_joints.csv");
  ASSERT_EQ(commands.rows.size(), rows);
  for (std::size_t r = 0; r < commands.rows.size(); ++r)
    for (std::size_t k = 1; k < held.header.size(); ++k)
      EXPECT_NEAR(commands.number(r, commands.column(held.header[k])), held.number(r, k), 1e-8);
}

}  // namespace mire::test
