#pragma once
// Does the lens model fit the images? The check run after every calibration
// (doc/calibration.md, "Model check"): three tests on the solution, each at a stated level,
// and a verdict naming what to try.
//
//  1. Residual structure over the image: the inlier residuals binned by radius from the
//     principal point (rings of equal point count) and direction (sectors); each bin's mean
//     residual against its view-cluster covariance (Hotelling's T² with views as clusters, so a
//     detector bias correlated within a view is not structure), Bonferroni over the bins.
//  2. Nested models: the calibration refitted with the terms a richer model adds (opencv5 →
//     + k4 k5 k6, + s1..s4 thin prism; opencv8 → + s1..s4; opencv4 → + k3, + s1..s4;
//     pinhole → + k1 k2 p1 p2), started from the solution, on its inliers; the likelihood
//     ratio (SSR − SSR_richer) / σ²_richer, divided by the design effect of within-view
//     correlation (the largest squared view-cluster inflation of the added terms, ≥ 1), against
//     χ²(added terms), Bonferroni over the candidates. A likelihood ratio, not a Wald test: the
//     rational terms are nearly degenerate with k1 k2 k3, and only the fit's change is
//     invariant to that.
//  3. Held-out views (k-fold over views, when asked): each fold calibrated without its views,
//     which are then fitted by their pose alone; their residual sum of squares against its
//     prediction σ²(2n − 6) + tr(Q J_θ Σ_θ J_θᵀ Q) (pixel noise, plus the training calibration's
//     own uncertainty seen through the held-out geometry, Q removing what the pose absorbs);
//     a one-sided t-test over views of measured/predicted > 1. Also the delete-a-fold jackknife σ
//     of every parameter against the printed σ.
// Verdict: adequate when no test rejects at its level (1 % each, so ≤ 3 % false alarms).
#include "mire/calibration/calibrate.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace mire::calibration {

struct ModelCheckOptions {
  double level = 0.01;    // each test's false-alarm probability (Bonferroni inside a test)
  int rings = 4;          // radial bins, equal point counts
  int sectors = 8;        // direction bins, 45° each
  int min_bin_views = 5;  // a bin needs points from this many views to be tested
  int holdout_folds = 0;  // k-fold over views; 0 = no held-out check
};

struct ResidualBin {
  double radius_min_px = 0.0, radius_max_px = 0.0;  // from the principal point
  double angle_min_rad = 0.0, angle_max_rad = 0.0;  // atan2(v − cy, u − cx)
  int points = 0;
  int views = 0;
  Eigen::Vector2d mean_px = Eigen::Vector2d::Zero();  // mean residual (projected − observed)
  double t2 = 0.0;                                    // Hotelling's T², views as clusters
  double p_value = 1.0;                               // F(2, views − 2) upper tail; 1 when untested
  bool tested = false;
  bool significant = false;  // p < level / tested bins
};

struct ResidualStructure {
  int rings = 0, sectors = 0;
  std::vector<double> ring_edges_px;  // rings + 1 radii
  std::vector<ResidualBin> bins;      // ring-major
  int tested_bins = 0;
  int significant_bins = 0;
  double min_p_value = 1.0;
  double corrected_p_value = 1.0;  // Bonferroni: min p × tested bins (≤ 1)
  bool significant = false;
  double structured_rms_px = 0.0;  // RMS over points of their bin's mean residual
};

struct NestedModelTest {
  std::string model;                          // the refit's model ("opencv12")
  std::vector<std::string> fixed;             // held at 0 in the refit (k4 k5 k6 for thin prism alone)
  std::vector<std::string> terms;             // the added terms tested
  std::vector<double> values, sigmas;         // their refitted values and printed σ
  double design_effect = 1.0;                 // max squared view-cluster inflation of the terms (≥ 1)
  double statistic = 0.0;                     // (SSR − SSR_richer) / (σ²_richer · design effect)
  int dof = 0;                                // terms.size()
  double p_value = 1.0;                       // χ²(dof) upper tail
  bool significant = false;                   // p < level / candidates
  double rms_px = 0.0;                        // the refit's reprojection RMS
  std::vector<double> intrinsics;             // the refit's fx fy cx cy
  std::vector<double> intrinsic_shift_sigma;  // (refit − solution) / refit's σ, fx fy cx cy
  std::string suggestion;                     // "--model opencv12"
};

struct HoldoutCheck {
  int folds = 0;
  int views = 0;                   // held-out views evaluated
  double measured_rms_px = 0.0;    // √(Σ SSR / Σ n) of the held-out views after their pose fit
  double predicted_rms_px = 0.0;   // √(Σ E[SSR] / Σ n)
  double noise_only_rms_px = 0.0;  // the part of the prediction from pixel noise alone
  double ratio = 0.0;              // measured / predicted RMS
  // The calibration's own share: held-out excess over pixel noise, measured / predicted (√);
  // the factor by which the calibration's σ would have to be scaled to explain it (NaN when
  // the excess is not positive).
  double calibration_sigma_scale = 0.0;
  double t_statistic = 0.0;  // mean over views of SSR/E[SSR] − 1, in its standard error
  double p_value = 1.0;      // one-sided (measured > predicted)
  bool significant = false;
  std::vector<std::string> names;
  std::vector<double> jackknife_sigma;  // delete-a-fold jackknife σ per parameter
  std::vector<double> jackknife_ratio;  // jackknife σ / printed σ (NaN for fixed parameters)
};

struct ModelCheck {
  ResidualStructure structure;
  std::vector<NestedModelTest> nested;
  std::optional<HoldoutCheck> holdout;
  double level = 0.01;
  bool adequate = true;
  std::vector<std::string> reasons;      // what failed, with numbers
  std::vector<std::string> suggestions;  // what to try
  // "model check: adequate" or "model check: insufficient (REASONS; try SUGGESTIONS)".
  std::string verdictLine() const;
};

// Runs the check on a calibration: its used views' inliers and its target points (as solved)
// are what the refits use; `options` are the calibration's options (model, fixed parameters;
// the refits keep them). Throws std::invalid_argument when the held-out folds leave fewer
// than 3 views to calibrate.
ModelCheck checkCalibrationModel(const CalibrationResult& result, const CalibrationOptions& options,
                                 const ModelCheckOptions& check_options = {});

// Test 1 alone (no refit).
ResidualStructure residualStructure(const CalibrationResult& result, const ModelCheckOptions& options = {});

}  // namespace mire::calibration
