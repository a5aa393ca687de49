#pragma once
// poses.csv and its covariance side file (doc/file-formats.md, doc/measurement.md).
//
// poses.csv: one row per pose, header
//   pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,
//   sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px
// then mire's extra columns:
//   sigma_pixel_tx_mm ... sigma_pixel_rz_deg            σ from the images' pixel noise alone
//   sigma_intrinsics_tx_mm ... sigma_intrinsics_rz_deg  σ from the camera's covariance alone
//   reduced_chi2                             whitened residual Σr²/(2N−6) (≫ 1: systematic
//                                            feature errors; the total σ is inflated by it;
//                                            one image: 1 by construction, σ from the residuals)
//   features                                 features used in the fit
//   ambiguous,ambiguity_ratio                planar flip flag (0/1) and cost(second)/cost(best)
//   flags                                    ';'-separated codes, empty when none
//                                            (campaign_screening.hpp, doc/measurement.md, "Imperfect campaigns")
// t and r are cTm (r a rotation vector, cv::Rodrigues); σ = total (features + intrinsics).
//
// poses_covariance.csv: the full 6×6 covariances, 24 rows per pose, header
//   pose_id,part,row,tx,ty,tz,rx,ry,rz
// part ∈ {total, features, intrinsics, pixel_noise}: total = features + intrinsics;
// features = pixel_noise × max(1, reduced_chi2); row ∈ {tx,ty,tz,rx,ry,rz};
// SI units: m², m·rad, rad².
#include "mire/metrology/pose_estimation.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mire::metrology {

struct MeasuredPose {
  // A constructor (not an aggregate) so that {id, used, total, estimate} still builds one
  // without naming the flags.
  MeasuredPose() = default;
  MeasuredPose(std::string id, int used, int total, PoseEstimate pose_estimate, std::vector<std::string> pose_flags = {})
      : pose_id(std::move(id)),
        images_used(used),
        images_total(total),
        estimate(std::move(pose_estimate)),
        flags(std::move(pose_flags)) {}

  std::string pose_id;
  int images_used = 0;
  int images_total = 0;
  PoseEstimate estimate;           // must be valid
  std::vector<std::string> flags;  // written ';'-separated in the `flags` column
};

std::string posesCsvString(const std::vector<MeasuredPose>& poses);
std::string posesCovarianceCsvString(const std::vector<MeasuredPose>& poses);

// Writes both files atomically (support::writeFileAtomically).
void writePosesCsv(const std::filesystem::path& path, const std::vector<MeasuredPose>& poses);
void writePosesCovarianceCsv(const std::filesystem::path& path, const std::vector<MeasuredPose>& poses);

// poses.csv is read back by mechanism::readPosesCsv (mire identify), the one reader of the format.

}  // namespace mire::metrology
