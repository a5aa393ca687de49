// camera.yaml (OpenCV keys + mire's, doc/file-formats.md) and ROS camera_info YAML, read by one
// reader through mire::support's YAML layer, and written as plain YAML.
#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/support/yaml.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mire::calibration {
namespace {

using support::YamlNode;
using support::YamlRange;

// Accepted spellings, mire's (= OpenCV's calibration samples') first.
const std::vector<std::string> kWidthKeys{"image_width", "width", "imageWidth"};
const std::vector<std::string> kHeightKeys{"image_height", "height", "imageHeight"};
const std::vector<std::string> kSizeKeys{"image_size", "imageSize", "cameraResolution", "resolution"};
const std::vector<std::string> kMatrixKeys{"camera_matrix", "cameraMatrix", "K"};
const std::vector<std::string> kDistortionKeys{
    "distortion_coefficients", "dist_coeffs", "distCoeffs", "dist_coeff", "distortion_coeffs", "D"};
const std::vector<std::string> kMireKeys{"model", "rms_px", "covariance", "covariance_parameters", "sigma", "name"};
// Written beside the camera by OpenCV's calibration samples and apps, by ROS, and by
// `mire calibrate`: accepted and ignored.
const std::vector<std::string> kIgnoredKeys{"calibration_time",
                                            "calibrationDate",
                                            "nr_of_frames",
                                            "nframes",
                                            "framesCount",
                                            "board_width",
                                            "board_height",
                                            "square_size",
                                            "marker_size",
                                            "aspectRatio",
                                            "fix_aspect_ratio",
                                            "flags",
                                            "flagValue",
                                            "avg_reprojection_error",
                                            "per_view_reprojection_errors",
                                            "extrinsic_parameters",
                                            "image_points",
                                            "grid_points",
                                            "cameraMatrix_std_dev",
                                            "dist_coeffs_std_dev",
                                            "camera_name",
                                            "distortion_model",
                                            "rectification_matrix",
                                            "projection_matrix",
                                            "sigma_px",
                                            "views_used",
                                            "views_rejected",
                                            "points_used",
                                            "points_rejected",
                                            "target_refined",
                                            "sigma_inflation",
                                            "projection_uncertainty_distance_m",
                                            "projection_uncertainty_px"};

constexpr YamlRange kAnyFinite{-1e300, 1e300};
// |coefficient| beyond this is no lens (k1 = 1e6 puts every point at the image centre).
constexpr double kMaxCoefficient = 1e4;
constexpr int kMaxImageSide = 100000;

std::vector<std::string> knownKeys() {
  std::vector<std::string> keys;
  for (const auto* list :
       {&kWidthKeys, &kHeightKeys, &kSizeKeys, &kMatrixKeys, &kDistortionKeys, &kMireKeys, &kIgnoredKeys})
    keys.insert(keys.end(), list->begin(), list->end());
  return keys;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// The one spelling present among `names`; two spellings of one quantity are an error.
std::optional<YamlNode> findOne(const YamlNode& root, const std::vector<std::string>& names) {
  std::optional<YamlNode> found;
  for (const auto& name : names) {
    auto node = root.find(name);
    if (!node) continue;
    if (found) node->fail("given twice, as '" + found->key() + "' and as '" + name + "'");
    found = node;
  }
  return found;
}

YamlNode requireOne(const YamlNode& root, const std::vector<std::string>& names) {
  auto node = findOne(root, names);
  if (!node)
    throw support::YamlError(root.where() + ": missing key '" + names.front() + "' (or " +
                             joined(std::vector<std::string>(names.begin() + 1, names.end())) + ")");
  return *node;
}

void readImageSize(const YamlNode& root, Camera& camera) {
  if (const auto size = findOne(root, kSizeKeys)) {
    if (findOne(root, kWidthKeys) || findOne(root, kHeightKeys))
      size->fail("given with image_width/image_height: give the size once");
    const auto values = size->items();
    if (values.size() != 2) size->fail("must be [width, height]");
    camera.width = static_cast<int>(values[0].asInt(1, kMaxImageSide));
    camera.height = static_cast<int>(values[1].asInt(1, kMaxImageSide));
    return;
  }
  camera.width = static_cast<int>(requireOne(root, kWidthKeys).asInt(1, kMaxImageSide));
  camera.height = static_cast<int>(requireOne(root, kHeightKeys).asInt(1, kMaxImageSide));
}

void checkIntrinsics(const YamlNode& node, const Camera& camera, double fx, double fy, double cx, double cy);

// fx fy cx cy from [fx 0 cx; 0 fy cy; 0 0 1], checked against the image size.
void readCameraMatrix(const YamlNode& root, Camera& camera) {
  const YamlNode node = requireOne(root, kMatrixKeys);
  const support::YamlMatrix k = node.asMatrix(kAnyFinite);
  if (k.data.size() != 9) node.fail("must be a 3x3 matrix, has " + std::to_string(k.data.size()) + " values");
  const auto at = [&](std::size_t r, std::size_t c) { return k.data[3 * r + c]; };
  if (at(0, 1) != 0.0) node.fail("skew (element 0,1) must be 0: mire's model has none");
  if (at(1, 0) != 0.0 || at(2, 0) != 0.0 || at(2, 1) != 0.0 || at(2, 2) != 1.0)
    node.fail("must be [fx 0 cx; 0 fy cy; 0 0 1]");
  checkIntrinsics(node, camera, at(0, 0), at(1, 1), at(0, 2), at(1, 2));
  camera.params = {at(0, 0), at(1, 1), at(0, 2), at(1, 2)};
}

// Focal lengths and principal point that a camera of this image size can have.
void checkIntrinsics(const YamlNode& node, const Camera& camera, double fx, double fy, double cx, double cy) {
  if (!(fx > 0.0) || !(fy > 0.0))
    node.fail("focal lengths must be positive (fx = " + support::formatMessageNumber(fx) +
              ", fy = " + support::formatMessageNumber(fy) + ")");
  if (fx > 1e6 || fy > 1e6)
    node.fail("focal length over 1e6 px is no camera (fx = " + support::formatMessageNumber(fx) + ")");
  // A principal point far outside the image is a typing error, not a lens.
  if (cx < -0.5 * camera.width || cx > 1.5 * camera.width || cy < -0.5 * camera.height || cy > 1.5 * camera.height)
    node.fail("principal point (" + support::formatMessageNumber(cx) + ", " + support::formatMessageNumber(cy) +
              ") px is far outside the " + std::to_string(camera.width) + " x " + std::to_string(camera.height) +
              " image");
}

std::vector<double> readDistortion(const YamlNode& node) {
  const support::YamlMatrix d = node.asMatrix({-kMaxCoefficient, kMaxCoefficient});
  if (d.rows != 1 && d.cols != 1 && !d.data.empty()) node.fail("must be 1xN or Nx1");
  return d.data;
}

bool allZero(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return v == 0.0; });
}

std::string countText(std::size_t count) {
  return std::to_string(count) + (count == 1 ? " coefficient" : " coefficients");
}

// mire's `model`: opencv, opencv<N>, pinhole, fisheye.
void applyMireModel(const YamlNode& node, std::vector<double>& coefficients, LensModel& lens) {
  const std::string model = node.asString();
  const std::string count = std::to_string(coefficients.size());
  if (model == "pinhole") {
    if (!allZero(coefficients)) node.fail("'pinhole' with non-zero distortion coefficients");
    coefficients.clear();
  } else if (model == "fisheye") {
    if (coefficients.size() != 4) node.fail("'fisheye' needs 4 coefficients k1..k4, the file has " + count);
    lens = LensModel::Fisheye;
  } else if (model == "opencv") {
    if (!isSupportedDistortionCount(static_cast<int>(coefficients.size())))
      node.fail("'opencv' needs 4, 5, 8 or 12 coefficients, the file has " + count);
  } else if (model.rfind("opencv", 0) == 0) {
    if (model != "opencv" + count)
      node.fail("'" + model + "' does not describe the file's " + countText(coefficients.size()) +
                " (expected \"opencv" + count + "\" or \"opencv\")");
  } else {
    node.fail("'" + model + "' is not one of opencv, opencv4, opencv5, opencv8, opencv12, pinhole, fisheye");
  }
}

// ROS camera_info's `distortion_model`.
void applyRosModel(const YamlNode& node, std::vector<double>& coefficients, LensModel& lens) {
  const std::string model = node.asString();
  const std::size_t n = coefficients.size();
  if (model == "plumb_bob") {
    if (n != 0 && n != 4 && n != 5)
      node.fail("'plumb_bob' has 5 coefficients k1 k2 p1 p2 k3, the file has " + std::to_string(n));
  } else if (model == "rational_polynomial") {
    if (n != 8 && n != 12) node.fail("'rational_polynomial' has 8 coefficients, the file has " + std::to_string(n));
  } else if (model == "equidistant" || model == "fisheye") {
    if (n != 4) node.fail("'" + model + "' has 4 coefficients k1..k4, the file has " + std::to_string(n));
    lens = LensModel::Fisheye;
  } else {
    node.fail("'" + model + "' is not one of plumb_bob, rational_polynomial, equidistant");
  }
}

void readLens(const YamlNode& root, Camera& camera) {
  const YamlNode node = requireOne(root, kDistortionKeys);
  std::vector<double> coefficients = readDistortion(node);
  LensModel lens = LensModel::OpenCV;
  const auto mire_model = root.find("model");
  const auto ros_model = root.find("distortion_model");
  if (ros_model) applyRosModel(*ros_model, coefficients, lens);
  if (mire_model) {
    LensModel mire_lens = LensModel::OpenCV;
    applyMireModel(*mire_model, coefficients, mire_lens);
    if (ros_model && mire_lens != lens)
      mire_model->fail("contradicts distortion_model '" + ros_model->asString() + "'");
    lens = mire_lens;
  }
  if (!mire_model && !ros_model && !coefficients.empty() &&
      !isSupportedDistortionCount(static_cast<int>(coefficients.size())))
    node.fail("has " + std::to_string(coefficients.size()) + " values; 0, 4, 5, 8 or 12 are supported");
  camera.lens = lens;
  camera.params.insert(camera.params.end(), coefficients.begin(), coefficients.end());
}

void readCovariance(const YamlNode& root, Camera& camera) {
  const auto node = root.find("covariance");
  const auto names_node = root.find("covariance_parameters");
  if (!node) {
    if (names_node) names_node->fail("given without 'covariance'");
    return;
  }
  const std::vector<std::string> names = camera.parameterNames();
  const int n = static_cast<int>(camera.params.size());
  const support::YamlMatrix c = node->asMatrix(kAnyFinite);
  if (c.rows != n || c.cols != n)
    node->fail("must be " + std::to_string(n) + "x" + std::to_string(n) + " (one row per parameter)");
  std::vector<int> order(static_cast<std::size_t>(n));  // the file's order, by name
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  if (names_node) {
    const auto items = names_node->items();
    if (static_cast<int>(items.size()) != n)
      names_node->fail("must list the " + std::to_string(n) + " parameter names");
    std::vector<bool> seen(static_cast<std::size_t>(n), false);
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string name = items[i].asString();
      const auto found = std::find(names.begin(), names.end(), name);
      if (found == names.end())
        items[i].fail("unknown parameter '" + name + "' (this camera has " + joined(names) + ")");
      const auto index = static_cast<std::size_t>(found - names.begin());
      if (seen[index]) items[i].fail("names '" + name + "' twice");
      seen[index] = true;
      order[i] = static_cast<int>(index);
    }
  }
  camera.covariance = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      camera.covariance(order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(j)]) = c(i, j);
  const double scale = std::max(1e-300, camera.covariance.cwiseAbs().maxCoeff());
  if ((camera.covariance - camera.covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    node->fail("must be symmetric");
  for (int i = 0; i < n; ++i)
    if (camera.covariance(i, i) < 0.0) node->fail("has a negative variance for " + names[static_cast<std::size_t>(i)]);
}

void readQuality(const YamlNode& root, Camera& camera) {
  if (const auto rms = root.find("rms_px")) camera.rms_px = rms->asDouble({0.0, 1e6});
  readCovariance(root, camera);
  if (const auto sigma = root.find("sigma")) {
    // Derived from the covariance (written for people); checked for size and sign only.
    const std::vector<double> values = sigma->asDoubles({0.0, 1e300});
    if (values.size() != camera.params.size())
      sigma->fail("must have " + std::to_string(camera.params.size()) + " values (one per parameter)");
  }
}

// ---- writing ----

std::string numberList(const double* values, int count) {
  std::string text = "[";
  for (int i = 0; i < count; ++i) text += std::string(i ? ", " : " ") + support::formatYamlNumber(values[i]);
  return text + " ]";
}

// An OpenCV matrix node: "!!opencv-matrix" with rows, cols, dt, data (one line per row).
std::string openCvMatrix(const std::string& key, const double* values, int rows, int cols) {
  std::ostringstream out;
  out << key << ": !!opencv-matrix\n  rows: " << rows << "\n  cols: " << cols << "\n  dt: d\n  data: [";
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) out << (c == 0 ? " " : ", ") << support::formatYamlNumber(values[r * cols + c]);
    if (r + 1 < rows && cols > 1) out << ",\n        ";
  }
  out << " ]\n";
  return out.str();
}

// A ROS matrix node: rows, cols, data (camera_calibration's layout, no tag).
std::string rosMatrix(const std::string& key, const double* values, int rows, int cols) {
  return key + ":\n  rows: " + std::to_string(rows) + "\n  cols: " + std::to_string(cols) +
         "\n  data: " + numberList(values, rows * cols) + "\n";
}

std::string mireModelName(const Camera& camera) {
  if (camera.lens == LensModel::Fisheye) return "fisheye";
  if (camera.distortionCount() == 0) return "pinhole";
  return "opencv" + std::to_string(camera.distortionCount());
}

// Coefficients as written: a pinhole camera gets OpenCV's five zeros, which every OpenCV
// consumer reads as no distortion (`model: pinhole` tells mire).
std::vector<double> writtenCoefficients(const Camera& camera) {
  std::vector<double> d(camera.params.begin() + kIntrinsicCount, camera.params.end());
  if (d.empty()) d.assign(5, 0.0);
  return d;
}

// covariance (OpenCV's tagged matrix, or ROS's untagged layout), covariance_parameters, sigma;
// nothing without a covariance.
std::string covarianceKeys(const Camera& camera, bool opencv_tag = true) {
  if (camera.covariance.size() == 0) return {};
  const int n = static_cast<int>(camera.params.size());
  std::vector<double> c;  // row-major
  c.reserve(static_cast<std::size_t>(camera.covariance.size()));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) c.push_back(camera.covariance(i, j));
  std::string out = opencv_tag ? openCvMatrix("covariance", c.data(), n, n) : rosMatrix("covariance", c.data(), n, n);
  out += "covariance_parameters: [ " + joined(camera.parameterNames()) + " ]\n";
  const std::vector<double> sigma = camera.sigmas();
  out += "sigma: " + numberList(sigma.data(), static_cast<int>(sigma.size())) + "\n";
  return out;
}

}  // namespace

Camera readCameraYaml(const std::filesystem::path& path) {
  const support::YamlFile file = support::YamlFile::load(path);
  return cameraFromYaml(file.rootMap());
}

Camera cameraFromYaml(const YamlNode& root) {
  root.requireMap();
  root.checkKeys(knownKeys());
  Camera camera;
  readImageSize(root, camera);
  readCameraMatrix(root, camera);
  readLens(root, camera);
  readQuality(root, camera);
  if (const auto name = findOne(root, {"name", "camera_name"})) camera.name = name->asString();
  try {
    camera.validate();
  } catch (const std::invalid_argument& error) {
    root.fail(error.what());
  }
  return camera;
}

std::filesystem::path covarianceSideFile(const std::filesystem::path& camera_path) {
  return camera_path.string() + ".covariance.yaml";
}

void readCovarianceSideFile(const std::filesystem::path& camera_path, Camera& camera) {
  const std::filesystem::path side = covarianceSideFile(camera_path);
  std::error_code ec;
  if (!std::filesystem::exists(side, ec)) return;
  const support::YamlFile file = support::YamlFile::load(side);
  const YamlNode& root = file.rootMap();
  root.checkKeys({"name", "rms_px", "covariance", "covariance_parameters", "sigma"});
  if (!root.has("covariance")) root.fail("missing key 'covariance'");
  if (!root.has("covariance_parameters")) root.fail("missing key 'covariance_parameters'");
  readQuality(root, camera);
  if (const auto name = root.find("name")) camera.name = name->asString();
}

std::string cameraCovarianceSideFileString(const Camera& camera) {
  std::ostringstream out;
  out << "%YAML 1.2\n---\n# mire: what the camera file beside this one cannot hold (doc/file-formats.md, \"Camera "
         "files\"):\n# the covariance of the parameters in the order of covariance_parameters, the reprojection RMS, "
         "the name.\n";
  if (!camera.name.empty()) out << "name: " << support::yamlQuoted(camera.name) << "\n";
  out << "rms_px: " << support::formatYamlNumber(camera.rms_px) << "\n";
  out << covarianceKeys(camera);
  return out.str();
}

Camera readCameraKalibrYaml(const std::filesystem::path& path) {
  const support::YamlFile file = support::YamlFile::load(path);
  const YamlNode& root = file.rootMap();
  const std::vector<std::string> cameras = root.keys();
  if (cameras.size() != 1 || cameras.front() != "cam0")
    root.fail("a Kalibr camchain with " + std::to_string(cameras.size()) + " cameras (" + joined(cameras) +
              "): mire reads a single camera, cam0");
  const YamlNode cam = root.at("cam0");
  cam.checkKeys({"camera_model", "intrinsics", "distortion_model", "distortion_coeffs", "resolution", "cam_overlaps",
                 "rostopic", "T_cn_cnm1", "T_cam_imu", "timeshift_cam_imu", "line_delay"});
  const YamlNode projection = cam.at("camera_model");
  if (projection.asString() != "pinhole")
    projection.fail("'" + projection.asString() + "': mire reads Kalibr's pinhole cameras only");
  Camera camera;
  const auto resolution = cam.at("resolution").items();
  if (resolution.size() != 2) cam.at("resolution").fail("must be [width, height]");
  camera.width = static_cast<int>(resolution[0].asInt(1, kMaxImageSide));
  camera.height = static_cast<int>(resolution[1].asInt(1, kMaxImageSide));
  const YamlNode intrinsics = cam.at("intrinsics");
  camera.params = intrinsics.asDoubles(kAnyFinite);
  if (camera.params.size() != 4) intrinsics.fail("must be [fx, fy, cx, cy]");
  checkIntrinsics(intrinsics, camera, camera.params[0], camera.params[1], camera.params[2], camera.params[3]);
  const YamlNode model = cam.at("distortion_model");
  const YamlNode coefficients_node = cam.at("distortion_coeffs");
  const std::vector<double> coefficients = coefficients_node.asDoubles({-kMaxCoefficient, kMaxCoefficient});
  const std::string name = model.asString();
  const std::size_t expected = name == "none" ? 0 : 4;
  if (name == "equidistant")
    camera.lens = LensModel::Fisheye;
  else if (name != "radtan" && name != "none")
    model.fail("'" + name + "' is not one of radtan, equidistant, none (the models mire shares with Kalibr)");
  if (coefficients.size() != expected)
    coefficients_node.fail("'" + name + "' has " + std::to_string(expected) + " coefficients, the file has " +
                           std::to_string(coefficients.size()));
  camera.params.insert(camera.params.end(), coefficients.begin(), coefficients.end());
  camera.validate();
  return camera;
}

std::string cameraYamlString(const Camera& camera) {
  camera.validate();
  std::ostringstream out;
  out << "%YAML 1.2\n---\n"
      << "# mire camera (doc/file-formats.md). OpenCV keys: pixels, OpenCV's pixel convention (integer coordinates at\n"
      << "# pixel centres); distortion in OpenCV's order k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]], or k1..k4 of\n"
      << "# cv::fisheye for model: fisheye (model: pinhole has none; its five zeros are for OpenCV). mire keys:\n"
      << "# model, rms_px (reprojection RMS, px), covariance of the parameters in the order of\n"
      << "# covariance_parameters (pixels^2 for fx fy cx cy, unitless^2 otherwise), sigma = square roots of its "
         "diagonal.\n";
  out << "image_width: " << camera.width << "\n";
  out << "image_height: " << camera.height << "\n";
  out << "model: " << mireModelName(camera) << "\n";
  const double k[9] = {camera.fx(), 0.0, camera.cx(), 0.0, camera.fy(), camera.cy(), 0.0, 0.0, 1.0};
  out << openCvMatrix("camera_matrix", k, 3, 3);
  const std::vector<double> d = writtenCoefficients(camera);
  out << openCvMatrix("distortion_coefficients", d.data(), 1, static_cast<int>(d.size()));
  out << "rms_px: " << support::formatYamlNumber(camera.rms_px) << "\n";
  if (!camera.name.empty()) out << "name: " << support::yamlQuoted(camera.name) << "\n";
  out << covarianceKeys(camera);
  return out.str();
}

std::string cameraRosYamlString(const Camera& camera, const std::string& camera_name) {
  camera.validate();
  std::string model = "plumb_bob";
  if (camera.lens == LensModel::Fisheye)
    model = "equidistant";
  else if (camera.distortionCount() >= 8)
    model = "rational_polynomial";
  // A pinhole camera has an empty D (image_geometry reads it as no distortion).
  const std::vector<double> d(camera.params.begin() + kIntrinsicCount, camera.params.end());
  const double k[9] = {camera.fx(), 0.0, camera.cx(), 0.0, camera.fy(), camera.cy(), 0.0, 0.0, 1.0};
  const double r[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  // The projection matrix of an unrectified monocular camera: K | 0.
  const double p[12] = {camera.fx(), 0.0, camera.cx(), 0.0, 0.0, camera.fy(), camera.cy(), 0.0, 0.0, 0.0, 1.0, 0.0};
  std::ostringstream out;
  out << "image_width: " << camera.width << "\nimage_height: " << camera.height << "\n";
  out << "camera_name: " << support::yamlQuoted(camera_name) << "\n";
  out << rosMatrix("camera_matrix", k, 3, 3);
  out << "distortion_model: " << model << "\n";
  out << rosMatrix("distortion_coefficients", d.data(), 1, static_cast<int>(d.size()));
  out << rosMatrix("rectification_matrix", r, 3, 3);
  out << rosMatrix("projection_matrix", p, 3, 4);
  if (camera.covariance.size() != 0) {
    // mire's keys (camera_info readers ignore them), in ROS's untagged matrix layout.
    out << "rms_px: " << support::formatYamlNumber(camera.rms_px) << "\n";
    out << covarianceKeys(camera, false);
  }
  return out.str();
}

}  // namespace mire::calibration
