// The Monte-Carlo study of paper §6.2 (run by hand): 3 subset sizes (6, 15, 71 poses) × 100
// identifications of model 12 (variant D) on the simulated true H4, each validated on the
// other poses (V1, V2) and on the two straight lines (V3). Target: under 2 s on 2 cores.
// Peer: the same study on 1 thread (ratio = parallel speed-up).
#include "mire/datasets/h4_true_robot.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/variants.hpp"

#include <cstdio>
#include <random>

int main() {
  using namespace mire;
  const datasets::H4TrueKinematics robot(datasets::makeTrueGeometry({}, datasets::H4ErrorSizes{}, 3));
  datasets::H4MeasurementNoise noise;
  noise.encoder_rad = 2e-5;
  const auto poses =
      datasets::toObservations(datasets::simulateMeasurements(robot, datasets::protocolPoses(), noise, 11), noise);
  std::mt19937_64 rng(12);
  std::vector<std::vector<Eigen::VectorXd>> lines;
  for (const auto& line : datasets::straightLineMotions()) {
    lines.emplace_back();
    for (const auto& q : datasets::recordJoints(robot, line, 1e-4, rng)) lines.back().emplace_back(q);
  }
  const auto initial = mechanism::makeH4VariantModel('D', {}, poses);

  for (const bool with_lines : {true, false}) {
    double seconds[2] = {0.0, 0.0};
    for (int threads : {2, 1}) {
      mechanism::MonteCarloOptions options;
      options.subset_sizes = {6, 15, 71};
      options.repeats = 100;
      options.threads = threads;
      const auto study = mechanism::runMonteCarloStudy(initial, poses, with_lines ? lines : decltype(lines){}, options);
      seconds[threads == 2 ? 0 : 1] = study.seconds;
      std::printf("%s, %d thread(s): 3 x 100 identifications in %.2f s\n",
                  with_lines ? "with V3 lines" : "without lines", threads, study.seconds);
      if (threads == 2)
        for (const auto& s : study.summaries)
          std::printf("  %2d poses: %3d ok; V2 %.2e rad, V3 %.3f mm\n", s.subset_size, s.runs_ok, s.v2_mean,
                      s.v3_mean * 1e3);
    }
    std::printf("  speed-up 2 threads vs 1: %.2fx\n", seconds[1] / seconds[0]);
  }
  return 0;
}
