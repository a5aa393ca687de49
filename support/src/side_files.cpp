// The side files' naming rule (side_files.hpp).
#include "mire/support/side_files.hpp"

namespace mire::support {
namespace {

std::filesystem::path withSuffix(const std::filesystem::path& file, const char* suffix) {
  std::filesystem::path out = file;
  out.replace_filename(file.stem().string() + suffix);
  return out;
}

}  // namespace

std::filesystem::path covarianceSidePath(const std::filesystem::path& file) {
  return withSuffix(file, "_covariance.csv");
}

std::filesystem::path sharedTermSidePath(const std::filesystem::path& poses_csv) {
  return withSuffix(poses_csv, "_shared.csv");
}

std::filesystem::path mechanismSidePath(const std::filesystem::path& parameters_yaml) {
  return withSuffix(parameters_yaml, "_mechanism.yaml");
}

}  // namespace mire::support
