#pragma once
// The side file of the calibration error shared by every pose (doc/uncertainty.md "Shared
// terms"): <stem>_shared.csv beside poses.csv, read by `mire identify`.
//   kind,id,row,<k_1>,...,<k_n>          header: the camera's parameter names (camera.yaml order)
//   covariance,camera,<k_i>,...          n rows: the camera's covariance Σ_k (SI / px units)
//   sensitivity,<pose_id>,<tx..rz>,...   6 rows per pose: ∂(t [m], r [rad])/∂k
// The per-pose `intrinsics` part of poses_covariance.csv is D Σ_k Dᵀ of these.
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/poses_csv.hpp"

namespace mire::metrology {

std::filesystem::path sharedTermSidePath(const std::filesystem::path& poses_csv);
// Empty string when the camera has no covariance or no pose has a sensitivity.
std::string sharedTermCsvString(const calibration::Camera& camera, const std::vector<MeasuredPose>& poses);
// Writes the file atomically; returns false (nothing written) when there is nothing to write.
bool writeSharedTermCsv(const std::filesystem::path& path, const calibration::Camera& camera,
                        const std::vector<MeasuredPose>& poses);

}  // namespace mire::metrology
