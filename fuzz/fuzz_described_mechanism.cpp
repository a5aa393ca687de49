// libFuzzer target: a mechanism description (`--model robot.yaml`, doc/mechanisms.md) through
// readMechanismDescription, then the model built from it (the parameters and the mechanism).
#include "fuzz_input.hpp"

#include "mire/mechanism/described.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("robot.yaml");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    const mire::mechanism::MechanismDescription description = mire::mechanism::readMechanismDescription(path.path());
    (void)mire::mechanism::makeDescribedModel(description);
  } catch (const std::exception&) {
  }
  return 0;
}
