// libFuzzer target: mechanism parameter YAML through readParameterFile + applyParameterFile (H4 model 12).
#include "fuzz_input.hpp"

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("parameters.yaml");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    const mire::mechanism::ParameterFile file = mire::mechanism::readParameterFile(path.path());
    mire::mechanism::ParameterSet parameters = mire::mechanism::h4Model12Parameters(mire::mechanism::H4Nominal{});
    mire::mechanism::applyParameterFile(file, parameters, {"amplification"});
  } catch (const std::exception&) {
  }
  return 0;
}
