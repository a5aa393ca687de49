// Calibration σ under systematic error (run by hand, results in
// doc/calibration.md): over N rendered calibration sets like the demo's (new poses and
// noise each), RMS of error/σ per parameter with pixel-noise σ ("before") and with the printed
// σ, inflated by the view-cluster sandwich where the residuals show systematic error ("after").
// Usage: bench_calibration_sigma [sets = 20] [views = 25]
#include "../tests/common/calibration_sigma_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  const int sets = argc > 1 ? std::atoi(argv[1]) : 20;
  const int views = argc > 2 ? std::atoi(argv[2]) : 25;
  const auto names = mire::datasets::referenceCamera().parameterNames();
  std::vector<mire::test::SigmaStudySet> results;
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < sets; ++s) {
    results.push_back(mire::test::runSigmaStudySet(views, 7000 + static_cast<std::uint64_t>(s)));
    const auto& r = results.back();
    std::printf("set %2d: %d views, rms %.3f px; error/sigma (pixel noise -> printed):", s, r.views, r.rms_px);
    for (std::size_t i = 0; i < r.error.size(); ++i)
      std::printf(" %s %+.2f->%+.2f", names[i].c_str(), r.error[i] / r.sigma_pixel[i], r.error[i] / r.sigma[i]);
    std::printf("\n");
    std::fflush(stdout);
  }
  const auto before = mire::test::normalisedSpread(results, true);
  const auto after = mire::test::normalisedSpread(results, false);
  std::printf(
      "\n%d sets of %d views, %.0f s\n| parameter | pixel-noise sigma: mean, std, RMS of error/sigma | printed "
      "sigma: mean, std, RMS | mean inflation |\n| --- | --- | --- | --- |\n",
      sets, views, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  for (std::size_t i = 0; i < before.size(); ++i) {
    double inflation = 0.0;
    double mean[2] = {0.0, 0.0};
    for (const auto& r : results) {
      inflation += r.inflation[i] / results.size();
      mean[0] += r.error[i] / r.sigma_pixel[i] / results.size();
      mean[1] += r.error[i] / r.sigma[i] / results.size();
    }
    const double rms[2] = {before[i], after[i]};
    std::printf("| %s |", names[i].c_str());
    for (int k = 0; k < 2; ++k)
      std::printf(" %+.2f, %.2f, %.2f |", mean[k],
                  std::sqrt(std::max(0.0, rms[k] * rms[k] - mean[k] * mean[k]) * results.size() /
                            std::max<std::size_t>(1, results.size() - 1)),
                  rms[k]);
    std::printf(" %.2f |\n", inflation);
  }
  return 0;
}
