// `mire convert --camera IN -o OUT [--to FORMAT] [--lossy]`: a camera file from one tool's format to
// another's (doc/file-formats.md "Camera files"). The input format is detected from its content, the
// output format taken from --to or from OUT's extension. A conversion that loses terms is refused
// unless --lossy, which prints the loss in pixels; the covariance goes in the file where the format
// holds it, in OUT.covariance.yaml otherwise; the camera's name is kept.
#include "commands.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/output_transaction.hpp"
#include "validate.hpp"

#include <cstdio>

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
  std::string to;    // empty: from the output's extension
  std::string name;  // empty: the input's name, else "camera"
  bool lossy = false;
};

std::string pixels(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g px", value);
  return buffer;
}

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
  calibration::Camera camera = calibration::readCamera(options.camera);
  checkCamera(camera, options.camera);
  if (!options.name.empty()) camera.name = options.name;
  const std::string name = camera.name.empty() ? std::string("camera") : camera.name;
  calibration::ConversionLoss loss;
  try {
    loss = calibration::conversionLoss(camera, *format);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(options.camera + ": cannot be written as " + calibration::cameraFormatName(*format) +
                             ": " + error.what());
  }
  const std::string loss_text =
      loss.lost + " (" + pixels(loss.rms_px) + " RMS, " + pixels(loss.max_px) + " max over the image)";
  if (!loss.exact() && !options.lossy)
    throw std::runtime_error(options.camera + ": " + calibration::cameraFormatName(*format) + " cannot hold this " +
                             camera.modelName() + " camera: it would lose " + loss_text +
                             "; give --lossy to write it anyway");
  std::string text;
  try {
    // Kalibr's writer takes the camera it can hold; ViSP's fits its own term and says so in the file.
    const calibration::Camera& written = *format == calibration::CameraFormat::Kalibr ? loss.written : camera;
    text = calibration::cameraString(written, *format, name);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(options.camera + ": cannot be written as " + calibration::cameraFormatName(*format) +
                             ": " + error.what());
  }
  const bool side_file =
      !calibration::formatHoldsCovariance(*format) &&
      (camera.covariance.size() != 0 || (*format == calibration::CameraFormat::Kalibr && !camera.name.empty()));
  support::OutputTransaction outputs;
  support::writeFileAtomically(outputs.stageFile(options.output), text);
  const fs::path side = calibration::covarianceSideFile(options.output);
  if (side_file)
    support::writeFileAtomically(outputs.stageFile(side), calibration::cameraCovarianceSideFileString(camera));
  outputs.commit();
  std::cout << "mire convert: " << options.camera << " (" << calibration::cameraFormatName(input_format) << ") -> "
            << options.output << " (" << calibration::cameraFormatName(*format) << ")\n";
  if (!loss.exact()) std::cout << "  lossy (--lossy): lost " << loss_text << "\n";
  if (side_file)
    std::cout << "  " << calibration::cameraFormatName(*format) << " files have no place for the "
              << (camera.covariance.size() != 0 ? "covariance" : "camera's name") << ": written to " << side.string()
              << " (mire reads it with the camera file)\n";
  else if (camera.covariance.size() != 0)
    std::cout << "  the covariance is in the file\n";
  return kOk;
}

}  // namespace

Runner addConvertCommand(CLI::App& app) {
  auto options = std::make_shared<ConvertOptions>();
  CLI::App* command =
      app.add_subcommand("convert", "Convert a camera file between OpenCV, ROS, ViSP, Kalibr and mrcal");
  command
      ->add_option("--camera", options->camera,
                   "input camera file (opencv, ros, visp, kalibr or mrcal; detected from the content)")
      ->required();
  command->add_option("-o,--output", options->output, "output file")->required();
  command
      ->add_option("--to", options->to,
                   "output format (default: from the extension: .yaml/.yml opencv, .xml visp, "
                   ".cameramodel mrcal)")
      ->check(CLI::IsMember({"opencv", "ros", "visp", "kalibr", "mrcal"}));
  command->add_option("--name", options->name,
                      "camera name written in the output (default: the input's name, else camera)");
  command->add_flag("--lossy", options->lossy,
                    "write even when the output format cannot hold the model (the loss is printed in px)");
  return [options] { return runConvert(*options); };
}

}  // namespace mire::app
