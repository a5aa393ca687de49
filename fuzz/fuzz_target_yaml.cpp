// libFuzzer target: target.yaml through metrology::Target::fromFile.
#include "fuzz_input.hpp"

#include "mire/metrology/target.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("target.yaml");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    const mire::metrology::Target target = mire::metrology::Target::fromFile(path.path());
    (void)target.points().size();
  } catch (const std::exception&) {
  }
  return 0;
}
