#pragma once
// A simulated "true" H4 robot (doc/mechanisms.md, "The simulated true H4"): the ground truth that
// identification is tested against. It carries what model 12 can represent (R, L, l, h, α_i, q0_i errors) AND what it
// cannot (paper §6.3; doc/mechanisms.md, "Evaluation criteria"): per-leg arm/forearm lengths, non-coplanar
// pivots, tilted arm axes (a model-31-like geometry per leg) and imperfect parallelograms that tilt the
// nacelle by ≈0.1°, varying over the workspace.
//
// Physical model (documented in README "The simulated true H4"):
//  * Leg i: arm pivot P_i anywhere in B; arm rotation axis given by the Euler angles (ψ_i, β_i)
//    of paper eq. 17, arm direction V_i = Rz(ψ_i)·Rx(β_i)·Rz(φ_i)·(−1,0,0), φ_i = q̄_i + q0_i;
//    elbow B_i = P_i + L_i·V_i; forearm ‖A_i − B_i‖ = l_i (centre line of the parallelogram).
//  * Nacelle: A_i = c + R_tilt(X)·(ε_i·h·(cosθ, sinθ, 0) + σ_i·d·(0,1,0)) with c = (x, y, z).
//  * Imperfect parallelogram: the two bars of forearm i differ in length by δ_i and are s apart
//    along the arm axis e_i. Closing such a quadrilateral turns its nacelle side by δ_i/s about
//    the normal n_i = e_i × f_i of the parallelogram plane (f_i the forearm direction). The
//    nacelle takes the mean of the four legs' rotations, horizontal part only (its yaw is θ,
//    fixed by the half-nacelles), minus its value at the levelling pose X_0 (the assembly is
//    levelled there): ω(X) = P_xy · ¼ Σ_i (δ_i/s)·(n_i(X) − n_i(X_0)), R_tilt = exp([ω]×).
//    n_i(X) is evaluated at the untilted configuration, so ω is a smooth single-valued function
//    of the pose: the IKM and the FKM below are exact inverses of each other.
//  * Effector: bTe = [R_tilt(X)·Rz(k·θ), c] (k = rotation_ratio, default 1).
// Conventions: doc/conventions.md (aTb maps b→a, SI units); pose X = (x, y, z, θ) of the central bar.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/support/constants.hpp"

namespace mire::datasets {

constexpr double kH4Pi = support::kPi;
constexpr double kH4Degree = kH4Pi / 180.0;

// X = (x, y, z, θ): position of the effector pivot in B (m) and rotation about z_B (rad).
using H4Pose = Eigen::Vector4d;
// Encoder readings q̄ of the four arms (rad), legs 1..4.
using H4Joints = Eigen::Vector4d;

struct H4TrueLeg {
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();  // P_i in B (m)
  double psi = 0.0;                                 // first Euler angle of the arm axis (eq. 17), rad
  double beta = 0.0;                                // second Euler angle of the arm axis (eq. 17), rad
  double arm_length = 0.0;                          // L_i (m)
  double forearm_length = 0.0;                      // l_i (m), centre line of the parallelogram
  double joint_offset = 0.0;                        // q0_i (rad): φ_i = q̄_i + q0_i
  double bar_mismatch = 0.0;                        // δ_i (m): length difference of the two forearm bars
};

struct H4TrueGeometry {
  std::array<H4TrueLeg, 4> legs;
  double h = 0.075;             // half length of a half-nacelle (m)
  double d = 0.10;              // half length of the central bar (m)
  double bar_spacing = 0.10;    // s: distance between the two bars of a forearm (m)
  double rotation_ratio = 1.0;  // k: effector rotation = k·θ
  // The nacelle was levelled at assembly at this pose (the workspace centre, H configuration):
  // the tilt is zero there, so z_B (normal to the nacelle, doc/mechanisms.md) stays well defined.
  Eigen::Vector4d level_pose{0.0, 0.0, -0.62, 0.0};
};

// The model-12 parameter values (doc/mechanisms.md, "H4 model 12") a true geometry can be built from: the
// mechanism module's nominal struct (R, L, l, h, d, α_i, q0_i, amplification k).
using H4Model12Values = mechanism::H4Nominal;

// Leg signs (ε_i, σ_i) of doc/mechanisms.md are the mechanism module's mechanism::kH4Epsilon, kH4Sigma.

// Exactly the geometry model 12 describes for `values` (no unmodelled defect).
H4TrueGeometry geometryFromModel12(const H4Model12Values& values);

// Sizes (1σ) of the random errors drawn by makeTrueGeometry.
struct H4ErrorSizes {
  // Manufacturing errors model 12 CAN represent (default ≈1 mm / 0.5°, doc/mechanisms.md).
  double length_m = 1e-3;              // R, L, l, h
  double angle_rad = 0.5 * kH4Degree;  // α_i
  // q0_i: encoder zero offsets. The paper's robot was off by far more than 0.5° (V2 −98 %,
  // square sides 4–7 mm, V3 1.8 mm before identification); a few degrees here reproduce
  // those magnitudes (measured: 3° → V2 1.5e-2 rad, V3 0.30 mm before identification).
  double joint_offset_rad = 0.5 * kH4Degree;
  // Defects model 12 can NOT represent (set all to 0 for a model-12-exact robot).
  double leg_length_m = 0.5e-3;            // per-leg differences of L_i and l_i
  double pivot_height_m = 1e-3;            // non-coplanar pivots (z of P_i)
  double axis_tilt_rad = 0.3 * kH4Degree;  // ψ_i, β_i deviations (tilted arm axes)
  double bar_mismatch_m = 1.0e-3;          // δ_i, parallelogram bar mismatch (≈0.1° nacelle tilt)

  static H4ErrorSizes withoutUnmodelledDefects() {
    H4ErrorSizes sizes;
    sizes.leg_length_m = sizes.pivot_height_m = sizes.axis_tilt_rad = sizes.bar_mismatch_m = 0.0;
    return sizes;
  }
};

// A random true geometry around `nominal`; deterministic for a seed. The errors model 12 can
// represent are drawn first, so two calls with the same seed that differ only in the
// unmodelled sizes share the same model-12 part.
H4TrueGeometry makeTrueGeometry(const H4Model12Values& nominal, const H4ErrorSizes& sizes, std::uint64_t seed);
// The model-12 part of makeTrueGeometry(nominal, sizes, seed): the best model-12 description
// of that robot (exact when `sizes` has no unmodelled defects).
H4Model12Values drawModel12Values(const H4Model12Values& nominal, const H4ErrorSizes& sizes, std::uint64_t seed);

// The true geometry as the campaigns' truth/robot.yaml writes it: h, d, bar_spacing,
// rotation_ratio and one line per leg (pivot, psi, beta, L, l, q0, bar_mismatch; SI).
std::string trueGeometryYaml(const H4TrueGeometry& geometry);

// Default true mounting of the camera (doc/mechanisms.md, "The simulated true H4"): below the workspace,
// looking up (z_C ≈ z_B), ≈0.8 m from the target, turned by ψ_BC = 25° with a 1–2° tilt like a real bracket.
Eigen::Isometry3d defaultBaseTCamera();
// Default true mounting of the target: plane parallel to the nacelle (z_M = z_E), 40 mm below
// the effector, origin (first feature) offset so a ≈180×140 mm board is centred on it, ψ_ME = 10°.
Eigen::Isometry3d defaultMarkerTEffector();

class H4TrueKinematics {
 public:
  explicit H4TrueKinematics(H4TrueGeometry geometry, const Eigen::Isometry3d& base_T_camera = defaultBaseTCamera(),
                            const Eigen::Isometry3d& marker_T_effector = defaultMarkerTEffector());

  const H4TrueGeometry& geometry() const { return geometry_; }
  const Eigen::Isometry3d& baseTCamera() const { return base_T_camera_; }
  const Eigen::Isometry3d& markerTEffector() const { return marker_T_effector_; }

  // Nacelle tilt ω(X) (rotation vector, rad; z component 0) at the actual pose X.
  Eigen::Vector3d tilt(const H4Pose& pose) const;
  // Attachment points A_i on the (tilted) nacelle at the actual pose X (m, in B).
  std::array<Eigen::Vector3d, 4> attachmentPoints(const H4Pose& pose) const;
  // Actual 6-DoF effector pose bTe at the actual pose X.
  Eigen::Isometry3d baseTEffector(const H4Pose& pose) const;
  // Target pose seen by the camera: cTm = bTc⁻¹ · bTe · mTe⁻¹.
  Eigen::Isometry3d cameraTMarker(const H4Pose& pose) const;

  // True IKM: exact encoder readings q̄ = φ − q0 for the actual pose X (elbow-out branch,
  // wrapped to (−π, π]); nullopt when a leg cannot reach.
  std::optional<H4Joints> joints(const H4Pose& pose) const;
  // Same plus Gaussian encoder noise of σ `noise_rad` per joint.
  std::optional<H4Joints> joints(const H4Pose& pose, double noise_rad, std::mt19937_64& rng) const;

  // True numerical FKM (Ceres, autodiff): the actual pose X reached for encoder readings q̄,
  // starting from `guess`; nullopt when it does not converge to |residual| < 1e-10 m.
  std::optional<H4Pose> pose(const H4Joints& q, const H4Pose& guess) const;
  // Convenience: the actual 6-DoF effector pose for encoder readings q̄.
  std::optional<Eigen::Isometry3d> baseTEffector(const H4Joints& q, const H4Pose& guess) const;

  // Elbow positions B_i for joint readings q̄ (m, in B).
  std::array<Eigen::Vector3d, 4> elbows(const H4Joints& q) const;

 private:
  H4TrueGeometry geometry_;
  Eigen::Isometry3d base_T_camera_;
  Eigen::Isometry3d marker_T_effector_;
};

// ---------------------------------------------------------------------------------------------
// Protocol of paper §5–6 (doc/mechanisms.md, "Evaluation criteria").

struct H4ProtocolGrid {
  Eigen::Vector3d centre{0.0, 0.0, -0.62};
  Eigen::Vector3d extent{0.20, 0.20, 0.15};  // full size of the 3×3×3 grid (m)
  std::array<double, 3> thetas{-20.0 * kH4Degree, 0.0, 20.0 * kH4Degree};
};

// The 81 poses: 27 positions (x fastest, then y, then z) × 3 orientations (θ innermost).
std::vector<H4Pose> protocolPoses(const H4ProtocolGrid& grid = {});

// The two straight-line motions of criterion V3 (paper §6.1): configuration 1 along x through
// the centre, configuration 2 along a space diagonal (x, y and z change), θ = 0.
std::array<std::vector<H4Pose>, 2> straightLineMotions(const H4ProtocolGrid& grid = {}, int points_per_line = 20);

// Encoder readings the true robot records along a motion (the effector being guided on the
// line); throws std::runtime_error if a pose is unreachable.
std::vector<H4Joints> recordJoints(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses, double noise_rad,
                                   std::mt19937_64& rng);

// The square test of paper §6.4 (Table 4): corners of a `side` square at constant z commanded
// through a control model's IKM (pose → encoder readings q̄); the TRUE robot's FKM gives the
// positions actually reached; side lengths are measured in the nacelle plane (x_B, y_B) like
// the stylus trace on the effector plate.
using CommandIkm = std::function<std::optional<H4Joints>(const H4Pose&)>;
struct SquareTestResult {
  std::array<H4Pose, 4> commanded;
  std::array<H4Pose, 4> reached;
  std::array<double, 4> side_error_m{};  // reached side length − commanded side (m)
  double max_abs_error_m = 0.0;
};
SquareTestResult squareTest(const H4TrueKinematics& robot, const CommandIkm& command_ikm,
                            const Eigen::Vector3d& centre = Eigen::Vector3d(0.0, 0.0, -0.62), double side = 0.100);

// A simulated measurement campaign: for each pose, the measured target pose cTm (true value
// plus Gaussian noise of σ_t per translation component and σ_r per rotation-vector
// component, paper §5: 0.2 mm and 0.03°) and the encoder readings.
struct H4SimulatedMeasurement {
  int pose_id = 0;
  H4Pose true_pose;
  Eigen::Isometry3d camera_T_marker;  // measured (noisy)
  H4Joints joints;                    // recorded (noisy)
};
struct H4MeasurementNoise {
  double translation_m = 0.2e-3;
  double rotation_rad = 0.03 * kH4Degree;
  double encoder_rad = 0.0;
};
std::vector<H4SimulatedMeasurement> simulateMeasurements(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses,
                                                         const H4MeasurementNoise& noise, std::uint64_t seed);

// Applies the measurement noise model above to a pose (rotation noise as a right-multiplied
// rotation vector).
Eigen::Isometry3d perturbPose(const Eigen::Isometry3d& pose, const H4MeasurementNoise& noise, std::mt19937_64& rng);

// The measurements as identification input: ids "1".."N", cTm, joints and the diagonal
// covariance of the noise model (σ_t², σ_r²).
std::vector<mechanism::PoseObservation> toObservations(const std::vector<H4SimulatedMeasurement>& measurements,
                                                       const H4MeasurementNoise& noise);

// Writes a campaign as `mire identify` reads it (doc/file-formats.md): dir/poses.csv (σ columns from
// `noise`, images_used = images_total = 10, rms_px = 0), dir/joints.csv and, when `lines` is
// not empty, dir/lines.csv (line_id 1, 2, ...). Atomic per file.
void writeSimulatedCampaign(const std::filesystem::path& dir, const std::vector<H4SimulatedMeasurement>& measurements,
                            const H4MeasurementNoise& noise, const std::vector<std::vector<H4Joints>>& lines = {});

// Smallest distance (pixels) between the projections of `marker_points` (in M) and the border
// of a width×height pinhole image (fx = fy = focal_px, principal point at the centre) over all
// `poses`; negative when a point leaves the image or goes behind the camera.
double smallestImageMargin(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses,
                           const std::vector<Eigen::Vector3d>& marker_points, int width = 1024, int height = 768,
                           double focal_px = 817.0);

}  // namespace mire::datasets
