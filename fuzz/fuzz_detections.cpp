// libFuzzer target: a detections file (mire's CSV or mrcal's corners vnlog) through
// metrology::readDetectionsFile, for a 9 x 6 chessboard of 25 mm squares.
#include "fuzz_input.hpp"

#include "mire/metrology/detections_file.hpp"
#include "mire/metrology/target.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("detections.csv");
  static const mire::metrology::Target target = [] {
    mire::metrology::TargetSpec spec;
    spec.type = mire::metrology::TargetType::Chessboard;
    spec.cols = 9;
    spec.rows = 6;
    spec.square_size_m = 0.025;
    return mire::metrology::Target(spec);
  }();
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    (void)mire::metrology::readDetectionsFile(path.path(), target).images.size();
  } catch (const std::exception&) {
  }
  return 0;
}
