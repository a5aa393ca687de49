// `mire convert --camera IN -o OUT [--to FORMAT]`: a camera file from one tool's format to
// another's (doc/file-formats.md "Camera files"). The input format is detected from its content, the
// output format taken from --to or from OUT's extension.
#include "commands.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/support/atomic_file.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

struct ConvertOptions {
  std::string camera;
  std::string output;
  std::string to;  // empty: from the output's extension
  std::string name = "camera";
};

bool samePath(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

int runConvert(const ConvertOptions& options) {
  std::optional<calibration::CameraFormat> format;
  if (!options.to.empty()) {
    format = calibration::cameraFormatFromName(options.to);
  } else {
    format = calibration::cameraFormatFromExtension(options.output);
    if (!format) {
      std::cerr << "mire convert: cannot tell the output format from '" << options.output
                << "' (.yaml/.yml = opencv, .xml = visp, .cameramodel = mrcal): give --to\n";
      return kUsage;
    }
  }
  if (options.output.empty()) throw std::runtime_error("-o: empty output path");
  if (samePath(options.camera, options.output))
    throw std::runtime_error(options.output + ": the output is the input camera file; choose another -o");
  const calibration::CameraFormat input_format = calibration::detectCameraFormat(options.camera);
  const calibration::Camera camera = calibration::readCamera(options.camera);
  std::string text;
  try {
    text = calibration::cameraString(camera, *format, options.name);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(options.camera + ": cannot be written as " + calibration::cameraFormatName(*format) +
                             ": " + error.what());
  }
  support::writeFileAtomically(options.output, text);
  std::cout << "mire convert: " << options.camera << " (" << calibration::cameraFormatName(input_format) << ") -> "
            << options.output << " (" << calibration::cameraFormatName(*format) << ")\n";
  if (*format == calibration::CameraFormat::Visp && camera.distortionCount() > 0)
    std::cout << "  ViSP's model has one radial term: the file's comment gives the fit's residual and what is lost\n";
  return kOk;
}

}  // namespace

Runner addConvertCommand(CLI::App& app) {
  auto options = std::make_shared<ConvertOptions>();
  CLI::App* command =
      app.add_subcommand("convert", "Convert a camera file between OpenCV, ROS, ViSP, Kalibr and mrcal");
  command
      ->add_option("--camera", options->camera,
                   "input camera file (opencv, ros, visp or kalibr; detected from the content)")
      ->required();
  command->add_option("-o,--output", options->output, "output file")->required();
  command
      ->add_option("--to", options->to,
                   "output format (default: from the extension: .yaml/.yml opencv, .xml visp, "
                   ".cameramodel mrcal)")
      ->check(CLI::IsMember({"opencv", "ros", "visp", "kalibr", "mrcal"}));
  command->add_option("--name", options->name, "camera name written in ROS and ViSP files (default: camera)");
  return [options] { return runConvert(*options); };
}

}  // namespace mire::app
