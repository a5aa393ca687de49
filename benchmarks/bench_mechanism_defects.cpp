// Unmodelled defects (doc/mechanisms.md): a Delta whose legs differ and whose plate tilts, a
// hexapod with encoder gains and joint eccentricities. Identified with their models, then
// V3 (two straight-line motions rebuilt with the model's FKM, paper §6.1) and the positioning
// test (a 100 mm square commanded through the model's IKM, reached by the true robot; RMS of
// the 3-D side-length errors, frame-invariant), with the nominal and the identified parameters.
// Beside each defective robot, the diagnosis rows: the FLOOR (the same geometric errors and
// campaign noise on a robot the model represents exactly: what the identification noise alone
// leaves), each defect alone, and the defective robot identified from noise-free poses (what
// the model's own error alone leaves).
// Usage: bench_mechanism_defects [seeds=5] [wide_spread=1.5] [wide_reach=1.875]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"

using namespace mire::mechanism;
using namespace mire::datasets;

namespace {

struct Scores {
  double v3 = 0, square = 0;
};

struct Outcome {
  Scores before, after;
  double joint_rms = 0, chi2_dof = 0;
};

// The true robot's encoder readings along the two V3 lines (datasets::straightLinePoses, 21
// poses each; `reach` scales their extent).
std::vector<std::vector<Eigen::VectorXd>> recordLines(const TrueRobot& robot, double reach) {
  std::vector<std::vector<Eigen::VectorXd>> lines;
  for (const auto& poses : straightLinePoses(robot, 21, reach)) {
    std::vector<Eigen::VectorXd> q;
    for (const Eigen::VectorXd& X : poses) {
      q.push_back(robot.joints(X));
      if (q.back().size() == 0) throw std::runtime_error("V3 line leaves the true robot's workspace");
    }
    lines.push_back(q);
  }
  return lines;
}

Scores score(const TrueRobot& robot, const Mechanism& m, const Eigen::VectorXd& g, double reach) {
  Scores s;
  const StraightnessResult v3 = straightnessCriterion(m, g, recordLines(robot, reach));
  s.v3 = v3.ok ? v3.v3_m : NAN;
  double sq = 0;
  for (const double side : positioningTestSides(robot, m, g)) sq += side * side;
  s.square = std::sqrt(sq / 4);
  return s;
}

struct Case {
  std::string robot, model;
  std::function<TrueRobot(unsigned)> make;
  bool noisy = true;    // pose noise 0.2 mm / 0.03°, or none (then the identification is unweighted)
  double spread = 1.0;  // protocol positions spread about the reference pose
  double reach = 1.0;   // V3 lines' half-extents scale
  int extra = 0;        // random poses added to the protocol (inside its volume)
};

// One campaign of the case's robot identified with its model; V3 and the square before and after.
Outcome study(const Case& k, unsigned seed) {
  const TrueRobot robot = k.make(seed);
  const std::string& model = k.model;
  const bool noisy = k.noisy;
  Campaign c = simulateDefectiveCampaign(robot, model, seed, noisy ? 0.2e-3 : 0.0, noisy ? 0.03 * kCampaignDeg : 0.0,
                                         k.extra, k.spread);
  if (!noisy)
    for (PoseObservation& p : c.poses) p.covariance.reset();
  const RegisteredModel reg = makeRegisteredModel(model);
  IdentificationModel initial = makeInitialModel(reg.mechanism, reg.nominal, c.poses, reg.external_form);
  fixGauge(initial, c.poses);
  const IdentificationResult result = identify(initial, c.poses);
  const bool translation = reg.mechanism->motionType() == MotionType::Translation;
  Outcome o;
  o.before = score(robot, *reg.mechanism, reg.nominal.values(), k.reach);
  o.after = score(robot, *reg.mechanism, result.model.geometricValues(), k.reach);
  o.joint_rms = result.rms_joint_residual * (translation ? 57.29578 : 1e3);
  const double dof = static_cast<double>(c.poses.size()) * reg.mechanism->jointCount() - result.free_names.size();
  o.chi2_dof = result.weighted ? result.chi2 / dof : NAN;
  return o;
}

struct Summary {
  double v3_before = 0, v3_after = 0, sq_before = 0, sq_after = 0, v3_worst = -1e9, sq_worst = -1e9;
  int n = 0;
};

double change(double before, double after) { return 100 * (after / before - 1); }

void printRow(const Case& k, unsigned seed, const Outcome& o) {
  std::printf(
      "%-40s %-19s seed %2u: joint RMS %.4f %s chi2/dof %5.2f; V3 %.4f -> %.4f mm (%+4.0f %%); square %.4f -> "
      "%.4f mm (%+4.0f %%)\n",
      k.robot.c_str(), k.model.c_str(), seed, o.joint_rms, k.model.rfind("delta", 0) == 0 ? "deg" : "mm", o.chi2_dof,
      o.before.v3 * 1e3, o.after.v3 * 1e3, change(o.before.v3, o.after.v3), o.before.square * 1e3, o.after.square * 1e3,
      change(o.before.square, o.after.square));
}

// `wide_spread`, `wide_reach`: the protocol spread and V3 line scale of the "wide" rows.
std::vector<Case> cases(double wide_spread, double wide_reach) {
  const double deg = kCampaignDeg;
  const auto delta = [](bool legs, double tilt, double metre = 1e-3, double radian = 0.5 * kCampaignDeg) {
    return [=](unsigned s) { return makeDefectiveDelta(s, legs, tilt, metre, radian); };
  };
  const auto hexapod = [](double gain, double eccentricity, double metre = 1e-3) {
    return [=](unsigned s) { return makeDefectiveHexapod(s, gain, eccentricity, metre); };
  };
  return {
      // The rows of the first pass (kept), then the diagnosis.
      {"Delta, equal legs, plate tilt", "delta", delta(false, 0.0116)},
      {"Delta, legs differ, plate tilt", "delta", delta(true, 0.0116)},
      {"Delta, legs differ, plate tilt", "delta-legs", delta(true, 0.0116)},
      {"Hexapod, gains 2e-3 + ecc. 0.3 mm", "gough-stewart", hexapod(2e-3, 0.3e-3)},
      {"Delta FLOOR (no defect)", "delta", delta(false, 0.0)},
      {"Delta, legs differ only", "delta", delta(true, 0.0)},
      {"Delta-legs FLOOR (legs differ, no tilt)", "delta-legs", delta(true, 0.0)},
      {"Delta, legs differ, tilt, noise-free", "delta", delta(true, 0.0116), false},
      {"Delta, legs differ, tilt, noise-free", "delta-legs", delta(true, 0.0116), false},
      {"Hexapod FLOOR (no defect)", "gough-stewart", hexapod(0.0, 0.0)},
      {"Hexapod, gains 2e-3 only", "gough-stewart", hexapod(2e-3, 0.0)},
      {"Hexapod, ecc. 0.3 mm only", "gough-stewart", hexapod(0.0, 0.3e-3)},
      {"Hexapod, gains + ecc., noise-free", "gough-stewart", hexapod(2e-3, 0.3e-3), false},
      // The model with one encoder scale per leg.
      {"Hexapod, gains 2e-3 + ecc. 0.3 mm", "gough-stewart-gains", hexapod(2e-3, 0.3e-3)},
      {"Hexapod-gains FLOOR (gains only)", "gough-stewart-gains", hexapod(2e-3, 0.0)},
      {"Hexapod, gains + ecc., noise-free", "gough-stewart-gains", hexapod(2e-3, 0.3e-3), false},
      {"Hexapod, gains 7e-4 (C10 screws)", "gough-stewart", hexapod(7e-4, 0.0)},
      {"Hexapod, gains 7e-4 (C10 screws)", "gough-stewart-gains", hexapod(7e-4, 0.0)},
      // Geometric errors of the paper's robot's size (3 mm / 3°, doc/mechanisms.md).
      {"Delta 3mm/3deg, equal legs, tilt", "delta", delta(false, 0.0116, 3e-3, 3 * deg)},
      {"Delta 3mm/3deg FLOOR (no defect)", "delta", delta(false, 0.0, 3e-3, 3 * deg)},
      {"Delta 3mm/3deg, legs differ, tilt", "delta", delta(true, 0.0116, 3e-3, 3 * deg)},
      {"Delta 3mm/3deg, legs differ, tilt", "delta-legs", delta(true, 0.0116, 3e-3, 3 * deg)},
      {"Delta-legs 3mm/3deg FLOOR (no tilt)", "delta-legs", delta(true, 0.0, 3e-3, 3 * deg)},
      {"Hexapod 3mm, gains + ecc.", "gough-stewart", hexapod(2e-3, 0.3e-3, 3e-3)},
      {"Hexapod 3mm, gains + ecc.", "gough-stewart-gains", hexapod(2e-3, 0.3e-3, 3e-3)},
      {"Hexapod 3mm FLOOR (no defect)", "gough-stewart", hexapod(0.0, 0.0, 3e-3)},
      // The hexapod's protocol and V3 lines over more of its stroke-limited workspace.
      {"Hexapod wide, gains + ecc.", "gough-stewart", hexapod(2e-3, 0.3e-3), true, wide_spread, wide_reach},
      {"Hexapod wide, gains + ecc.", "gough-stewart-gains", hexapod(2e-3, 0.3e-3), true, wide_spread, wide_reach},
      {"Hexapod wide FLOOR (no defect)", "gough-stewart", hexapod(0.0, 0.0), true, wide_spread, wide_reach},
      // The Delta's protocol (±150 mm, ±75 mm) and lines over twice the extent: ±300 mm and
      // ±150 mm, lines ±240 mm in x and y (the reachable radius is ≈ 0.45–0.53 m at these heights).
      {"Delta wide, equal legs, tilt", "delta", delta(false, 0.0116), true, 2.0, 2.0},
      {"Delta wide FLOOR (no defect)", "delta", delta(false, 0.0), true, 2.0, 2.0},
      {"Delta wide, legs differ, tilt", "delta", delta(true, 0.0116), true, 2.0, 2.0},
      {"Delta wide, legs differ, tilt", "delta-legs", delta(true, 0.0116), true, 2.0, 2.0},
      {"Delta-legs wide FLOOR (no tilt)", "delta-legs", delta(true, 0.0), true, 2.0, 2.0},
      // The floor is the identification noise: 4x the poses should halve it.
      {"Delta FLOOR, 4x poses (27 + 81)", "delta", delta(false, 0.0), true, 1.0, 1.0, 81},
      {"Hexapod FLOOR, 4x poses (81 + 243)", "gough-stewart", hexapod(0.0, 0.0), true, 1.0, 1.0, 243},
  };
}

}  // namespace

int main(int argc, char** argv) {
  const unsigned seeds = argc > 1 ? static_cast<unsigned>(std::atoi(argv[1])) : 5;
  const double wide_spread = argc > 2 ? std::atof(argv[2]) : 1.5, wide_reach = argc > 3 ? std::atof(argv[3]) : 1.875;
  const std::vector<Case> all = cases(wide_spread, wide_reach);
  std::vector<Summary> summary(all.size());
  for (unsigned s = 1; s <= seeds; ++s)
    for (std::size_t i = 0; i < all.size(); ++i) {
      Outcome o;
      try {
        o = study(all[i], s);
      } catch (const std::exception& e) {
        std::printf("%-40s %-19s seed %2u: failed: %s\n", all[i].robot.c_str(), all[i].model.c_str(), s, e.what());
        continue;
      }
      printRow(all[i], s, o);
      Summary& m = summary[i];
      m.v3_before += o.before.v3;
      m.v3_after += o.after.v3;
      m.sq_before += o.before.square;
      m.sq_after += o.after.square;
      ++m.n;
      m.v3_worst = std::max(m.v3_worst, change(o.before.v3, o.after.v3));
      m.sq_worst = std::max(m.sq_worst, change(o.before.square, o.after.square));
    }
  std::printf("\nMeans over %u seeds (change of the means; worst seed's change in brackets):\n", seeds);
  std::printf(
      "| robot | model | V3 before -> after [mm] | square side RMS before -> after [mm] |\n|---|---|---|---|\n");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Summary& m = summary[i];
    if (m.n == 0) {
      std::printf("| %s | `%s` | every seed failed | |\n", all[i].robot.c_str(), all[i].model.c_str());
      continue;
    }
    std::printf("| %s | `%s` | %.4f -> %.4f (%+.0f %%; worst %+.0f %%) | %.4f -> %.4f (%+.0f %%; worst %+.0f %%) |%s\n",
                all[i].robot.c_str(), all[i].model.c_str(), 1e3 * m.v3_before / m.n, 1e3 * m.v3_after / m.n,
                change(m.v3_before, m.v3_after), m.v3_worst, 1e3 * m.sq_before / m.n, 1e3 * m.sq_after / m.n,
                change(m.sq_before, m.sq_after), m.sq_worst,
                m.n < static_cast<int>(seeds) ? (" " + std::to_string(m.n) + " seeds").c_str() : "");
  }
  return 0;
}
