// Camera files of other tools: format detection, the ViSP XML reader (ViSP's own parser), and
// the Kalibr writer (mrcal's reader and writer: camera_mrcal.cpp) (doc/file-formats.md "Camera files").
#include "mire/calibration/camera_formats.hpp"

#include "mire/calibration/camera_io.hpp"
#include "mire/support/yaml.hpp"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpException.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace mire::calibration {
namespace {

// The first bytes of a file, past a UTF-8 BOM and leading blanks.
std::string fileStart(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error(path.string() +
                             (std::filesystem::exists(path, ec) ? ": not a regular file" : ": file not found"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open for reading");
  std::string text(4096, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  const auto begin = text.find_first_not_of(" \t\r\n");
  return begin == std::string::npos ? std::string() : text.substr(begin);
}

std::string numberList(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + support::formatYamlNumber(values[i]);
  return text + "]";
}

std::vector<double> coefficientsOf(const Camera& camera) {
  return std::vector<double>(camera.params.begin() + kIntrinsicCount, camera.params.end());
}

// Kalibr's radtan has k1 k2 p1 p2 only: a longer OpenCV vector goes if its tail is zero.
std::vector<double> radtanCoefficients(const Camera& camera) {
  std::vector<double> d = coefficientsOf(camera);
  const std::vector<std::string> names = camera.parameterNames();
  for (std::size_t i = 4; i < d.size(); ++i)
    if (d[i] != 0.0)
      throw std::invalid_argument("Kalibr's radtan model has k1 k2 p1 p2 only; this camera's " +
                                  names[kIntrinsicCount + i] + " = " + support::formatMessageNumber(d[i]) +
                                  " cannot be written (calibrate with --model opencv4 for Kalibr)");
  d.resize(4);
  return d;
}

Camera vispCamera(const vpXmlParserCamera& parser, const vpCameraParameters& parameters,
                  const std::filesystem::path& path) {
  Camera camera;
  camera.width = static_cast<int>(parser.getWidth());
  camera.height = static_cast<int>(parser.getHeight());
  if (camera.width <= 0 || camera.height <= 0 || camera.width > 100000 || camera.height > 100000)
    throw std::runtime_error(path.string() + ": image_width/image_height missing or out of range (1..100000)");
  camera.params = {parameters.get_px(), parameters.get_py(), parameters.get_u0(), parameters.get_v0()};
  // ViSP: u = u0 + px·x·(1 + kud·r²) with (x, y) the undistorted ray, which is OpenCV's k1; kdu
  // (its approximate inverse) has no place in OpenCV's model and is not read.
  if (parameters.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion)
    camera.params.insert(camera.params.end(), {parameters.get_kud(), 0.0, 0.0, 0.0, 0.0});
  try {
    camera.validate();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(path.string() + ": " + error.what());
  }
  if (!(camera.fx() > 0.0) || camera.fx() > 1e6 || camera.fy() > 1e6)
    throw std::runtime_error(path.string() + ": px/py out of range (0..1e6)");
  return camera;
}

// ViSP's parser selects a camera by name: the first <camera>'s <name> (XML-unescaped).
std::string firstVispCameraName(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto camera = text.find("<camera>");
  if (camera == std::string::npos)
    throw std::runtime_error(path.string() + ": no <camera> element (not a ViSP camera XML file)");
  const auto begin = text.find("<name>", camera);
  const auto end = text.find("</name>", begin);
  if (begin == std::string::npos || end == std::string::npos) return {};
  std::string name = text.substr(begin + 6, end - begin - 6);
  for (const auto& [entity, character] : {std::pair<std::string, std::string>{"&lt;", "<"},
                                          {"&gt;", ">"},
                                          {"&quot;", "\""},
                                          {"&apos;", "'"},
                                          {"&amp;", "&"}}) {
    for (auto at = name.find(entity); at != std::string::npos; at = name.find(entity, at + 1))
      name.replace(at, entity.size(), character);
  }
  return name;
}

// Redirects std::cout to nothing for its lifetime.
class SilenceStdout {
 public:
  SilenceStdout() : previous_(std::cout.rdbuf(nullptr)) {}
  ~SilenceStdout() { std::cout.rdbuf(previous_); }
  SilenceStdout(const SilenceStdout&) = delete;
  SilenceStdout& operator=(const SilenceStdout&) = delete;

 private:
  std::streambuf* previous_;
};

}  // namespace

std::string cameraFormatName(CameraFormat format) {
  switch (format) {
    case CameraFormat::OpenCV:
      return "opencv";
    case CameraFormat::Ros:
      return "ros";
    case CameraFormat::Visp:
      return "visp";
    case CameraFormat::Kalibr:
      return "kalibr";
    case CameraFormat::Mrcal:
      return "mrcal";
  }
  return "opencv";
}

std::optional<CameraFormat> cameraFormatFromName(const std::string& name) {
  for (const auto format :
       {CameraFormat::OpenCV, CameraFormat::Ros, CameraFormat::Visp, CameraFormat::Kalibr, CameraFormat::Mrcal})
    if (cameraFormatName(format) == name) return format;
  return std::nullopt;
}

std::optional<CameraFormat> cameraFormatFromExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension == ".yaml" || extension == ".yml") return CameraFormat::OpenCV;
  if (extension == ".xml") return CameraFormat::Visp;
  if (extension == ".cameramodel") return CameraFormat::Mrcal;
  return std::nullopt;
}

CameraFormat detectCameraFormat(const std::filesystem::path& path) {
  const std::string start = fileStart(path);
  if (!start.empty() && start.front() == '<') return CameraFormat::Visp;
  // mrcal's models are Python literals that open with comments, then {'lensmodel': ...}.
  if (start.find("'lensmodel'") != std::string::npos || start.find("\"lensmodel\"") != std::string::npos)
    return CameraFormat::Mrcal;
  const support::YamlFile file = support::YamlFile::load(path);
  const support::YamlNode& root = file.rootMap();
  if (root.has("cam0")) return CameraFormat::Kalibr;
  for (const char* key : {"distortion_model", "projection_matrix", "rectification_matrix", "camera_name"})
    if (root.has(key)) return CameraFormat::Ros;
  return CameraFormat::OpenCV;
}

Camera readCamera(const std::filesystem::path& path) {
  switch (detectCameraFormat(path)) {
    case CameraFormat::Visp: {
      Camera camera = readCameraVispXml(path);
      readCovarianceSideFile(path, camera);
      return camera;
    }
    case CameraFormat::Kalibr: {
      Camera camera = readCameraKalibrYaml(path);
      readCovarianceSideFile(path, camera);
      return camera;
    }
    case CameraFormat::Mrcal:
      return readCameraMrcal(path);
    case CameraFormat::OpenCV:
    case CameraFormat::Ros:
      break;
  }
  return readCameraYaml(path);
}

Camera readCameraVispXml(const std::filesystem::path& path) {
  const std::string name = firstVispCameraName(path);
  vpXmlParserCamera parser;
  vpCameraParameters parameters;
  // The first camera of the file, with distortion when the file has that model.
  for (const auto model :
       {vpCameraParameters::perspectiveProjWithDistortion, vpCameraParameters::perspectiveProjWithoutDistortion}) {
    int status = vpXmlParserCamera::SEQUENCE_ERROR;
    try {
      const SilenceStdout quiet;  // ViSP's parser reports each camera it finds on std::cout
      status = parser.parse(parameters, path.string(), name, model, 0, 0);
    } catch (const vpException& error) {
      throw std::runtime_error(path.string() + ": not a ViSP camera XML file (" + error.getStringMessage() + ")");
    }
    if (status == vpXmlParserCamera::SEQUENCE_OK) {
      Camera camera = vispCamera(parser, parameters, path);
      camera.name = name;
      return camera;
    }
  }
  throw std::runtime_error(path.string() +
                           ": no <camera> with a perspectiveProjWithDistortion or perspectiveProjWithoutDistortion "
                           "<model> (ViSP's camera XML, as vpXmlParserCamera writes it)");
}

std::string cameraKalibrYamlString(const Camera& camera) {
  camera.validate();
  std::string model = "radtan";
  std::vector<double> d;
  if (camera.lens == LensModel::Fisheye) {
    model = "equidistant";
    d = coefficientsOf(camera);
  } else if (camera.distortionCount() == 0) {
    model = "none";
  } else {
    d = radtanCoefficients(camera);
  }
  const std::vector<double> intrinsics(camera.params.begin(), camera.params.begin() + kIntrinsicCount);
  std::ostringstream out;
  out << "# Kalibr camchain written by mire (doc/file-formats.md): pinhole projection, " << model << " distortion.\n"
      << "cam0:\n"
      << "  camera_model: pinhole\n"
      << "  intrinsics: " << numberList(intrinsics) << "\n"
      << "  distortion_model: " << model << "\n"
      << "  distortion_coeffs: " << numberList(d) << "\n"
      << "  resolution: [" << camera.width << ", " << camera.height << "]\n"
      << "  cam_overlaps: []\n"
      << "  rostopic: /cam0/image_raw\n";
  return out.str();
}

std::string cameraString(const Camera& camera, CameraFormat format, const std::string& camera_name) {
  switch (format) {
    case CameraFormat::OpenCV:
      return cameraYamlString(camera);
    case CameraFormat::Ros:
      return cameraRosYamlString(camera, camera_name);
    case CameraFormat::Visp:
      return cameraVispXmlString(camera, camera_name);
    case CameraFormat::Kalibr:
      return cameraKalibrYamlString(camera);
    case CameraFormat::Mrcal:
      return cameraMrcalString(camera);
  }
  return cameraYamlString(camera);
}

bool formatHoldsCovariance(CameraFormat format) {
  return format == CameraFormat::OpenCV || format == CameraFormat::Ros || format == CameraFormat::Mrcal;
}

namespace {

// The projection difference between two cameras of one image size, over every 8th pixel.
void measureLoss(const Camera& camera, ConversionLoss* loss) {
  double sum = 0.0;
  int count = 0;
  for (int v = 0; v <= camera.height; v += 8)
    for (int u = 0; u <= camera.width; u += 8) {
      const Eigen::Vector2d pixel(u - 0.5, v - 0.5);
      Eigen::Vector2d ray, back;
      if (!camera.unproject(pixel, &ray) || !loss->written.project({ray.x(), ray.y(), 1.0}, &back)) continue;
      const double e = (back - pixel).norm();
      sum += e * e;
      loss->max_px = std::max(loss->max_px, e);
      ++count;
    }
  loss->rms_px = count > 0 ? std::sqrt(sum / count) : 0.0;
}

// The non-zero coefficients from index `first` on (names), set to zero in `written`.
std::string dropCoefficients(const Camera& camera, std::size_t first, Camera* written) {
  const std::vector<std::string> names = camera.parameterNames();
  std::string lost;
  for (std::size_t i = kIntrinsicCount + first; i < camera.params.size(); ++i)
    if (camera.params[i] != 0.0) {
      lost += (lost.empty() ? "" : " ") + names[i];
      written->params[i] = 0.0;
    }
  return lost;
}

}  // namespace

ConversionLoss conversionLoss(const Camera& camera, CameraFormat format) {
  camera.validate();
  ConversionLoss loss;
  loss.written = camera;
  const bool fisheye = camera.lens == LensModel::Fisheye;
  switch (format) {
    case CameraFormat::OpenCV:
    case CameraFormat::Ros:
      return loss;
    case CameraFormat::Mrcal:
      if (fisheye) throw std::invalid_argument("mrcal has no equidistant (OpenCV fisheye) model: write ros or kalibr");
      return loss;
    case CameraFormat::Kalibr:
      if (fisheye || camera.distortionCount() == 0) return loss;
      // radtan: k1 k2 p1 p2; the rest dropped.
      loss.lost = dropCoefficients(camera, 4, &loss.written);
      break;
    case CameraFormat::Visp: {
      if (fisheye)
        throw std::invalid_argument(
            "ViSP's camera XML has no fisheye (equidistant) model: write ros, kalibr or opencv");
      if (camera.distortionCount() == 0) return loss;
      // One radial term: what ViSP's reader gives back from the file the writer fits.
      loss.lost = dropCoefficients(camera, 1, &loss.written);
      if (!loss.lost.empty()) {
        // The k1 ViSP's reader gives back: the writer's least-squares kud.
        const std::string xml = cameraVispXmlString(camera, "loss");
        const auto begin = xml.find("<kud>") + 5;
        loss.written.params[kIntrinsicCount] = std::stod(xml.substr(begin, xml.find("</kud>") - begin));
      }
      break;
    }
  }
  if (!loss.lost.empty()) measureLoss(camera, &loss);
  return loss;
}

}  // namespace mire::calibration
