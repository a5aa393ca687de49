#pragma once
// The end-to-end σ study of `bench_chain` (doc/studies/, the chain studies): what every kind of
// robot's study shares — its arguments and the loop over chains — and the two studies: the H4's
// (chain_study_h4.cpp: model 12, variant D, in the paper's z_ME gauge) and the other robots'
// (chain_study_mechanisms.cpp: the family's truth model against the truth in the identification's
// gauge, with the fit's term diagnosed from the true pose errors).
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

namespace mire::bench {

struct ChainRun {
  std::string mechanism;  // a family of the table, or delta-same-legs (the `delta` model)
  int chains = 20;
  int images_per_pose = 10;
  std::filesystem::path work;  // one folder per chain, removed after it
  int first_chain = 0;
  bool draw_placement = true;  // the H4's: the camera placement drawn per chain, or the demo's
};

// Runs chains from run.first_chain until run.chains succeeded (at most twice as many attempts:
// some random robots cannot be initialised from the nominal); a failed chain is reported, its
// folder removed. Returns the chains that succeeded.
template <class Study, class RunChain>
int runChains(const ChainRun& run, Study& study, const RunChain& run_chain) {
  for (int chain = run.first_chain; study.chains < run.chains && chain < run.first_chain + 2 * run.chains; ++chain) {
    try {
      run_chain(chain);
    } catch (const std::exception& e) {
      ++study.failed;
      std::printf("chain %2d failed: %s\n", chain, e.what());
      std::filesystem::remove_all(run.work / ("chain" + std::to_string(chain)));
    }
  }
  return study.chains;
}

int runH4ChainStudy(const ChainRun& run);
int runMechanismChainStudy(const ChainRun& run);

}  // namespace mire::bench
