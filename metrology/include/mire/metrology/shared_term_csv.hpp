#pragma once
// The side file of the errors shared by every pose (doc/uncertainty.md "Shared terms"):
// <stem>_shared.csv beside poses.csv, read by `mire identify`.
//   kind,id,row,<k_1>,...,<k_n>          header: the camera's parameter names (camera.yaml order),
//                                        then detector_bias_1 … (detector_bias.hpp)
//   covariance,camera,<k_i>,...          the camera's covariance Σ_k (SI / px units)
//   covariance,detector,<bias_i>,...     the detector-bias modes: unit variance each
//   sensitivity,<pose_id>,<tx..rz>,...   6 rows per pose: ∂(t [m], r [rad])/∂k, then the modes
// The per-pose `intrinsics` part of poses_covariance.csv is the camera's part D Σ_k Dᵀ; the
// detector-bias part is inside the pose's `noise` part (its share that every pose repeats).
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/poses_csv.hpp"

namespace mire::metrology {

// Empty string when neither the camera's covariance nor a detector bias is there, or no pose has
// a sensitivity for every column.
std::string sharedTermCsvString(const calibration::Camera& camera, const std::vector<MeasuredPose>& poses,
                                const DetectorBiasTerm& bias = {});
// Writes the file atomically; returns false (nothing written) when there is nothing to write.
bool writeSharedTermCsv(const std::filesystem::path& path, const calibration::Camera& camera,
                        const std::vector<MeasuredPose>& poses, const DetectorBiasTerm& bias = {});

}  // namespace mire::metrology
