// The model check's false alarms and power on rendered calibration sets (run by hand; results in
// doc/studies/2026-11-26-lens-model-check.md): N clean sets through the reference camera (a lens
// opencv5 represents) and N through the decentred thin-prism lens, each calibrated with opencv5
// and checked (each test at 1 %); prints every verdict, the tests' p-values and the counts.
// Usage: bench_model_check [sets = 20] [views = 25] [folds = 0]
#include "../tests/common/model_check_study.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace {

struct Counts {
  int insufficient = 0, structure = 0, nested = 0, holdout = 0;
};

void runSets(const char* label, const mire::calibration::Camera& truth, int sets, int views, int folds,
             std::uint64_t first_seed, Counts* counts) {
  for (int s = 0; s < sets; ++s) {
    const auto set = mire::test::renderCalibrationSet(truth, views, first_seed + static_cast<std::uint64_t>(s));
    const auto checked = mire::test::calibrateAndCheck(set, truth, mire::calibration::DistortionModel::OpenCV5, folds);
    const auto& check = checked.check;
    const auto sigma = checked.result.camera.sigmas();
    bool nested = false;
    for (const auto& test : check.nested) nested = nested || test.significant;
    counts->insufficient += check.adequate ? 0 : 1;
    counts->structure += check.structure.significant ? 1 : 0;
    counts->nested += nested ? 1 : 0;
    counts->holdout += check.holdout && check.holdout->significant ? 1 : 0;
    std::printf("%s set %2d: %zu views, rms %.4f px, cx %+.2f (%.1f sigma) cy %+.2f (%.1f sigma); structure p %.3g",
                label, s, set.views.size(), checked.result.camera.rms_px, checked.result.camera.cx() - truth.cx(),
                (checked.result.camera.cx() - truth.cx()) / sigma[2], checked.result.camera.cy() - truth.cy(),
                (checked.result.camera.cy() - truth.cy()) / sigma[3], check.structure.corrected_p_value);
    for (const auto& test : check.nested)
      std::printf("; %s LR %.1f p %.3g", test.model.c_str(), test.statistic, test.p_value);
    if (check.holdout) std::printf("; held out ratio %.3f p %.3g", check.holdout->ratio, check.holdout->p_value);
    std::printf("\n  %s\n", check.verdictLine().c_str());
    if (!check.adequate) {
      // The model the verdict names (thin prism on opencv5), on the same views: its errors.
      const auto opencv12 = mire::test::calibrateAndCheck(set, truth, mire::calibration::DistortionModel::OpenCV12,
                                                          folds, {"k4", "k5", "k6"});
      const auto& camera = opencv12.result.camera;
      const auto sigma12 = camera.sigmas();
      std::printf("  opencv12: fx %+.3f fy %+.3f cx %+.3f cy %+.3f px (sigma %.3f %.3f %.3f %.3f); %s\n",
                  camera.fx() - truth.fx(), camera.fy() - truth.fy(), camera.cx() - truth.cx(), camera.cy() - truth.cy(),
                  sigma12[0], sigma12[1], sigma12[2], sigma12[3], opencv12.check.verdictLine().c_str());
    }
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int sets = argc > 1 ? std::atoi(argv[1]) : 20;
  const int views = argc > 2 ? std::atoi(argv[2]) : 25;
  const int folds = argc > 3 ? std::atoi(argv[3]) : 0;
  const auto start = std::chrono::steady_clock::now();
  Counts clean, prism;
  runSets("clean", mire::datasets::referenceCamera(), sets, views, folds, 9000, &clean);
  runSets("prism", mire::test::thinPrismCamera(), sets, views, folds, 9500, &prism);
  std::printf("\n%d sets of %d views each, %.0f s\n", sets, views,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  std::printf("| lens | insufficient | structure | nested | held out |\n| --- | --- | --- | --- | --- |\n");
  std::printf("| clean (opencv5 lens) | %d | %d | %d | %d |\n", clean.insufficient, clean.structure, clean.nested,
              clean.holdout);
  std::printf("| thin prism | %d | %d | %d | %d |\n", prism.insufficient, prism.structure, prism.nested, prism.holdout);
  return 0;
}
