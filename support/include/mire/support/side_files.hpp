#pragma once
// The side files that travel beside a data file (doc/file-formats.md): one naming rule for
// every writer and reader.
#include <filesystem>

namespace mire::support {

// "dir/poses.csv" → "dir/poses_covariance.csv": the 6×6 pose covariances beside poses.csv, the
// parameter covariance beside an identified YAML file.
std::filesystem::path covarianceSidePath(const std::filesystem::path& file);

// "dir/poses.csv" → "dir/poses_shared.csv": the error every pose shares (doc/uncertainty.md).
std::filesystem::path sharedTermSidePath(const std::filesystem::path& poses_csv);

// "dir/identified.yaml" → "dir/identified_mechanism.yaml": the description of a described
// mechanism, which the identified file names as its `model:` (doc/mechanisms.md).
std::filesystem::path mechanismSidePath(const std::filesystem::path& parameters_yaml);

}  // namespace mire::support
