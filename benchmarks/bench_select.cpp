// `mire select` acceptance study (doc/plan-and-select.md), run by hand:
//  1. 20 simulated H4 campaigns (81 protocol poses, 0.2 mm / 0.03° pose noise) whose true robot
//     is exactly model 12: how often a model-12 variant (A–D) is recommended;
//  2. 20 campaigns whose arm and forearm lengths differ per leg by 1–3 mm: how often a
//     model-31 variant (E–H) is recommended;
//  3. Delta (27 protocol poses + `extra` random ones): equal legs → `delta`; arm and forearm
//     lengths differing per leg by 1–3 mm (as the H4 case) → `delta-legs`; and the detection
//     limit: every per-leg parameter within 1 mm / 0.5°;
//  4. time of one selection over the eight H4 variants, 10-fold CV, 81 poses.
// Usage: bench_select [campaigns=20] [extra Delta poses=0]
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "h4_selection_campaign.hpp"
#include "mire/datasets/h4_true_robot.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/mechanism/model_selection.hpp"

using namespace mire::mechanism;
namespace ds = mire::datasets;

namespace {

std::vector<SelectionCandidate> h4Candidates() {
  return parseSelectionCandidates("h4-12:A,B,C,D,h4-31c:E,F,G,H",
                                  [](const std::string& n) { return makeDesignModel(n); });
}

std::string describe(const SelectionResult& r) {
  std::string s;
  for (const ModelScore& m : r.scores) {
    char b[64];
    std::snprintf(b, sizeof b, " %s:%.4g", m.label.c_str(), m.ok ? m.cv_rms() * 180 / 3.14159265358979 * 1e3 : -1.0);
    s += b;
  }
  return s;
}

void h4Case(bool legs_differ, int campaigns) {
  const auto candidates = h4Candidates();
  int hits = 0;
  std::map<std::string, int> counts;
  std::vector<double> times;
  for (int c = 0; c < campaigns; ++c) {
    const auto poses = mire::test::h4SelectionCampaign(100u + static_cast<unsigned>(c), legs_differ);
    const std::clock_t c0 = std::clock();
    const SelectionResult r = selectModel(candidates, poses);
    const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    const std::string rec = r.recommendedLabel();
    ++counts[rec];
    times.push_back(cpu);
    const bool model31 = rec == "E" || rec == "F" || rec == "G" || rec == "H";
    hits += legs_differ == model31 ? 1 : 0;
    std::printf("  campaign %2d: recommended %s, best %s; CV rms [mdeg]%s\n", c, rec.c_str(),
                r.best >= 0 ? r.scores[static_cast<std::size_t>(r.best)].label.c_str() : "-", describe(r).c_str());
  }
  std::sort(times.begin(), times.end());
  std::printf("H4 %s: %s variant recommended in %d of %d campaigns (",
              legs_differ ? "legs differ 1-3 mm" : "exact model 12", legs_differ ? "a model-31" : "a model-12", hits,
              campaigns);
  for (const auto& [k, v] : counts) std::printf(" %s:%d", k.c_str(), v);
  std::printf(" ); selection CPU time median %.3f s, max %.3f s\n", times[times.size() / 2], times.back());
}

// A Delta's legs: equal (`delta` is exact), every per-leg parameter perturbed by up to
// 1 mm / 0.5° (makeDefectiveDelta: the detection limit), or, as the H4 case above, each leg's
// arm and forearm lengths changed by 1–3 mm (random sign) on top of equal legs.
enum class DeltaLegs { Equal, SmallPerturbation, LengthsDiffer };

ds::TrueRobot deltaRobot(unsigned seed, DeltaLegs legs) {
  ds::TrueRobot robot = ds::makeDefectiveDelta(seed, legs == DeltaLegs::SmallPerturbation, 0.0);
  if (legs != DeltaLegs::LengthsDiffer) return robot;
  std::mt19937 rng(seed + 77);
  std::uniform_real_distribution<double> size(1e-3, 3e-3);
  for (const char* name : {"L1", "L2", "L3", "l1", "l2", "l3"})
    robot.geometry.setValue(name, robot.geometry.value(name) + (rng() & 1U ? 1 : -1) * size(rng));
  return robot;
}

void deltaCase(DeltaLegs legs, int campaigns, int extra_poses) {
  const auto candidates =
      parseSelectionCandidates("delta,delta-legs", [](const std::string& n) { return makeDesignModel(n); });
  const bool legs_differ = legs != DeltaLegs::Equal;
  int hits = 0;
  for (int c = 0; c < campaigns; ++c) {
    const ds::TrueRobot robot = deltaRobot(200u + static_cast<unsigned>(c), legs);
    const ds::Campaign campaign = ds::simulateDefectiveCampaign(robot, "delta", 300u + static_cast<unsigned>(c), 0.2e-3,
                                                                0.03 * ds::kCampaignDeg, extra_poses);
    SelectionOptions options;
    options.folds = 9;
    const SelectionResult r = selectModel(candidates, campaign.poses, {}, options);
    const std::string rec = r.recommendedLabel();
    hits += (rec == "delta-legs") == legs_differ ? 1 : 0;
    std::printf("  campaign %2d: recommended %s;%s\n", c, rec.c_str(), describe(r).c_str());
  }
  const char* what = legs == DeltaLegs::Equal               ? "equal legs"
                     : legs == DeltaLegs::SmallPerturbation ? "every leg parameter within 1 mm / 0.5 deg"
                                                            : "arm and forearm lengths differ 1-3 mm";
  std::printf("Delta %s, %d poses: %s recommended in %d of %d campaigns\n", what, 27 + extra_poses,
              legs_differ ? "delta-legs" : "delta", hits, campaigns);
}

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 20;
  h4Case(false, campaigns);
  h4Case(true, campaigns);
  const int extra = argc > 2 ? std::atoi(argv[2]) : 0;
  deltaCase(DeltaLegs::Equal, campaigns, extra);
  deltaCase(DeltaLegs::LengthsDiffer, campaigns, extra);
  deltaCase(DeltaLegs::SmallPerturbation, campaigns, extra);
  return 0;
}
