// Every example file mire ships (datasets/specs: simulation specs, the nominal H4 parameters,
// the reference camera; examples/mechanisms: the described robots) read in each YAML syntax a person or another tool
// may write gives the same result: plain YAML (as shipped), OpenCV's %YAML:1.0 header, a '---' line only, CRLF, a UTF-8
// BOM, flow style, comments everywhere. One test per file and variant.
#include "mire/calibration/camera_formats.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"

#include "test_support.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

namespace mire {
namespace {

namespace fs = std::filesystem;

fs::path specsDir() { return test::sourceDir() / "datasets/specs"; }

std::string variant(const std::string& kind, const std::string& text) {
  if (kind == "Plain") return text;
  if (kind == "OpenCvHeader") return "%YAML:1.0\n---\n" + text;
  if (kind == "DocumentMarker") return "---\n" + text;
  if (kind == "Bom") return "\xEF\xBB\xBF" + text;
  std::string out;
  if (kind == "Crlf") {
    for (const char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
  }
  if (kind == "Commented") {  // a comment line after every line, and one before
    std::istringstream lines(text);
    out = "# a comment first\n";
    for (std::string line; std::getline(lines, line);) out += line + "\n   # and one after each line\n";
    return out;
  }
  // "Flow": the same document in flow style, as yaml-cpp emits it.
  YAML::Emitter emitter;
  emitter.SetMapFormat(YAML::Flow);
  emitter.SetSeqFormat(YAML::Flow);
  emitter << YAML::Load(text);
  return std::string(emitter.c_str()) + "\n";
}

const std::vector<std::string> kVariants{"Plain", "OpenCvHeader", "DocumentMarker", "Crlf", "Bom", "Commented", "Flow"};

class YamlVariant : public ::testing::TestWithParam<std::string> {
 protected:
  // Writes the variant of specs/<name> beside copies of the files it refers to.
  fs::path write(const std::string& name) {
    for (const char* file : {"reference_camera.yaml", "target_chessboard.yaml"})
      fs::copy_file(specsDir() / file, dir_.path() / file, fs::copy_options::overwrite_existing);
    const fs::path path = dir_.path() / ("variant_" + name);
    std::ofstream(path, std::ios::binary) << variant(GetParam(), test::readText(specsDir() / name));
    return path;
  }
  test::TempDir dir_;
};

void expectSameSpec(const datasets::SimulationSpec& a, const datasets::SimulationSpec& b) {
  EXPECT_EQ(a.camera.params, b.camera.params);
  EXPECT_EQ(a.camera.width, b.camera.width);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.render.supersampling, b.render.supersampling);
  EXPECT_EQ(a.render.blur_sigma_px, b.render.blur_sigma_px);
  EXPECT_EQ(a.render.vignetting, b.render.vignetting);
  EXPECT_EQ(a.render.cluttered_background, b.render.cluttered_background);
  EXPECT_EQ(a.noise.gaussian_sigma, b.noise.gaussian_sigma);
  EXPECT_EQ(a.noise.shot_noise_gain, b.noise.shot_noise_gain);
  EXPECT_EQ(a.calibration.views, b.calibration.views);
  EXPECT_EQ(a.calibration.min_distance_m, b.calibration.min_distance_m);
  EXPECT_EQ(a.calibration.max_distance_m, b.calibration.max_distance_m);
  EXPECT_EQ(a.images_per_pose, b.images_per_pose);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    EXPECT_EQ(a.poses[i].id, b.poses[i].id);
    EXPECT_TRUE(a.poses[i].camera_T_target.isApprox(b.poses[i].camera_T_target, 0.0));
  }
}

TEST_P(YamlVariant, SimulateCalibrationSpec) {
  const auto reference = datasets::readSimulationSpec(specsDir() / "simulate_calibration.yaml");
  expectSameSpec(datasets::readSimulationSpec(write("simulate_calibration.yaml")), reference);
  EXPECT_EQ(reference.calibration.views, 25);
  EXPECT_EQ(reference.noise.gaussian_sigma, 12.0);
}

TEST_P(YamlVariant, SimulatePosesSpec) {
  const auto reference = datasets::readSimulationSpec(specsDir() / "simulate_poses.yaml");
  expectSameSpec(datasets::readSimulationSpec(write("simulate_poses.yaml")), reference);
  EXPECT_EQ(reference.poses.size(), 27u * 3u);
}

TEST_P(YamlVariant, NominalParameters) {
  mechanism::ParameterSet reference = mechanism::h4Model12Parameters(mechanism::H4Nominal{});
  mechanism::ParameterSet read = reference;
  read.setValues(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(read.size())));
  mechanism::applyParameterFile(mechanism::readParameterFile(write("h4_nominal.yaml")), read);
  EXPECT_EQ(read.values(), reference.values());
}

TEST_P(YamlVariant, ReferenceCamera) {
  const auto reference = calibration::readCamera(specsDir() / "reference_camera.yaml");
  const auto read = calibration::readCamera(write("reference_camera.yaml"));
  EXPECT_EQ(read.params, reference.params);
  EXPECT_EQ(read.width, 1024);
}

TEST_P(YamlVariant, DescribedMechanisms) {
  for (const char* name : {"linear-delta.yaml", "6-rus.yaml", "6-pus.yaml"}) {
    const fs::path shipped = test::sourceDir() / "examples/mechanisms" / name;
    const fs::path path = dir_.path() / (std::string("variant_") + name);
    std::ofstream(path, std::ios::binary) << variant(GetParam(), test::readText(shipped));
    EXPECT_EQ(mechanism::readMechanismDescription(path).yamlString(),
              mechanism::readMechanismDescription(shipped).yamlString())
        << name;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryYamlSyntax, YamlVariant, ::testing::ValuesIn(kVariants),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace mire
