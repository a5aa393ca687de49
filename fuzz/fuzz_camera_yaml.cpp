// libFuzzer target: camera.yaml (OpenCV FileStorage and the formats readCameraYaml accepts).
#include "fuzz_input.hpp"

#include "mire/calibration/camera_io.hpp"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mire::fuzz::ScratchFile path("camera.yaml");
  mire::fuzz::writeScratch(path.path(), data, size);
  try {
    const mire::calibration::Camera camera = mire::calibration::readCameraYaml(path.path());
    (void)camera.sigmas();
  } catch (const std::exception&) {
  }
  return 0;
}
