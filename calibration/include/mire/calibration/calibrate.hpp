#pragma once
// Camera calibration from views of a planar target (paper §5; doc/calibration.md): OpenCV-calib3d
// shaped (per-view object points + image points + image size), solved as a Ceres bundle
// adjustment over the intrinsics + distortion (one parameter block, projected through
// calibration::projectPoint), every view's pose and — optionally — the target's own 3D points
// (Lavest & Dhome, the method the paper cites; OpenCV's cv::calibrateCameraRO is the peer).
//
// Pipeline (calibrateCamera):
//  1. initialisation by OpenCV: cv::initCameraMatrix2D (zero distortion) + cv::solvePnP (IPPE)
//     per view;
//  2. plain least squares from there;
//  3. robust pass: Huber loss (or Cauchy) whose scale is `robust_scale_sigmas` × σ, σ estimated
//     robustly from pass 2 (median residual norm / 1.1774, the Rayleigh median);
//  4. outlier rejection: points whose residual norm exceeds `outlier_threshold_sigmas` × σ;
//     views left with too few points are rejected whole;
//  5. final plain least-squares on the inliers, so the covariance below is the ordinary
//     Gauss–Newton one: Σ = σ² (JᵀJ)⁻¹ with σ² = SSR / (2N − n_free) (N inlier points,
//     n_free the free parameters: intrinsics + 6 per view + free target coordinates).
#include "mire/calibration/camera_model.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace mire::calibration {

// The models calibrate estimates (doc/calibration.md). OpenCV's distortion models:
// pinhole = no distortion, opencv4 = k1 k2 p1 p2 (Bouguet's toolbox, k3 = 0), opencv5 = + k3
// (Brown–Conrady), opencv8 = + k4 k5 k6 (rational, CALIB_RATIONAL_MODEL), opencv12 = + s1 s2 s3 s4
// (thin prism, CALIB_THIN_PRISM_MODEL: a decentred or tilted lens element); fisheye = OpenCV's
// cv::fisheye equidistant model, k1..k4.
enum class DistortionModel { OpenCV4, OpenCV5, OpenCV8, OpenCV12, Pinhole, Fisheye };
int distortionCoefficientCount(DistortionModel model);
LensModel lensOf(DistortionModel model);
// "opencv4", "opencv5", "opencv8", "opencv12", "pinhole", "fisheye"
std::string distortionModelName(DistortionModel model);
// Throws std::invalid_argument naming the accepted values.
DistortionModel parseDistortionModel(const std::string& name);

enum class RobustLoss { None, Huber, Cauchy };

struct CalibrationOptions {
  DistortionModel model = DistortionModel::OpenCV5;
  // Parameters held at their initial value, by Camera::parameterNames() name ("fx", "cx",
  // "k3", "p1", ...). Without `initial_params`, fixed distortion terms stay 0 and a fixed
  // principal point stays at the image centre ((w−1)/2, (h−1)/2).
  std::vector<std::string> fixed_parameters;
  // Optional starting intrinsics (fx fy cx cy + the model's coefficients), instead of
  // cv::initCameraMatrix2D.
  std::optional<std::vector<double>> initial_params;

  RobustLoss robust_loss = RobustLoss::Huber;
  double robust_scale_sigmas = 3.0;       // loss scale, in σ of the first pass
  double outlier_threshold_sigmas = 5.0;  // points beyond are rejected (≈4e-6 false rate)
  double min_sigma_px = 0.01;             // floor for σ when data are (nearly) exact
  int min_points_per_view = 6;
  double min_inlier_fraction = 0.5;  // a view keeping fewer of its points is rejected

  // Lavest & Dhome: the target's points become unknowns (gauge: see CalibrationResult).
  bool refine_target = false;

  // Inflate the covariance by the view-cluster (sandwich) estimate where it is larger: the
  // σ then include systematic errors that are correlated within a view (doc/calibration.md).
  bool view_cluster_covariance = true;

  // Working distance for the projection uncertainty; 0 = the median distance of the target
  // in the calibration views.
  double uncertainty_distance_m = 0.0;
  // Ceres' threads. Above 1 the result is not bit-reproducible: each thread sums the cost and
  // gradient of the residual blocks it happened to take, so the order of the additions (and the
  // last digits of the result) changes from run to run. 1 (the default, `mire calibrate`'s
  // choice) gives identical results on every run.
  int num_threads = 1;
};

// One image's observations: target point indices and their pixels (OpenCV's convention).
struct CalibrationView {
  std::string name;  // image file name, for reports
  std::vector<int> ids;
  std::vector<Eigen::Vector2d> pixels;
};

struct CalibrationViewResult {
  std::string name;
  bool used = false;
  std::string rejection_reason;                           // empty when used
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();     // cTm, angle-axis (rad)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // cTm, target units (metres)
  double rms_px = 0.0;                                    // over this view's inliers
  double tilt_deg = 0.0;                                  // angle between the target normal and the optical axis
  std::vector<int> ids;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Eigen::Vector2d> residuals;  // projected − observed, px
  std::vector<bool> inlier;
};

// Projection uncertainty at the image centre, the middle of the right edge and the corner.
struct ProjectionUncertaintySummary {
  double centre_px = 0.0;
  double edge_px = 0.0;
  double corner_px = 0.0;
};

// `refine_target` against the same views with the nominal target held rigid
// (doc/calibration.md, "Weakly determined target refinement"): the refinement's extra unknowns
// can trade against the intrinsics when the views do not pin them down.
struct TargetRefinementCheck {
  int added_unknowns = 0;            // free target coordinates
  std::vector<double> rigid_params;  // the rigid-target calibration's intrinsics
  std::vector<double> rigid_sigmas;  // and their σ
  // (refined − rigid) / √(σ_rigid² + σ_refined²), per parameter (0 where both σ are 0)
  std::vector<double> shift_sigmas;
  // Growth of each parameter's pixel-noise σ at equal pixel noise: √diag of the refined
  // (JᵀJ)⁻¹ over the rigid one (1 = the target points cost the parameter nothing).
  std::vector<double> information_loss;
  ProjectionUncertaintySummary rigid_uncertainty;
  ProjectionUncertaintySummary refined_uncertainty;
  double largest_intrinsic_shift_sigma = 0.0;  // |shift_sigmas| over fx fy cx cy
  double largest_uncertainty_ratio = 0.0;      // refined / rigid over centre, edge, corner
  bool weakly_determined = false;              // the rule of doc/calibration.md
};

struct CalibrationResult {
  Camera camera;  // params, rms_px (over inliers), covariance (fixed parameters: 0 rows/cols)
  DistortionModel model = DistortionModel::OpenCV5;
  std::vector<std::string> fixed_parameters;
  std::vector<CalibrationViewResult> views;
  int used_views = 0;
  int used_points = 0;
  int rejected_points = 0;  // in used views
  int rejected_views = 0;
  int free_parameter_count = 0;
  double sigma_px = 0.0;         // sqrt(SSR / (2N − n_free)): the covariance's scale
  double robust_scale_px = 0.0;  // Huber/Cauchy scale used by the robust pass (0 if none)

  // Target points (nominal, or refined with refine_target), in target units.
  std::vector<Eigen::Vector3d> target_points;
  bool target_refined = false;
  // Gauge of the target refinement: point gauge[0] fixed (3 coordinates: translation),
  // gauge[1] — the point farthest from it — fixed (3: the direction of the line (2 rotations)
  // and its length (the scale, which images alone cannot give)), and the z of gauge[2] — the
  // point farthest from that line — fixed (1: the rotation about the line). 7 constraints =
  // the 7 degrees of freedom of the similarity (rotation, translation, scale) that would
  // otherwise move target points and poses together without changing any projection.
  std::array<int, 3> gauge_points{{-1, -1, -1}};
  double target_out_of_plane_rms_m = 0.0;  // refined points vs their best-fit plane
  double target_out_of_plane_max_m = 0.0;
  double target_displacement_rms_m = 0.0;  // refined − nominal (3D)

  // What the σ include (doc/calibration.md): camera.covariance and state_covariance are the
  // classical σ² (JᵀJ)⁻¹ (pixel noise, estimated from the residuals) with each parameter's σ
  // multiplied by sigma_inflation (≥ 1; ambient order, 1 for fixed parameters): the ratio of
  // the view-cluster sandwich σ to the classical one, when residuals are correlated within
  // views (systematic error). covariance_pixel_noise: the intrinsics' classical covariance.
  std::vector<double> sigma_inflation;
  Eigen::MatrixXd covariance_pixel_noise;

  // Covariance of the state [intrinsics (ambient, as camera.params), then 6 per used view
  // (rotation, translation) in `views` order], marginalised over the target points; used by
  // the projection uncertainty.
  Eigen::MatrixXd state_covariance;
  std::vector<int> state_view_index;  // views[] index of each pose block in state_covariance
  double uncertainty_distance_m = 0.0;

  // Data that do not constrain the model well (coverage, tilt, rank, a weak target refinement).
  std::vector<std::string> warnings;
  // With refine_target: the comparison with the rigid-target calibration behind its warnings.
  std::optional<TargetRefinementCheck> target_refinement;
};

// Calibrates from a target's points (target frame; z = 0 for the initialisation) and the
// views that observed them. Throws std::invalid_argument on malformed input (ids out of
// range, width/height ≤ 0, non-planar target without initial_params) and std::runtime_error
// when fewer than 3 views remain usable.
CalibrationResult calibrateCamera(const std::vector<Eigen::Vector3d>& target_points,
                                  const std::vector<CalibrationView>& views, int width, int height,
                                  const CalibrationOptions& options = {});

// cv::calibrateCamera-shaped overload: per-view object points and image points. Identical
// object points across views are the same target point (needed by refine_target).
CalibrationResult calibrateCamera(const std::vector<std::vector<Eigen::Vector3d>>& object_points,
                                  const std::vector<std::vector<Eigen::Vector2d>>& image_points, int width, int height,
                                  const CalibrationOptions& options = {});

// Projection uncertainty à la mrcal: the pixel `pixel` is unprojected through the estimated
// intrinsics to the point at `distance_m` along its ray (z = distance), that point is carried
// into every used view's target frame, back by the perturbed poses, averaged, and projected
// by the perturbed intrinsics; the 2×2 covariance of that pixel is propagated (first order)
// from `state_covariance`. Returns the 1-σ of the worst direction (sqrt of the larger
// eigenvalue), in px. NaN where the pixel cannot be unprojected.
double projectionUncertaintyPx(const CalibrationResult& result, const Eigen::Vector2d& pixel, double distance_m);
// The full 2×2 covariance (px²) behind projectionUncertaintyPx (NaN where undefined).
Eigen::Matrix2d projectionCovariancePx(const CalibrationResult& result, const Eigen::Vector2d& pixel, double distance_m);
// The function whose spread that is: the pixel where the point seen at `pixel` (through
// `truth_params`, at `distance_m`, carried through the true poses `truth_poses`) lands with
// the estimated intrinsics and poses. Exposed for Monte-Carlo validation. Poses: 6-vectors
// (angle-axis, t) of cTm, one per entry of `view_indices` (indices into result.views);
// `lens` is the model of both parameter vectors.
Eigen::Vector2d reprojectThroughEstimate(const std::vector<double>& estimate_params,
                                         const std::vector<Eigen::Matrix<double, 6, 1>>& estimate_poses,
                                         const std::vector<double>& truth_params,
                                         const std::vector<Eigen::Matrix<double, 6, 1>>& truth_poses,
                                         const Eigen::Vector2d& pixel, double distance_m,
                                         LensModel lens = LensModel::OpenCV);

ProjectionUncertaintySummary summarizeProjectionUncertainty(const CalibrationResult& result);

// The comparison of a target-refined calibration with the rigid-target one of the same views,
// and the warnings it implies (appended to `refined->warnings`; doc/calibration.md). Called by
// calibrateCamera when refine_target is set.
TargetRefinementCheck checkTargetRefinement(const CalibrationResult& rigid, CalibrationResult* refined);

}  // namespace mire::calibration
