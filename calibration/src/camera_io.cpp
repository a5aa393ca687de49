// ViSP's camera XML writer (camera.yaml and ROS YAML are in camera_yaml.cpp).
#include "mire/calibration/camera_io.hpp"

#include <opencv2/core.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::calibration {
namespace {

// "opencv" or "opencv<N>" with N the coefficient count.
std::string modelName(int distortion_count) { return "opencv" + std::to_string(distortion_count); }

// Sample pixels over the whole image, and their exact undistorted normalised rays.
struct FieldSample {
  Eigen::Vector2d distorted;    // (u − cx)/fx, (v − cy)/fy
  Eigen::Vector2d undistorted;  // the ray's (x, y)
};
std::vector<FieldSample> sampleField(const Camera& camera) {
  std::vector<FieldSample> samples;
  constexpr int kSteps = 32;
  for (int i = 0; i <= kSteps; ++i) {
    for (int j = 0; j <= kSteps; ++j) {
      const Eigen::Vector2d pixel(-0.5 + camera.width * static_cast<double>(j) / kSteps,
                                  -0.5 + camera.height * static_cast<double>(i) / kSteps);
      FieldSample sample;
      if (!camera.unproject(pixel, &sample.undistorted)) continue;
      sample.distorted =
          Eigen::Vector2d((pixel.x() - camera.cx()) / camera.fx(), (pixel.y() - camera.cy()) / camera.fy());
      samples.push_back(sample);
    }
  }
  return samples;
}

struct OneTermFit {
  double coefficient = 0.0;
  double rms_px = 0.0;
  double max_px = 0.0;
};

// Least squares, in pixels, of `to` ≈ from·(1 + k·|from|²) over the samples.
template <typename From, typename To>
OneTermFit fitOneRadialTerm(const Camera& camera, const std::vector<FieldSample>& samples, From from, To to) {
  double numerator = 0.0, denominator = 0.0;
  const Eigen::Vector2d f(camera.fx(), camera.fy());
  for (const FieldSample& sample : samples) {
    const Eigen::Vector2d a = from(sample), b = to(sample);
    const Eigen::Vector2d basis = a.squaredNorm() * a.cwiseProduct(f);
    const Eigen::Vector2d target = (b - a).cwiseProduct(f);
    numerator += basis.dot(target);
    denominator += basis.squaredNorm();
  }
  OneTermFit fit;
  fit.coefficient = denominator > 0.0 ? numerator / denominator : 0.0;
  double sum = 0.0;
  for (const FieldSample& sample : samples) {
    const Eigen::Vector2d a = from(sample), b = to(sample);
    const double e = ((a * (1.0 + fit.coefficient * a.squaredNorm()) - b).cwiseProduct(f)).norm();
    sum += e * e;
    fit.max_px = std::max(fit.max_px, e);
  }
  fit.rms_px = samples.empty() ? 0.0 : std::sqrt(sum / samples.size());
  return fit;
}

std::string number(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

std::string escapeXml(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '&')
      escaped += "&amp;";
    else if (c == '<')
      escaped += "&lt;";
    else if (c == '>')
      escaped += "&gt;";
    else
      escaped += c;
  }
  return escaped;
}

std::string shortNumber(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

}  // namespace

namespace {
// ViSP's perspectiveProjWithoutDistortion: the pinhole camera, exactly.
std::string vispPinholeXml(const Camera& camera, const std::string& camera_name) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n<root>\n"
      << "  <!-- Written by mire from a pinhole camera (no distortion). Pixel convention: integer coordinates\n"
      << "       at pixel centres (as OpenCV). -->\n"
      << "  <camera>\n    <name>" << escapeXml(camera_name) << "</name>\n"
      << "    <image_width>" << camera.width << "</image_width>\n"
      << "    <image_height>" << camera.height << "</image_height>\n"
      << "    <model>\n      <type>perspectiveProjWithoutDistortion</type>\n"
      << "      <px>" << camera.fx() << "</px>\n      <py>" << camera.fy() << "</py>\n"
      << "      <u0>" << camera.cx() << "</u0>\n      <v0>" << camera.cy() << "</v0>\n"
      << "    </model>\n  </camera>\n</root>\n";
  return xml.str();
}
}  // namespace

std::string cameraVispXmlString(const Camera& camera, const std::string& camera_name) {
  camera.validate();
  if (camera.lens == LensModel::Fisheye)
    throw std::invalid_argument("ViSP's camera XML has no fisheye (equidistant) model: write ros, kalibr or opencv");
  if (camera.distortionCount() == 0) return vispPinholeXml(camera, camera_name);
  const std::vector<FieldSample> samples = sampleField(camera);
  // ViSP (3.5) perspectiveProjWithDistortion: u = u0 + px·x·(1 + kud·r²) with (x, y) the
  // undistorted ray, and back x = (u − u0)/px·(1 + kdu·r_d²). Each single term is fitted
  // by least squares in pixels to OpenCV's model over a 33 × 33 grid covering the image.
  const OneTermFit kud = fitOneRadialTerm(
      camera, samples, [](const FieldSample& s) { return s.undistorted; },
      [](const FieldSample& s) { return s.distorted; });
  const OneTermFit kdu = fitOneRadialTerm(
      camera, samples, [](const FieldSample& s) { return s.distorted; },
      [](const FieldSample& s) { return s.undistorted; });

  const std::vector<std::string> names = camera.parameterNames();
  std::string lost;
  for (std::size_t i = kIntrinsicCount + 1; i < camera.params.size(); ++i)
    lost += (lost.empty() ? "" : ", ") + names[i] + " = " + number(camera.params[i]);
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n"
      << "<root>\n"
      << "  <!-- Written by mire from an OpenCV camera (" << modelName(camera.distortionCount())
      << ", k1 = " << number(camera.params[kIntrinsicCount]) << ").\n"
      << "       ViSP's model has one radial term each way: kud and kdu are least-squares fits of OpenCV's\n"
      << "       whole distortion over the image (residual kud: RMS " << shortNumber(kud.rms_px) << " px, max "
      << shortNumber(kud.max_px) << " px; kdu: RMS " << shortNumber(kdu.rms_px) << " px, max "
      << shortNumber(kdu.max_px) << " px).\n"
      << "       Lost in the conversion: " << (lost.empty() ? "nothing" : lost) << ".\n"
      << "       Pixel convention: integer coordinates at pixel centres (as OpenCV). -->\n"
      << "  <camera>\n"
      << "    <name>" << escapeXml(camera_name) << "</name>\n"
      << "    <image_width>" << camera.width << "</image_width>\n"
      << "    <image_height>" << camera.height << "</image_height>\n"
      << "    <model>\n"
      << "      <type>perspectiveProjWithDistortion</type>\n"
      << "      <px>" << camera.fx() << "</px>\n"
      << "      <py>" << camera.fy() << "</py>\n"
      << "      <u0>" << camera.cx() << "</u0>\n"
      << "      <v0>" << camera.cy() << "</v0>\n"
      << "      <kud>" << kud.coefficient << "</kud>\n"
      << "      <kdu>" << kdu.coefficient << "</kdu>\n"
      << "    </model>\n"
      << "  </camera>\n"
      << "</root>\n";
  return xml.str();
}

}  // namespace mire::calibration
