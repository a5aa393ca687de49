#pragma once
// Combining the detections of one pose over several images (paper §5: "10 images per pose,
// combined to reduce high-frequency image noise", paper §5; doc/measurement.md).
//
// Each feature's position is averaged over the images that kept it, and its scatter gives the
// covariance of that mean, which weights the pose fit and yields the pose's precision.
#include "mire/metrology/detection.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mire::metrology {

struct AveragingOptions {
  // Outlier test probability: an image (or a single observation) is rejected when its
  // chi-square statistic exceeds the (1 - probability) quantile of chi-square with 2 degrees
  // of freedom (13.8155 at 99.9 %).
  double rejection_confidence = 0.999;
  // Each feature's covariance is the pose's pooled covariance (all features, all images)
  // scaled by the feature's own relative noise level, shrunk toward 1:
  //   s_i = tr(Σ_pooled⁻¹ S_i)/2,  c_i = (ν0 + d_i s_i)/(ν0 + d_i),  d_i = 2(n_i − 1),
  //   Σ_i = c_i Σ_pooled  (one observation),  covariance of the mean = Σ_i / n_i.
  // With 10 images a single feature's own scatter is ±17 % uncertain; the pool has 18 ×
  // features degrees of freedom. ν0 ≤ 0 (default): chosen per pose by empirical Bayes from
  // how much more the s_i spread than sampling noise explains (equal noise → pooled; strongly
  // unequal → closer to each feature's own scatter). See the .cpp.
  double pooled_prior_dof = 0.0;
  // A feature must be seen in at least this fraction of the images kept.
  double min_feature_fraction = 0.5;
  // The whole-image displacement test below. measurePose turns it off: a displaced image is a
  // moved pose, which the static-pose integrity test (pose_integrity.hpp) names instead of
  // silently dropping it as an "outlier".
  bool reject_images = true;
};

struct AveragedFeatures {
  std::vector<int> ids;                     // indices into Target::points()
  std::vector<Eigen::Vector2d> pixels;      // mean position over the images kept
  std::vector<Eigen::Matrix2d> covariance;  // covariance of that mean (px²)
  std::vector<int> observations;            // images that contributed to each feature
  int images_used = 0;
  int images_total = 0;
  std::vector<int> rejected_images;                             // indices into the input, for reports
  int rejected_observations = 0;                                // single-feature outliers dropped
  Eigen::Matrix2d pooled_covariance = Eigen::Matrix2d::Zero();  // one observation (px²)
  int pooled_dof = 0;                                           // 0 when a single image: no scatter known
  double prior_dof = 0.0;                                       // ν0 used for the shrinkage
  // Several images but no scatter at all (identical features): treated as a single image
  // (pooled_dof = 0, the pose fit takes its noise from its residuals), never divided by zero.
  bool zero_scatter = false;
  std::size_t size() const { return ids.size(); }
  bool hasScatter() const { return pooled_dof > 0; }
};

// Averages per-image detections of the same target in the same pose. Images whose detection
// is not `found` count in images_total but not in images_used.
//
// Outliers (stated test): with m_i the per-feature median over images, each image's mean
// displacement d_j = mean_i (x_ij − m_i) is compared with the robust spread of those
// displacements over images (median absolute deviation × 1.4826, per axis, floored by the
// spread a pure per-feature noise would give): image j is rejected when
// |d_j − median(d)|² / σ_d² (summed over x, y) exceeds χ²₂(rejection_confidence). Then within
// the kept images, a single observation is dropped when its Mahalanobis distance to the
// feature's median under the robust pooled covariance exceeds the same quantile.
// Needs at least 3 images to test; fewer are all kept.
AveragedFeatures averageDetections(const std::vector<Detection>& detections, const AveragingOptions& options = {});

// The χ² quantile with 2 degrees of freedom: −2 ln(1 − p).
double chiSquare2Quantile(double probability);

}  // namespace mire::metrology
