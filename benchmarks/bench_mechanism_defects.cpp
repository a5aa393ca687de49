// Unmodelled defects (doc/mechanisms.md): a Delta whose legs differ and whose plate tilts, a
// hexapod with encoder gains and joint eccentricities. Identified with their models, then
// V3 (two straight-line motions rebuilt with the model's FKM, paper §6.1) and the positioning
// test (a 100 mm square commanded through the model's IKM, reached by the true robot; RMS of
// the 3-D side-length errors, frame-invariant), with the nominal and the identified parameters.
// Usage: bench_mechanism_defects [seeds=5]
#include <cmath>
#include <cstdio>
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

std::vector<std::vector<Eigen::VectorXd>> recordLines(const DefectiveRobot& robot, bool translation) {
  std::vector<std::vector<Eigen::VectorXd>> lines;
  const Eigen::VectorXd ref = robot.mechanism().referencePose(robot.geometry.values());
  const double a = translation ? 0.12 : 0.04, dz = translation ? 0.05 : 0.025;
  for (int sign : {1, -1}) {
    std::vector<Eigen::VectorXd> q;
    for (int k = 0; k <= 20; ++k) {
      const double s = -1.0 + k / 10.0;
      Eigen::VectorXd X = ref;
      X[0] += a * s;
      X[1] += sign * a * s;
      X[2] += dz * s;
      q.push_back(robot.joints(X));
    }
    lines.push_back(q);
  }
  return lines;
}

Scores score(const DefectiveRobot& robot, const Mechanism& m, const Eigen::VectorXd& g, bool translation) {
  Scores s;
  const StraightnessResult v3 = straightnessCriterion(m, g, recordLines(robot, translation));
  s.v3 = v3.ok ? v3.v3_m : NAN;
  const Eigen::VectorXd ref = m.referencePose(g);
  std::vector<Eigen::Vector3d> reached;
  const double corners[5][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}};
  for (const auto& c : corners) {
    Eigen::VectorXd X = ref;
    X[0] += 0.05 * c[0];
    X[1] += 0.05 * c[1];
    const IkmResult ikm = m.inverseKinematics(g, m.poseToTransform(X));
    reached.push_back(robot.fkm(ikm.joints).head<3>());
  }
  double sq = 0;
  for (int k = 0; k < 4; ++k) sq += std::pow((reached[k + 1] - reached[k]).norm() - 0.1, 2);
  s.square = std::sqrt(sq / 4);
  return s;
}

void study(const std::string& label, const DefectiveRobot& robot, const std::string& model, unsigned seed) {
  const Campaign c = simulateDefectiveCampaign(robot, model, seed);
  const RegisteredModel reg = makeRegisteredModel(model);
  IdentificationModel initial = makeInitialModel(reg.mechanism, reg.nominal, c.poses, reg.external_form);
  fixGauge(initial, c.poses);
  const IdentificationResult result = identify(initial, c.poses);
  const bool translation = reg.mechanism->motionType() == MotionType::Translation;
  const Scores before = score(robot, *reg.mechanism, reg.nominal.values(), translation);
  const Scores after = score(robot, *reg.mechanism, result.model.geometricValues(), translation);
  std::printf(
      "%-34s %-13s seed %u: joint RMS %.4f %s; V3 %.4f -> %.4f mm (%+.0f %%); square side RMS %.4f -> %.4f mm (%+.0f "
      "%%)\n",
      label.c_str(), model.c_str(), seed,
      translation ? result.rms_joint_residual * 57.29578 : result.rms_joint_residual * 1e3, translation ? "deg" : "mm",
      before.v3 * 1e3, after.v3 * 1e3, 100 * (after.v3 / before.v3 - 1), before.square * 1e3, after.square * 1e3,
      100 * (after.square / before.square - 1));
}

}  // namespace

int main(int argc, char** argv) {
  const unsigned seeds = argc > 1 ? static_cast<unsigned>(std::atoi(argv[1])) : 5;
  for (unsigned s = 1; s <= seeds; ++s) {
    const DefectiveRobot same = makeDefectiveDelta(s, false);
    const DefectiveRobot differ = makeDefectiveDelta(s, true);
    study("Delta, equal legs, plate tilt", same, "delta", s);
    study("Delta, legs differ, plate tilt", differ, "delta", s);
    study("Delta, legs differ, plate tilt", differ, "delta-legs", s);
    study("Hexapod, gains + eccentricities", makeDefectiveHexapod(s), "gough-stewart", s);
  }
  return 0;
}
