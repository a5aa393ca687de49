#pragma once
// The held-out check of `fkm --frame camera` against a simulated campaign's truth: the RMS
// position error and its ratio to the RMS predicted σ (doc/mechanisms.md, "Limits").
#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <string>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/support/csv.hpp"

namespace mire::test {

struct HeldOutScore {
  std::size_t rows = 0;
  double rms_m = 0.0;  // RMS position error against the truth
  double ratio = 0.0;  // RMS error / RMS predicted σ
};

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

}  // namespace mire::test
