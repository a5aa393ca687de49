#pragma once
// One validation layer for what every command reads before the long work starts: input
// files (existing, regular: a FIFO or a device would block or never end), option values,
// camera and target sanity, and the limits of doc/limits.md. Every check throws with a
// message naming the file, the option or the key; UsageError (exit 2) for the command line,
// std::runtime_error (exit 1) for bad input.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/target.hpp"
#include "mire/pipeline/image_check.hpp"

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

// Declared only: the checks' users that register no option need not parse CLI11
// (doc/install.md, "Build time").
namespace CLI {
class Validator;
}

namespace mire::app {

// A wrong command line (exit code 2, see commands.hpp).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Limits (doc/limits.md).
constexpr int kMaxThreads = 256;
using pipeline::kMaxImagePixels;
using pipeline::kMaxImageSide;
constexpr std::size_t kMaxTargetFeatures = 20'000;  // features (corners, circles, tag corners)
constexpr std::size_t kMaxPoses = 1'000'000;        // poses given to identify, rows given to fkm / ikm
constexpr int kMaxPlanCandidates = 100'000;         // plan --candidates (the default is 10 000)
constexpr double kMaxViewDistanceM = 50.0;          // implied target distance: beyond, a unit mistake
constexpr double kMinViewDistanceM = 0.01;

// CLI11 validator: the value parses as a finite number (CLI11's ranges let NaN through).
CLI::Validator finiteNumber();

// An existing regular file the process can read; `option` names it in the message.
void requireInputFile(const std::filesystem::path& path, const std::string& option);
// An existing folder the process can read.
void requireInputFolder(const std::filesystem::path& path, const std::string& option);

// A table of `count` rows read from `file` for `command`: at most kMaxPoses.
void checkRowCount(std::size_t count, const std::string& file, const std::string& command);

// Worker threads from an option value: 0 = all cores, 1..kMaxThreads; else UsageError.
int workerThreads(int requested, const std::string& option);

// The --mounting word (doc/mechanisms.md, "Camera on the effector"): true for camera-on-effector,
// false for camera-fixed; else UsageError naming it.
bool cameraOnEffector(const std::string& mounting);

// Camera sanity (file = where it was read): positive finite focal lengths of comparable size,
// principal point inside the image, distortion coefficients of a plausible size, and a
// covariance (when present) that is symmetric positive semi-definite with positive variances
// of the free parameters.
void checkCamera(const calibration::Camera& camera, const std::filesystem::path& file);

// Target size limit (kMaxTargetFeatures).
void checkTargetSize(const metrology::Target& target, const std::filesystem::path& file);

// The target's distance in every view/pose (m): all beyond 50 m or all under 1 cm means
// target.yaml's sizes are not in metres (e.g. square_size_m: 25 typed in millimetres).
void checkImpliedDistances(const std::vector<double>& distances_m, const std::filesystem::path& target_file,
                           const std::string& what);

}  // namespace mire::app
