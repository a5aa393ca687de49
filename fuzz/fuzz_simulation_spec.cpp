// libFuzzer target: simulation spec through datasets::readSimulationSpec (paths inside resolve beside the scratch file).
#include "fuzz_input.hpp"

#include "mire/datasets/simulation.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("spec.yaml");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    const mire::datasets::SimulationSpec spec = mire::datasets::readSimulationSpec(path.path());
    (void)spec.poses.size();
  } catch (const std::exception&) {
  }
  return 0;
}
