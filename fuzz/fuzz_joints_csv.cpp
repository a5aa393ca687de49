// libFuzzer target: joints.csv through mechanism::readJointsCsv.
#include "fuzz_input.hpp"

#include "mire/mechanism/io.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("joints.csv");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    (void)mire::mechanism::readJointsCsv(path.path());
  } catch (const std::exception&) {
  }
  return 0;
}
