// Simulation specs on the YAML layer: misspelt keys, duplicate or unsafe pose ids, NaN and a
// target behind the camera are errors naming the file, the line and the key.
#include "mire/datasets/simulation.hpp"

#include "test_support.hpp"

#include <fstream>

namespace mire::datasets {
namespace {

namespace fs = std::filesystem;

std::string specError(const std::string& text) {
  const test::TempDir dir;
  for (const char* file : {"reference_camera.yaml", "target_chessboard.yaml"})
    fs::copy_file(test::sourceDir() / "datasets/specs" / file, dir.path() / file);
  const auto path = dir.path() / "spec.yaml";
  std::ofstream(path, std::ios::binary) << text;
  try {
    readSimulationSpec(path);
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    return message.rfind(path.string(), 0) == 0 ? "spec.yaml" + message.substr(path.string().size()) : message;
  }
  return "(no error)";
}

const std::string kHead = "camera: reference_camera.yaml\ntarget: target_chessboard.yaml\n";

TEST(SpecErrors, MisspeltKeysAreErrorsWithAHint) {
  EXPECT_EQ(specError(kHead + "nosie:\n  gaussian_sigma: 3\n"),
            "spec.yaml:3: unknown key 'nosie' (did you mean 'noise'?)");
  EXPECT_EQ(specError(kHead + "noise:\n  gausian_sigma: 3\n"),
            "spec.yaml:4: unknown key 'noise.gausian_sigma' (did you mean 'gaussian_sigma'?)");
  EXPECT_EQ(specError(kHead + "seed: 1\nseed: 2\n"), "spec.yaml:4: key 'seed' appears twice (first at line 3)");
  EXPECT_EQ(specError(kHead + "render:\n  blur_sigma_px: 1e300\n"),
            "spec.yaml:4: key 'render.blur_sigma_px': 1e+300 is out of range (0..20)");
  EXPECT_EQ(specError(kHead + "calibration: {views: 3000000000}\n"),
            "spec.yaml:3: key 'calibration.views': 3000000000 is out of range (1..10000)");
  EXPECT_EQ(specError("target: target_chessboard.yaml\n"), "spec.yaml:1: missing key 'camera'");
  EXPECT_EQ(specError(kHead + "noise: {gaussian_sigma: 2, shot_noise_gain: 4}\nrender: {cluttered_background: true}\n"),
            "(no error)");
}

TEST(SpecErrors, PoseListIdsAndValuesAreChecked) {
  const std::string list = kHead + "poses:\n  list:\n";
  EXPECT_EQ(
      specError(list + "    - {id: a, t: [0, 0, 0.6], r: [0, 0, 0]}\n    - {id: a, t: [0, 0, 0.7], r: [0, 0, 0]}\n"),
      "spec.yaml:6: key 'poses.list[1].id': 'a' is given twice (first at line 5)");
  EXPECT_EQ(
      specError(list + "    - {id: '..', t: [0, 0, 0.6], r: [0, 0, 0]}\n"),
      "spec.yaml:5: key 'poses.list[0].id': '..' is not usable as a folder name (letters, digits, '_', '-', '.')");
  EXPECT_EQ(specError(list + "    - {id: p, t: [0, .nan, 0.6], r: [0, 0, 0]}\n"),
            "spec.yaml:5: key 'poses.list[0].t[1]': '.nan' is not a finite number");
  EXPECT_EQ(specError(list + "    - {id: p, t: [0, 0, -0.6], r: [0, 0, 0]}\n"),
            "spec.yaml:5: key 'poses.list[0].t': z = -0.6 m puts the target behind the camera");
  EXPECT_EQ(specError(list + "    - {id: p01, t: [0, 0, 0.6], r: [0, 0, 0]}\n"), "(no error)");
}

TEST(SpecErrors, InlineCameraUsesTheCameraReader) {
  const std::string inline_camera =
      "camera:\n  image_width: 640\n  image_height: 480\n  K: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n  D: [0, 0, 0, 0, "
      "0]\n"
      "target: target_chessboard.yaml\n";
  EXPECT_EQ(specError(inline_camera), "(no error)");
  EXPECT_EQ(specError(inline_camera + "camera: x.yaml\n"), "spec.yaml:7: key 'camera' appears twice (first at line 1)");
  std::string bad = inline_camera;
  bad.replace(bad.find("image_height"), 12, "image_heigth");
  EXPECT_EQ(specError(bad), "spec.yaml:3: unknown key 'camera.image_heigth' (did you mean 'image_height'?)");
}

}  // namespace
}  // namespace mire::datasets
