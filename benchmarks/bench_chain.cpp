// Honest σ end to end, run by hand (doc/studies/2026-11-24-chain-study-h4.md,
// doc/studies/2026-11-24-chain-study-delta-gough-stewart.md): each chain renders a new campaign of
// `mire demo --mechanism NAME` (new calibration images, pose images and encoder noise) of a true
// robot exactly of the identified model, then runs the demo's pipeline — calibrate, measure (poses.csv
// with the shared-term side file), identify without and with the shared calibration term — and
// scores every stage against the simulator's truth: calibration error/σ, pose error/σ,
// identification error/σ, the camera-frame position `mire fkm` predicts (chain_study.hpp).
// Usage: bench_chain <mechanism> [chains=20] [images_per_pose=10] [work_dir] [first_chain=0] [drawn|fixed]
// mechanism: a family of the table (h4, delta, gough-stewart), or delta-same-legs (identical legs,
// the `delta` model). drawn|fixed (the H4): the camera placement drawn per chain, or the demo's; the
// other robots' placement is the demo's moved by a few cm and degrees per chain.
// Even chains: the demo's robot (robot seed 2004); odd chains: a different random robot each.
#include "chain_study.hpp"

#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/demo.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  namespace mech = mire::mechanism;
  mire::bench::ChainRun run;
  run.mechanism = argc > 1 ? argv[1] : "";
  run.chains = argc > 2 ? std::atoi(argv[2]) : 20;
  run.images_per_pose = argc > 3 ? std::atoi(argv[3]) : 10;
  run.work = argc > 4 ? std::filesystem::path(argv[4])
                      : std::filesystem::temp_directory_path() / ("mire_bench_chain_" + run.mechanism);
  run.first_chain = argc > 5 ? std::atoi(argv[5]) : 0;
  const std::string placement = argc > 6 ? argv[6] : "drawn";
  run.draw_placement = placement == "drawn";
  const bool same_legs = run.mechanism == "delta-same-legs";
  bool known = same_legs;
  std::string names;  // h4|delta|...|, for the usage line
  for (const mech::MechanismFamily& family : mech::mechanismFamilies()) {
    known = known || family.name == run.mechanism;
    names += family.name + "|";
  }
  if (!known || run.chains < 2 || run.images_per_pose < 1 || run.first_chain < 0 ||
      (placement != "drawn" && placement != "fixed")) {
    std::fprintf(stderr,
                 "usage: bench_chain <%sdelta-same-legs> [chains>=2] [images_per_pose>=1] [work_dir] "
                 "[first_chain>=0] [drawn|fixed]\n",
                 names.c_str());
    return 2;
  }
  // The H4's study identifies the paper's default variant in the paper's gauge (eq. 24).
  if (!same_legs && mire::pipeline::takesPaperVariants(mech::mechanismFamily(run.mechanism)))
    return mire::bench::runH4ChainStudy(run);
  return mire::bench::runMechanismChainStudy(run);
}
