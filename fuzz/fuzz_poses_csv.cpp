// libFuzzer target: poses.csv, and with its covariance side file: the input is poses.csv, optionally followed by a line
// "====" and poses_covariance.csv.
#include "fuzz_input.hpp"

#include "mire/mechanism/io.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile poses("poses.csv");
  static const mire::fuzz::ScratchFile covariance("poses_covariance.csv");
  const auto [first, second] = mire::fuzz::splitInput(data, size);
  mire::fuzz::writeScratch(poses.path(), reinterpret_cast<const std::uint8_t*>(first.data()), first.size());
  try {
    if (second.empty()) {
      (void)mire::mechanism::readPosesCsv(poses.path());
    } else {
      mire::fuzz::writeScratch(covariance.path(), reinterpret_cast<const std::uint8_t*>(second.data()), second.size());
      (void)mire::mechanism::readPosesCsv(poses.path(), covariance.path());
    }
  } catch (const std::exception&) {
  }
  return 0;
}
