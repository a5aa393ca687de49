// `mire identify` linear in the pose count (doc/studies/2026-11-24-identify-scaling.md): the
// library calls `mire identify --model h4-12` makes (read poses.csv +
// joints.csv, makeH4VariantModel 'D' = axis alignment + FKM + linear mounting, identify
// weighted by the pose covariances) on 10³, 10⁴ and 10⁵ simulated H4 poses (random poses in the
// protocol volume, 0.2 mm / 0.03° noise), CPU time per stage and the ratios between sizes.
// With a `mire` binary as 4th argument, also the command itself on the same files (CPU time of
// the child: process start, reading, identification, the report and identified.yaml).
// Usage: bench_identify_scaling [largest=100000] [smallest=1000] [repeats=0: 9/5/3 by size] [mire]
#include <sys/resource.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/external.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/variants.hpp"

using namespace mire::mechanism;

namespace {

double cpuSeconds(const std::function<void()>& f) {
  const std::clock_t t0 = std::clock();
  f();
  return double(std::clock() - t0) / CLOCKS_PER_SEC;
}

// CPU seconds (user + system) of the children waited for so far.
double childrenCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

struct StageTimes {
  double read = 0, alignment = 0, initial = 0, identify = 0, command = 0;
  int iterations = 0;
  double total() const { return read + initial + identify; }
};

// Median over `repeats` runs of each stage (the machine is shared: medians, CPU time).
StageTimes timeOne(int n, int repeats, const std::string& mire) {
  const mire::datasets::Campaign c =
      mire::datasets::simulateCampaign("h4-12", 9, 0.2e-3, 0.03 * mire::datasets::kCampaignDeg, 0, n);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("mire_bench_identify_scaling_" + std::to_string(n));
  std::filesystem::create_directories(dir);
  mire::datasets::writeCampaignFiles(c, dir, 0, c.poses.size());
  const H4Nominal nominal;
  std::vector<double> read, alignment, initial, solve, command;
  StageTimes out;
  for (int r = 0; r < repeats; ++r) {
    ObservationSet observations;
    read.push_back(cpuSeconds([&] {
      observations =
          readObservations(dir / "poses.csv", dir / "joints.csv", std::nullopt, c.model.mechanism->jointColumnNames());
    }));
    // The CSV gives σ only (diagonal covariance), as the simulated poses: use them directly.
    const std::vector<PoseObservation>& poses = c.poses;
    alignment.push_back(cpuSeconds([&] { (void)estimateAxisAlignment(poses); }));
    IdentificationModel model;
    initial.push_back(cpuSeconds([&] { model = makeH4VariantModel('D', nominal, poses, {}); }));
    IdentificationResult result;
    solve.push_back(cpuSeconds([&] { result = identify(model, poses); }));
    out.iterations = result.iterations;
    if (!mire.empty()) {
      const std::string run = mire + " identify --model h4-12 --poses " + (dir / "poses.csv").string() + " --joints " +
                              (dir / "joints.csv").string() + " -o " + (dir / "identified.yaml").string() +
                              " >/dev/null 2>&1";
      const double before = childrenCpuSeconds();
      if (std::system(run.c_str()) != 0) std::fprintf(stderr, "mire identify failed on %d poses\n", n);
      command.push_back(childrenCpuSeconds() - before);
    }
  }
  std::filesystem::remove_all(dir);
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  out.read = median(read);
  out.alignment = median(alignment);
  out.initial = median(initial);
  out.identify = median(solve);
  if (!command.empty()) out.command = median(command);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int largest = argc > 1 ? std::atoi(argv[1]) : 100000;
  const int smallest = argc > 2 ? std::atoi(argv[2]) : 1000;
  const int fixed_repeats = argc > 3 ? std::atoi(argv[3]) : 0;
  const std::string mire = argc > 4 ? argv[4] : "";
  std::printf("mire identify --model h4-12 stages, CPU seconds (median of the repeats)\n");
  std::printf("%8s %8s %10s %10s %10s %10s %10s %6s %12s\n", "poses", "repeats", "read csv", "axis align", "initial",
              "identify", "total", "iters", "ratio total");
  StageTimes previous;
  for (int n = smallest; n <= largest; n *= 10) {
    const int repeats = fixed_repeats > 0 ? fixed_repeats : n <= 1000 ? 9 : n <= 10000 ? 5 : 3;
    const StageTimes t = timeOne(n, repeats, mire);
    char ratio[64] = "";
    if (previous.total() > 0) std::snprintf(ratio, sizeof ratio, "%.2fx", t.total() / previous.total());
    std::printf("%8d %8d %10.3f %10.3f %10.3f %10.3f %10.3f %6d %12s\n", n, repeats, t.read, t.alignment, t.initial,
                t.identify, t.total(), t.iterations, ratio);
    if (previous.total() > 0)
      std::printf(
          "%8s ratios vs %d poses: read %.2fx, axis alignment %.2fx, initial %.2fx, identify %.2fx "
          "(limit 10x per 10x poses)\n",
          "", n / 10, t.read / previous.read, t.alignment / previous.alignment, t.initial / previous.initial,
          t.identify / previous.identify);
    if (!mire.empty())
      std::printf("%8s mire identify command: %.3f s CPU%s\n", "", t.command,
                  previous.command > 0 ? (", " + std::to_string(t.command / previous.command) + "x").c_str() : "");
    std::fflush(stdout);
    previous = t;
  }
  return 0;
}
