#pragma once
// legs.csv (doc/file-formats.md, "legs.csv"): one row per pose × observed leg, the leg's axis in the
// camera frame in Plücker coordinates and its 4×4 covariance in the line perturbation of
// support/line_3d.hpp. Header (extra columns allowed):
//   pose_id,leg,dx,dy,dz,mx_m,my_m,mz_m,c11,c12,c13,c14,c22,c23,c24,c33,c34,c44
// leg 1-based in joint order; c the upper triangle of the covariance of δ = (a1, a2 [rad], b1, b2 [m]).
#include <filesystem>
#include <vector>

#include "mire/mechanism/leg_observation.hpp"

namespace mire::mechanism {

// Throws std::runtime_error "path:line: ..." on a missing column, a non-finite value, a leg outside
// 1..leg_count, a repeated (pose, leg), a direction not of unit length (within 1e-6), a moment not
// ⟂ its direction, or a covariance not positive definite. Directions are renormalised on read.
std::vector<LegObservation> readLegsCsv(const std::filesystem::path& legs_csv, int leg_count);

// Writes legs.csv atomically (17 significant digits).
void writeLegsCsv(const std::filesystem::path& legs_csv, const std::vector<LegObservation>& legs);

}  // namespace mire::mechanism
