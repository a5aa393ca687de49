#include "mire/metrology/feature_averaging.hpp"
#include "mire/support/statistics.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace mire::metrology {
namespace {

// Spreads below this (px) are treated as noiseless data, not as infinitely precise.
constexpr double kSpreadFloorPx = 1e-6;

using support::median;

// One feature's observations: (image index in `found`, pixel).
struct Track {
  std::vector<int> images;
  std::vector<Eigen::Vector2d> pixels;
};

Eigen::Vector2d trackMedian(const Track& track, const std::vector<bool>& kept) {
  std::vector<double> xs, ys;
  for (std::size_t k = 0; k < track.images.size(); ++k) {
    if (!kept[static_cast<std::size_t>(track.images[k])]) continue;
    xs.push_back(track.pixels[k].x());
    ys.push_back(track.pixels[k].y());
  }
  return {median(xs), median(ys)};
}

// Each feature's noise scale relative to the pooled covariance: s_i = tr(Σ_pooled⁻¹ S_i)/2,
// which has 2(n_i − 1) degrees of freedom when the feature's covariance has the pooled shape
// (only its size differs: corners of unequal sharpness).
std::vector<double> relativeScales(const std::vector<Eigen::Matrix2d>& sample_covariance, const Eigen::Matrix2d& pooled) {
  const Eigen::Matrix2d inverse = pooled.inverse();
  std::vector<double> scales;
  scales.reserve(sample_covariance.size());
  for (const auto& s : sample_covariance) scales.push_back(0.5 * (inverse * s).trace());
  return scales;
}

// Empirical Bayes strength ν0 of the pooled prior (method of moments): the relative scales s_i
// scatter by sampling noise alone as Var(s_i) = 2 E[c²]/d, d = 2(n − 1); any excess is a real
// spread τ² of the features' noise. A scaled inverse-χ² prior with ν0 degrees of freedom has
// a squared coefficient of variation 2/(ν0 − 4), so ν0 = 4 + 2 m²/τ². Homogeneous noise
// (τ² ≤ 0) gives the pooled estimate (ν0 = kMaxPriorDof).
double empiricalPriorDof(const std::vector<double>& scales, const std::vector<int>& observations) {
  constexpr double kMaxPriorDof = 1e4;
  constexpr double kMinPriorDof = 4.5;
  double sum = 0.0, sum_squares = 0.0, sum_dof = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < scales.size(); ++i) {
    if (observations[i] < 2) continue;
    sum += scales[i];
    sum_squares += scales[i] * scales[i];
    sum_dof += 2.0 * (observations[i] - 1);
    ++count;
  }
  if (count < 3) return kMaxPriorDof;
  const double mean = sum / count;
  const double variance = (sum_squares - count * mean * mean) / (count - 1);
  const double dof = sum_dof / count;
  const double spread = (variance - 2.0 * mean * mean / dof) / (1.0 + 2.0 / dof);
  if (!(spread > 0.0) || !(mean > 0.0)) return kMaxPriorDof;
  return std::clamp(4.0 + 2.0 * mean * mean / spread, kMinPriorDof, kMaxPriorDof);
}

// Images where the target was found, and each feature's track across them.
struct FeatureTracks {
  std::vector<int> found;  // indices into the detections
  std::map<int, Track> tracks;
};

FeatureTracks collectTracks(const std::vector<Detection>& detections) {
  FeatureTracks result;
  for (std::size_t j = 0; j < detections.size(); ++j) {
    const Detection& detection = detections[j];
    if (!detection.found) continue;
    const int slot = static_cast<int>(result.found.size());
    result.found.push_back(static_cast<int>(j));
    for (std::size_t i = 0; i < detection.ids.size(); ++i) {
      Track& track = result.tracks[detection.ids[i]];
      track.images.push_back(slot);
      track.pixels.push_back(detection.pixels[i]);
    }
  }
  return result;
}

// Residuals of every observation about its feature's median over the kept images, per image.
std::vector<std::vector<Eigen::Vector2d>> residualsPerImage(const std::map<int, Track>& tracks,
                                                            const std::vector<bool>& kept) {
  std::vector<std::vector<Eigen::Vector2d>> per_image(kept.size());
  for (const auto& [id, track] : tracks) {
    if (track.images.size() < 2) continue;
    const Eigen::Vector2d centre = trackMedian(track, kept);
    for (std::size_t k = 0; k < track.images.size(); ++k)
      per_image[static_cast<std::size_t>(track.images[k])].push_back(track.pixels[k] - centre);
  }
  return per_image;
}

// RMS of the values within 5 robust σ (MAD), floored at kSpreadFloorPx.
double clippedRms(const std::vector<double>& values) {
  const double limit = 5.0 * std::max(support::madSigma(values), kSpreadFloorPx);
  double sum = 0.0;
  std::size_t count = 0;
  for (const double v : values)
    if (std::abs(v) <= limit) {
      sum += v * v;
      ++count;
    }
  return std::max(count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0, kSpreadFloorPx);
}

// Per-axis σ of one observation: the RMS of the residuals within 5 robust σ (MAD). The RMS,
// not the MAD, because features of unequal sharpness make a scale mixture whose MAD
// underestimates its RMS; the clipping keeps gross outliers out.
Eigen::Vector2d pooledRobustSigma(const std::vector<std::vector<Eigen::Vector2d>>& per_image,
                                  const std::vector<bool>& kept) {
  std::vector<double> xs, ys;
  for (std::size_t j = 0; j < per_image.size(); ++j)
    if (kept[j])
      for (const auto& r : per_image[j]) {
        xs.push_back(r.x());
        ys.push_back(r.y());
      }
  return Eigen::Vector2d(clippedRms(xs), clippedRms(ys));
}

// Image-level test: a whole image displaced (vibration, a wrong refinement) has a mean
// residual far from the other images'; such images are no longer kept.
void rejectDisplacedImages(const std::map<int, Track>& tracks, double threshold, std::vector<bool>* kept) {
  const std::size_t image_count = kept->size();
  const std::vector<std::vector<Eigen::Vector2d>> per_image = residualsPerImage(tracks, *kept);
  const Eigen::Vector2d observation_sigma = pooledRobustSigma(per_image, *kept);
  std::vector<Eigen::Vector2d> displacement(image_count, Eigen::Vector2d::Zero());
  std::vector<double> dx, dy;
  std::size_t typical_features = 0;
  for (std::size_t j = 0; j < image_count; ++j) {
    if (per_image[j].empty()) continue;
    for (const auto& r : per_image[j]) displacement[j] += r;
    displacement[j] /= static_cast<double>(per_image[j].size());
    dx.push_back(displacement[j].x());
    dy.push_back(displacement[j].y());
    typical_features = std::max(typical_features, per_image[j].size());
  }
  const Eigen::Vector2d centre(median(dx), median(dy));
  // Floor: the spread of a mean of independent per-feature noise.
  const double floor_scale = 1.0 / std::sqrt(static_cast<double>(std::max<std::size_t>(typical_features, 1)));
  const Eigen::Vector2d spread(std::max(support::madSigma(dx), observation_sigma.x() * floor_scale),
                               std::max(support::madSigma(dy), observation_sigma.y() * floor_scale));
  for (std::size_t j = 0; j < image_count; ++j) {
    if (per_image[j].empty()) continue;
    const Eigen::Vector2d z = (displacement[j] - centre).cwiseQuotient(spread);
    if (z.squaredNorm() > threshold) (*kept)[j] = false;
  }
}

// Sums of the per-feature scatter, for the pooled covariance.
struct Scatter {
  std::vector<Eigen::Matrix2d> sample_covariance;  // per averaged feature
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  int dof = 0;
};

// Observation-level test (with 3 kept images or more), then the mean and scatter of each
// feature seen in enough kept images; the means go into `result`.
Scatter averageTracks(const std::map<int, Track>& tracks, const std::vector<bool>& kept, double threshold,
                      const AveragingOptions& options, AveragedFeatures* result) {
  const int kept_count = result->images_used;
  Eigen::Vector2d observation_sigma(kSpreadFloorPx, kSpreadFloorPx);
  if (kept_count >= 3) observation_sigma = pooledRobustSigma(residualsPerImage(tracks, kept), kept);
  const int min_observations = std::max(1, static_cast<int>(std::ceil(options.min_feature_fraction * kept_count - 1e-9)));
  Scatter scatter_total;
  for (const auto& [id, track] : tracks) {
    const Eigen::Vector2d centre = trackMedian(track, kept);
    std::vector<Eigen::Vector2d> values;
    for (std::size_t k = 0; k < track.images.size(); ++k) {
      if (!kept[static_cast<std::size_t>(track.images[k])]) continue;
      if (kept_count >= 3) {
        const Eigen::Vector2d z = (track.pixels[k] - centre).cwiseQuotient(observation_sigma);
        if (z.squaredNorm() > threshold) {
          ++result->rejected_observations;
          continue;
        }
      }
      values.push_back(track.pixels[k]);
    }
    if (static_cast<int>(values.size()) < min_observations) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& v : values) mean += v;
    mean /= static_cast<double>(values.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& v : values) scatter += (v - mean) * (v - mean).transpose();
    const int n = static_cast<int>(values.size());
    scatter_total.sum += scatter;
    scatter_total.dof += n - 1;
    result->ids.push_back(id);
    result->pixels.push_back(mean);
    result->observations.push_back(n);
    scatter_total.sample_covariance.push_back(n > 1 ? Eigen::Matrix2d(scatter / (n - 1)) : Eigen::Matrix2d::Zero());
  }
  return scatter_total;
}

// Each averaged feature's covariance: its own scatter shrunk towards the pooled covariance
// (empirical Bayes, prior strength ν0), divided by its observation count.
void featureCovariances(const Scatter& scatter, const AveragingOptions& options, AveragedFeatures* result) {
  result->pooled_dof = scatter.dof;
  if (scatter.dof > 0) result->pooled_covariance = scatter.sum / scatter.dof;
  result->covariance.resize(result->ids.size(), Eigen::Matrix2d::Zero());
  if (scatter.dof == 0) return;  // a single image: no scatter; the pose fit falls back on its residuals
  // No scatter at all (copies of one frame): no noise is known from the images; the pose fit
  // estimates it from its residuals as for one image (pose_estimation.hpp).
  if (result->pooled_covariance.isZero(0.0)) {
    result->zero_scatter = true;
    result->pooled_dof = 0;
    return;
  }
  // A singular pooled covariance (scatter along one axis only) is noiseless data on the other:
  // no shrinkage needed.
  if (!(result->pooled_covariance.determinant() > 0.0)) {
    for (std::size_t i = 0; i < result->ids.size(); ++i)
      result->covariance[i] = result->pooled_covariance / result->observations[i];
    return;
  }
  const std::vector<double> scales = relativeScales(scatter.sample_covariance, result->pooled_covariance);
  const double prior =
      options.pooled_prior_dof > 0.0 ? options.pooled_prior_dof : empiricalPriorDof(scales, result->observations);
  result->prior_dof = prior;
  for (std::size_t i = 0; i < result->ids.size(); ++i) {
    const double n = result->observations[i];
    const double dof = 2.0 * (n - 1.0);
    const double scale = (prior + dof * scales[i]) / (prior + dof);
    result->covariance[i] = scale * result->pooled_covariance / n;
  }
}

}  // namespace

double chiSquare2Quantile(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) throw std::invalid_argument("probability must be in (0, 1)");
  return -2.0 * std::log(1.0 - probability);
}

// Stages: the feature tracks, the image-level rejection, the observation-level rejection and
// per-feature means, then the covariances.
AveragedFeatures averageDetections(const std::vector<Detection>& detections, const AveragingOptions& options) {
  AveragedFeatures result;
  result.images_total = static_cast<int>(detections.size());
  const double threshold = chiSquare2Quantile(options.rejection_confidence);
  const FeatureTracks tracks = collectTracks(detections);
  const std::size_t image_count = tracks.found.size();
  std::vector<bool> kept(image_count, true);
  if (image_count == 0) return result;
  if (image_count >= 3 && options.reject_images) rejectDisplacedImages(tracks.tracks, threshold, &kept);
  for (std::size_t j = 0; j < image_count; ++j)
    if (!kept[j]) result.rejected_images.push_back(tracks.found[j]);
  result.images_used = static_cast<int>(std::count(kept.begin(), kept.end(), true));
  const Scatter scatter = averageTracks(tracks.tracks, kept, threshold, options, &result);
  featureCovariances(scatter, options, &result);
  return result;
}

}  // namespace mire::metrology
