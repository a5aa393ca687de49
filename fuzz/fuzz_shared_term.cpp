// libFuzzer target: the shared-term side file (poses_shared.csv, doc/uncertainty.md) through
// readSharedTermCsv, a reader of the Python module too.
#include "fuzz_input.hpp"

#include "mire/mechanism/identification_covariance.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("poses_shared.csv");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    (void)mire::mechanism::readSharedTermCsv(path.path());
  } catch (const std::exception&) {
  }
  return 0;
}
