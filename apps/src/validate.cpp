#include "validate.hpp"

#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

namespace mire::app {
namespace fs = std::filesystem;

namespace {

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

std::string shortNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

// What kind of non-regular file a path is, for the message.
std::string kindOf(const struct stat& info) {
  if (S_ISDIR(info.st_mode)) return "a folder";
  if (S_ISFIFO(info.st_mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) return "a device";
  if (S_ISSOCK(info.st_mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

CLI::Validator finiteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::size_t used = 0;
        double value = 0.0;
        try {
          value = std::stod(text, &used);
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (used != text.size() || !std::isfinite(value)) return "'" + text + "' is not a finite number";
        return {};
      },
      "FINITE");
}

void requireInputFile(const fs::path& path, const std::string& option) {
  if (path.empty()) throw UsageError(option + ": empty path");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw std::runtime_error(option + " " + quoted(path) + ": no such file");
  if (!S_ISREG(info.st_mode))
    throw std::runtime_error(option + " " + quoted(path) + ": is " + kindOf(info) + ", a regular file is expected");
  if (::access(path.c_str(), R_OK) != 0)
    throw std::runtime_error(option + " " + quoted(path) + ": cannot be read (permission)");
}

void requireInputFolder(const fs::path& path, const std::string& option) {
  if (path.empty()) throw UsageError(option + ": empty path");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw std::runtime_error(option + " " + quoted(path) + ": no such folder");
  if (!S_ISDIR(info.st_mode))
    throw std::runtime_error(option + " " + quoted(path) + ": is " +
                             (S_ISREG(info.st_mode) ? std::string("a file") : kindOf(info)) + ", a folder is expected");
  if (::access(path.c_str(), R_OK | X_OK) != 0)
    throw std::runtime_error(option + " " + quoted(path) + ": cannot be read (permission)");
}

void checkRowCount(std::size_t count, const std::string& file, const std::string& command) {
  if (count > kMaxPoses)
    throw std::runtime_error(file + ": " + std::to_string(count) + " rows; " + command + " handles at most " +
                             std::to_string(kMaxPoses) + " (doc/limits.md): split the file");
}

int workerThreads(int requested, const std::string& option) {
  if (requested < 0 || requested > kMaxThreads)
    throw UsageError(option + " " + std::to_string(requested) + ": expected 0 (all cores) to " +
                     std::to_string(kMaxThreads));
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

bool cameraOnEffector(const std::string& mounting) {
  if (mounting != "camera-fixed" && mounting != "camera-on-effector")
    throw UsageError("--mounting '" + mounting + "': expected camera-fixed or camera-on-effector");
  return mounting == "camera-on-effector";
}

namespace {

void checkIntrinsics(const calibration::Camera& camera, const std::string& where) {
  const double fx = camera.fx(), fy = camera.fy(), cx = camera.cx(), cy = camera.cy();
  const double w = camera.width, h = camera.height;
  if (!(camera.width > 0 && camera.height > 0) || w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxImagePixels)
    throw std::runtime_error(where + ": image size " + std::to_string(camera.width) + "x" +
                             std::to_string(camera.height) + " is outside 1.." + std::to_string(kMaxImageSide) +
                             " px per side and " + std::to_string(kMaxImagePixels / 1'000'000) + " megapixels");
  for (double value : camera.params)
    if (!std::isfinite(value)) throw std::runtime_error(where + ": a camera parameter is not a finite number");
  if (!(fx > 0.0 && fy > 0.0)) throw std::runtime_error(where + ": fx and fy must be > 0 (pixels)");
  if (fx / fy > 10.0 || fy / fx > 10.0)
    throw std::runtime_error(where + ": fx = " + shortNumber(fx) + " and fy = " + shortNumber(fy) +
                             " differ by more than 10x (pixels are not that far from square)");
  if (cx < 0.0 || cx > w || cy < 0.0 || cy > h)
    throw std::runtime_error(where + ": principal point (cx, cy) = (" + shortNumber(cx) + ", " + shortNumber(cy) +
                             ") lies outside the " + std::to_string(camera.width) + "x" +
                             std::to_string(camera.height) + " image");
  // Radial/tangential/thin-prism/tilt coefficients act on normalised coordinates (|x| ~ 1 at
  // most): coefficients beyond 1000 describe no lens (OpenCV's rational model stays far below).
  const std::vector<std::string> names = camera.parameterNames();
  for (std::size_t i = 4; i < camera.params.size(); ++i)
    if (std::abs(camera.params[i]) > 1000.0)
      throw std::runtime_error(where + ": distortion coefficient " + (i < names.size() ? names[i] : std::to_string(i)) +
                               " = " + shortNumber(camera.params[i]) +
                               " is not a plausible lens (|value| <= 1000 expected)");
}

// How much the lens stretches the image corners (distorted / undistorted radius): real lenses
// stay within 0.2 (a fisheye in OpenCV's rational model) and 2 (telephoto pincushion is
// ~1.05); k1 = 100 stretches a 480x360 corner by 3.9 and puts poses hundreds of mm off. The
// fisheye model maps angles, not radii: not checked here.
constexpr double kMinCornerStretch = 0.2, kMaxCornerStretch = 2.0;

void checkDistortionStretch(const calibration::Camera& camera, const std::string& where) {
  if (camera.lens == calibration::LensModel::Fisheye || camera.distortionCount() == 0) return;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(camera.width, 0.0), Eigen::Vector2d(0.0, camera.height),
        Eigen::Vector2d(camera.width, camera.height)}) {
    const Eigen::Vector2d pinhole((corner.x() - camera.cx()) / camera.fx(), (corner.y() - camera.cy()) / camera.fy());
    Eigen::Vector2d ray;
    if (!camera.unproject(corner, &ray) || ray.norm() < 1e-12) continue;
    const double stretch = pinhole.norm() / ray.norm();
    if (stretch < kMinCornerStretch || stretch > kMaxCornerStretch)
      throw std::runtime_error(where + ": the distortion stretches the image corner (" + shortNumber(corner.x()) +
                               ", " + shortNumber(corner.y()) + ") by " + shortNumber(stretch) +
                               " (distorted / undistorted radius; real lenses: " + shortNumber(kMinCornerStretch) +
                               " to " + shortNumber(kMaxCornerStretch) +
                               "): not a plausible lens, check distortion_coefficients (k1 = " +
                               shortNumber(camera.params.size() > 4 ? camera.params[4] : 0.0) + ")");
  }
}

void checkCovariance(const calibration::Camera& camera, const std::string& where) {
  const Eigen::MatrixXd& c = camera.covariance;
  if (c.size() == 0) return;
  const Eigen::Index n = static_cast<Eigen::Index>(camera.params.size());
  if (c.rows() != n || c.cols() != n)
    throw std::runtime_error(where + ": covariance is " + std::to_string(c.rows()) + "x" + std::to_string(c.cols()) +
                             ", expected " + std::to_string(n) + "x" + std::to_string(n));
  if (!c.allFinite()) throw std::runtime_error(where + ": covariance holds a non-finite number");
  const double scale = c.cwiseAbs().maxCoeff();
  if ((c - c.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(scale, 1e-300))
    throw std::runtime_error(where + ": covariance is not symmetric");
  for (Eigen::Index i = 0; i < n; ++i)
    if (c(i, i) < 0.0)
      throw std::runtime_error(where + ": covariance: negative variance of parameter " + std::to_string(i));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(c, Eigen::EigenvaluesOnly);
  const double smallest = solver.eigenvalues().minCoeff(), largest = solver.eigenvalues().maxCoeff();
  if (smallest < -1e-9 * std::max(largest, 0.0))
    throw std::runtime_error(where + ": covariance is not positive semi-definite (eigenvalue " + shortNumber(smallest) +
                             "): it would give negative variances");
}

}  // namespace

void checkCamera(const calibration::Camera& camera, const fs::path& file) {
  const std::string where = file.string();
  if (camera.params.size() < 4) throw std::runtime_error(where + ": fewer than 4 intrinsic parameters");
  checkIntrinsics(camera, where);
  checkDistortionStretch(camera, where);
  checkCovariance(camera, where);
}

void checkTargetSize(const metrology::Target& target, const fs::path& file) {
  const std::size_t count = target.points().size();
  if (count > kMaxTargetFeatures)
    throw std::runtime_error(file.string() + ": the target has " + std::to_string(count) +
                             " features; mire handles at most " + std::to_string(kMaxTargetFeatures));
}

void checkImpliedDistances(const std::vector<double>& distances_m, const fs::path& target_file, const std::string& what) {
  if (distances_m.empty()) return;
  const auto [low, high] = std::minmax_element(distances_m.begin(), distances_m.end());
  if (*low > kMaxViewDistanceM)
    throw std::runtime_error(
        target_file.string() + ": the target would be " + shortNumber(*low) + " to " + shortNumber(*high) +
        " m from the camera in every " + what +
        ": are its sizes in millimetres? target.yaml sizes are in metres (square_size_m: 0.025, not 25)");
  if (*high < kMinViewDistanceM)
    throw std::runtime_error(
        target_file.string() + ": the target would be " + shortNumber(*low) + " to " + shortNumber(*high) +
        " m from the camera in every " + what +
        ": are its sizes in the wrong unit? target.yaml sizes are in metres (square_size_m: 0.025)");
}

}  // namespace mire::app
