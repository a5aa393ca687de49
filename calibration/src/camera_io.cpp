// camera.yaml (BRIEF §10) and ViSP's camera XML.
#include "mire/calibration/camera_io.hpp"

#include <opencv2/core.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::calibration {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& key, const std::string& what) {
  throw std::runtime_error(file + ": key '" + key + "': " + what);
}

cv::Mat readMatrix(const cv::FileNode& node, const std::string& file, const std::string& key) {
  cv::Mat matrix;
  try {
    node >> matrix;
  } catch (const cv::Exception&) {
    fail(file, key, "not an OpenCV matrix (!!opencv-matrix)");
  }
  if (matrix.empty()) fail(file, key, "not an OpenCV matrix (!!opencv-matrix)");
  if (matrix.channels() != 1) fail(file, key, "must have one channel");
  cv::Mat values;
  matrix.convertTo(values, CV_64F);
  return values;
}

std::vector<double> readNumberList(const cv::FileNode& node, const std::string& file, const std::string& key) {
  if (!node.isSeq()) fail(file, key, "must be a list of numbers");
  std::vector<double> values;
  for (const cv::FileNode& item : node) {
    if (!item.isReal() && !item.isInt()) fail(file, key, "must be a list of numbers");
    values.push_back(static_cast<double>(item));
  }
  return values;
}

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
      sample.distorted = Eigen::Vector2d((pixel.x() - camera.cx()) / camera.fx(), (pixel.y() - camera.cy()) / camera.fy());
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
    if (c == '&') escaped += "&amp;";
    else if (c == '<') escaped += "&lt;";
    else if (c == '>') escaped += "&gt;";
    else escaped += c;
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

Camera readCameraYaml(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(file + ": cannot open camera file");
  cv::FileStorage storage;
  try {
    storage.open(file, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& error) {
    throw std::runtime_error(file + ": not a valid OpenCV YAML camera file (" + error.err + ")");
  }
  if (!storage.isOpened()) throw std::runtime_error(file + ": cannot open camera file");

  const auto integer = [&](const char* key) {
    const cv::FileNode node = storage[key];
    if (node.empty()) fail(file, key, "missing");
    if (!node.isInt()) fail(file, key, "must be an integer");
    const int value = static_cast<int>(node);
    if (value <= 0) fail(file, key, "must be positive");
    return value;
  };
  Camera camera;
  camera.width = integer("image_width");
  camera.height = integer("image_height");

  if (storage["camera_matrix"].empty()) fail(file, "camera_matrix", "missing");
  const cv::Mat k = readMatrix(storage["camera_matrix"], file, "camera_matrix");
  if (k.rows != 3 || k.cols != 3) fail(file, "camera_matrix", "must be 3x3");
  if (k.at<double>(0, 1) != 0.0) fail(file, "camera_matrix", "skew (element 0,1) must be 0: mire's model has none");
  if (k.at<double>(1, 0) != 0.0 || k.at<double>(2, 0) != 0.0 || k.at<double>(2, 1) != 0.0 || k.at<double>(2, 2) != 1.0)
    fail(file, "camera_matrix", "must be [fx 0 cx; 0 fy cy; 0 0 1]");

  if (storage["distortion_coefficients"].empty()) fail(file, "distortion_coefficients", "missing");
  const cv::Mat d = readMatrix(storage["distortion_coefficients"], file, "distortion_coefficients");
  if (d.rows != 1 && d.cols != 1) fail(file, "distortion_coefficients", "must be 1xN or Nx1");
  const int count = static_cast<int>(d.total());
  if (count != 0 && !isSupportedDistortionCount(count))
    fail(file, "distortion_coefficients", "has " + std::to_string(count) + " values; 0, 4, 5, 8 or 12 are supported");
  camera.params = {k.at<double>(0, 0), k.at<double>(1, 1), k.at<double>(0, 2), k.at<double>(1, 2)};
  for (int i = 0; i < count; ++i) camera.params.push_back(d.at<double>(i));

  if (!storage["model"].empty()) {
    const cv::FileNode node = storage["model"];
    const std::string model = node.isString() ? node.string() : std::string();
    // pinhole is written with 4 zero coefficients, so OpenCV's readers get a usable vector.
    const bool zero = std::all_of(camera.params.begin() + kIntrinsicCount, camera.params.end(), [](double c) { return c == 0.0; });
    if (model == "fisheye" && count == 4) camera.lens = LensModel::Fisheye;
    else if (model == "pinhole" && zero) camera.params.resize(kIntrinsicCount);
    else if (model != "opencv" && model != modelName(count))
      fail(file, "model", "'" + model + "' does not describe " + std::to_string(count) + " OpenCV coefficients (expected \"" +
                              modelName(count) + "\" or \"opencv\")");
  }
  if (!storage["rms_px"].empty()) {
    const cv::FileNode node = storage["rms_px"];
    if (!node.isReal() && !node.isInt()) fail(file, "rms_px", "must be a number");
    camera.rms_px = static_cast<double>(node);
    if (!(camera.rms_px >= 0.0) || !std::isfinite(camera.rms_px)) fail(file, "rms_px", "must be finite and >= 0");
  }
  const std::vector<std::string> names = camera.parameterNames();
  if (!storage["covariance"].empty()) {
    const cv::Mat c = readMatrix(storage["covariance"], file, "covariance");
    const int n = static_cast<int>(camera.params.size());
    if (c.rows != n || c.cols != n)
      fail(file, "covariance", "must be " + std::to_string(n) + "x" + std::to_string(n) + " (one row per parameter)");
    // The file's order, by name; defaults to this camera's order.
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    if (!storage["covariance_parameters"].empty()) {
      const cv::FileNode list = storage["covariance_parameters"];
      if (!list.isSeq() || static_cast<int>(list.size()) != n)
        fail(file, "covariance_parameters", "must list the " + std::to_string(n) + " parameter names");
      int i = 0;
      for (const cv::FileNode& item : list) {
        const std::string name = item.isString() ? item.string() : std::string();
        const auto found = std::find(names.begin(), names.end(), name);
        if (found == names.end()) fail(file, "covariance_parameters", "unknown parameter '" + name + "'");
        order[i++] = static_cast<int>(found - names.begin());
      }
      std::vector<int> sorted = order;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        fail(file, "covariance_parameters", "names a parameter twice");
    }
    camera.covariance = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) camera.covariance(order[i], order[j]) = c.at<double>(i, j);
    if (!camera.covariance.allFinite()) fail(file, "covariance", "must be finite");
    const double scale = std::max(1e-300, camera.covariance.cwiseAbs().maxCoeff());
    if ((camera.covariance - camera.covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
      fail(file, "covariance", "must be symmetric");
    for (int i = 0; i < n; ++i)
      if (camera.covariance(i, i) < 0.0) fail(file, "covariance", "has a negative variance for " + names[i]);
  } else if (!storage["covariance_parameters"].empty()) {
    fail(file, "covariance_parameters", "given without 'covariance'");
  }
  if (!storage["sigma"].empty()) {
    // Derived from the covariance (written for people); checked for size only.
    const std::vector<double> sigma = readNumberList(storage["sigma"], file, "sigma");
    if (sigma.size() != camera.params.size())
      fail(file, "sigma", "must have " + std::to_string(camera.params.size()) + " values (one per parameter)");
  }
  try {
    camera.validate();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(file + ": " + error.what());
  }
  return camera;
}

std::string cameraYamlString(const Camera& camera) {
  camera.validate();
  cv::FileStorage storage(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  storage.writeComment(
      " mire camera (BRIEF §10). OpenCV keys: pixels, OpenCV's pixel convention (integer coordinates at pixel centres);\n"
      " distortion in OpenCV's order k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]. mire keys: model, rms_px (reprojection RMS, px),\n"
      " covariance of the parameters in the order of covariance_parameters (pixels^2 for fx fy cx cy, unitless^2 otherwise),\n"
      " sigma = square roots of its diagonal.");
  storage << "image_width" << camera.width;
  storage << "image_height" << camera.height;
  storage << "model" << camera.modelName();
  const cv::Matx33d k(camera.fx(), 0.0, camera.cx(), 0.0, camera.fy(), camera.cy(), 0.0, 0.0, 1.0);
  storage << "camera_matrix" << cv::Mat(k);
  const cv::Mat d = camera.distortionCount() == 0
                        ? cv::Mat(cv::Mat::zeros(1, 4, CV_64F))  // pinhole: OpenCV's readers expect a vector
                        : cv::Mat(1, camera.distortionCount(), CV_64F, const_cast<double*>(camera.params.data() + kIntrinsicCount));
  storage << "distortion_coefficients" << d;
  storage << "rms_px" << camera.rms_px;
  if (camera.covariance.size() != 0) {
    const int n = static_cast<int>(camera.params.size());
    cv::Mat c(n, n, CV_64F);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) c.at<double>(i, j) = camera.covariance(i, j);
    storage << "covariance" << c;
    storage << "covariance_parameters" << "[";
    for (const std::string& name : camera.parameterNames()) storage << name;
    storage << "]";
    storage << "sigma" << "[";
    for (const double sigma : camera.sigmas()) storage << sigma;
    storage << "]";
  }
  return storage.releaseAndGetString();
}

std::string cameraVispXmlString(const Camera& camera, const std::string& camera_name) {
  camera.validate();
  const std::vector<FieldSample> samples = sampleField(camera);
  // ViSP (3.5) perspectiveProjWithDistortion: u = u0 + px·x·(1 + kud·r²) with (x, y) the
  // undistorted ray, and back x = (u − u0)/px·(1 + kdu·r_d²). Each single term is fitted
  // by least squares in pixels to OpenCV's model over a 33 × 33 grid covering the image.
  const OneTermFit kud = fitOneRadialTerm(
      camera, samples, [](const FieldSample& s) { return s.undistorted; }, [](const FieldSample& s) { return s.distorted; });
  const OneTermFit kdu = fitOneRadialTerm(
      camera, samples, [](const FieldSample& s) { return s.distorted; }, [](const FieldSample& s) { return s.undistorted; });

  const std::vector<std::string> names = camera.parameterNames();
  std::string lost;
  for (std::size_t i = kIntrinsicCount + 1; i < camera.params.size(); ++i)
    lost += (lost.empty() ? "" : ", ") + names[i] + " = " + number(camera.params[i]);
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n"
      << "<root>\n"
      << "  <!-- Written by mire from an OpenCV camera (" << modelName(camera.distortionCount()) << ", k1 = "
      << number(camera.params[kIntrinsicCount]) << ").\n"
      << "       ViSP's model has one radial term each way: kud and kdu are least-squares fits of OpenCV's\n"
      << "       whole distortion over the image (residual kud: RMS " << shortNumber(kud.rms_px) << " px, max "
      << shortNumber(kud.max_px) << " px; kdu: RMS " << shortNumber(kdu.rms_px) << " px, max " << shortNumber(kdu.max_px)
      << " px).\n"
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
