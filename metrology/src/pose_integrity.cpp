#include "mire/metrology/pose_integrity.hpp"

#include "mire/metrology/pose_estimation.hpp"
#include "mire/support/statistics.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

namespace mire::metrology {
namespace {

using support::kMadToSigma;
// Noise below this (px) is treated as noiseless data, not as infinitely precise.
constexpr double kNoiseFloorPx = 1e-4;

std::string shortName(const std::vector<std::string>& names, std::size_t index) {
  if (index >= names.size() || names[index].empty()) return "image #" + std::to_string(index + 1);
  const std::string name = std::filesystem::path(names[index]).filename().string();
  return name.empty() ? names[index] : name;
}

std::string nameList(const std::vector<std::string>& names, const std::vector<int>& indices) {
  std::string text;
  for (const int j : indices) text += (text.empty() ? "" : ", ") + shortName(names, static_cast<std::size_t>(j));
  return text;
}

std::string toleranceText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

bool sameFeatures(const Detection& a, const Detection& b, double tolerance) {
  if (a.ids != b.ids) return false;
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    if ((a.pixels[i] - b.pixels[i]).cwiseAbs().maxCoeff() > tolerance) return false;
  return true;
}

using support::median;

AveragedFeatures singleImage(const Detection& detection) {
  AveragedFeatures features;
  features.ids = detection.ids;
  features.pixels = detection.pixels;
  features.covariance.assign(detection.ids.size(), Eigen::Matrix2d::Zero());
  features.observations.assign(detection.ids.size(), 1);
  features.images_used = features.images_total = 1;
  return features;
}

// One tested image: its own pose, residuals and the pose covariance per unit noise.
struct ImagePose {
  int index = 0;                     // into the input
  Eigen::Matrix<double, 6, 1> pose;  // (t, r)
  Eigen::Isometry3d cTm;
  std::vector<Eigen::Vector2d> residuals;  // observed − projected, per feature of the detection
  Eigen::MatrixXd jacobian;                // unwhitened 2N×6, (t, r) order
};

bool fitImage(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points, const Detection& detection,
              ImagePose* image) {
  const AveragedFeatures features = singleImage(detection);
  const PoseEstimate estimate = estimatePose(camera, points, features);
  if (!estimate.valid) return false;
  image->cTm = estimate.cTm;
  image->pose << estimate.translation, estimate.rotation_vector;
  for (std::size_t i = 0; i < detection.ids.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!camera.project(estimate.cTm * points[static_cast<std::size_t>(detection.ids[i])], &pixel)) return false;
    image->residuals.emplace_back(detection.pixels[i] - pixel);
  }
  Eigen::MatrixXd jk;
  reprojectionJacobians(camera, points, features, estimate.cTm, &image->jacobian, &jk);
  return true;
}

// Each feature's centre residual over the images in `members`: the mean, or (robust, when
// the images may hold two views) the per-axis median.
std::map<int, std::pair<Eigen::Vector2d, int>> centreResiduals(const std::vector<ImagePose>& images,
                                                               const std::vector<int>& members,
                                                               const std::vector<Detection>& detections, bool robust) {
  std::map<int, std::vector<Eigen::Vector2d>> tracks;
  for (const int m : members) {
    const ImagePose& image = images[static_cast<std::size_t>(m)];
    const Detection& d = detections[static_cast<std::size_t>(image.index)];
    for (std::size_t i = 0; i < d.ids.size(); ++i) tracks[d.ids[i]].push_back(image.residuals[i]);
  }
  std::map<int, std::pair<Eigen::Vector2d, int>> centres;
  for (const auto& [id, values] : tracks) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    if (robust) {
      std::vector<double> xs, ys;
      for (const auto& v : values) {
        xs.push_back(v.x());
        ys.push_back(v.y());
      }
      centre = Eigen::Vector2d(median(xs), median(ys));
    } else {
      for (const auto& v : values) centre += v;
      centre /= static_cast<double>(values.size());
    }
    centres[id] = {centre, static_cast<int>(values.size())};
  }
  return centres;
}

// Σ of one observation from the per-image residuals of the images in `members` about each
// feature's centre residual (the common detector bias cancels), clipped at 5 robust σ per axis.
// The degrees of freedom are those of the mean; with the robust centre (first pass only, to
// find the consistent group) the estimate is slightly high.
Eigen::Matrix2d observationNoise(const std::vector<ImagePose>& images, const std::vector<int>& members,
                                 const std::vector<Detection>& detections, bool robust) {
  const auto centres = centreResiduals(images, members, detections, robust);
  std::vector<Eigen::Vector2d> deviations;
  double dof = 0.0;
  for (const int m : members) {
    const ImagePose& image = images[static_cast<std::size_t>(m)];
    const Detection& d = detections[static_cast<std::size_t>(image.index)];
    dof += 2.0 * static_cast<double>(d.ids.size()) - 6.0;
    for (std::size_t i = 0; i < d.ids.size(); ++i) {
      const auto& entry = centres.at(d.ids[i]);
      if (entry.second < 2) continue;
      deviations.emplace_back(image.residuals[i] - entry.first);
    }
  }
  int tracked = 0;
  for (const auto& [id, entry] : centres) tracked += entry.second >= 2 ? 1 : 0;
  dof -= std::max(0.0, 2.0 * tracked - 6.0);  // the per-feature mean (itself free of the pose's 6)
  std::vector<double> xs, ys;
  for (const auto& e : deviations) {
    xs.push_back(std::abs(e.x()));
    ys.push_back(std::abs(e.y()));
  }
  const double limit_x = 5.0 * std::max(kMadToSigma * median(xs), kNoiseFloorPx);
  const double limit_y = 5.0 * std::max(kMadToSigma * median(ys), kNoiseFloorPx);
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  std::size_t kept = 0;
  for (const auto& e : deviations) {
    if (std::abs(e.x()) > limit_x || std::abs(e.y()) > limit_y) continue;
    scatter += e * e.transpose();
    ++kept;
  }
  if (deviations.empty() || dof <= 0.0) return kNoiseFloorPx * kNoiseFloorPx * Eigen::Matrix2d::Identity();
  const double effective_dof = dof * static_cast<double>(kept) / static_cast<double>(deviations.size());
  return 2.0 * scatter / std::max(effective_dof, 1.0) + kNoiseFloorPx * kNoiseFloorPx * Eigen::Matrix2d::Identity();
}

// Covariance of the unweighted per-image pose for observation noise Σ (sandwich form).
Eigen::Matrix<double, 6, 6> poseCovariance(const Eigen::MatrixXd& jacobian, const Eigen::Matrix2d& noise) {
  const Eigen::Matrix<double, 6, 6> normal = jacobian.transpose() * jacobian;
  Eigen::Matrix<double, 6, 6> middle = Eigen::Matrix<double, 6, 6>::Zero();
  for (Eigen::Index i = 0; i + 1 < jacobian.rows(); i += 2) {
    const Eigen::Matrix<double, 2, 6> block = jacobian.middleRows(i, 2);
    middle += block.transpose() * noise * block;
  }
  const Eigen::Matrix<double, 6, 6> inverse = normal.fullPivLu().inverse();
  return inverse * middle * inverse;
}

using Covariances = std::vector<Eigen::Matrix<double, 6, 6>>;

Covariances poseCovariances(const std::vector<ImagePose>& images, const Eigen::Matrix2d& noise) {
  Covariances covariance;
  for (const ImagePose& image : images) covariance.push_back(poseCovariance(image.jacobian, noise));
  return covariance;
}

// T_jk for every pair of images, for the per-image pose covariances.
Eigen::MatrixXd pairwiseStatistics(const std::vector<ImagePose>& images, const Covariances& covariance) {
  const std::size_t n = images.size();
  Eigen::MatrixXd statistic = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      const Eigen::Matrix<double, 6, 1> difference = images[a].pose - images[b].pose;
      const Eigen::Matrix<double, 6, 6> sum = covariance[a] + covariance[b];
      const auto ia = static_cast<Eigen::Index>(a), ib = static_cast<Eigen::Index>(b);
      statistic(ia, ib) = statistic(ib, ia) = difference.dot(sum.fullPivLu().solve(difference));
    }
  return statistic;
}

// Cochran's homogeneity statistic Q = Σ_j (p_j − p̄)ᵀ C_j⁻¹ (p_j − p̄) over `members`, p̄ the
// weighted mean: χ² with 6(m − 1) dof for a static pose. Pools the evidence of every image,
// so it sees a small motion of a group of images that no single pair shows.
double homogeneity(const std::vector<ImagePose>& images, const Covariances& covariance, const std::vector<int>& members) {
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> weighted = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Matrix<double, 6, 6>> weights;
  for (const int m : members) {
    weights.emplace_back(covariance[static_cast<std::size_t>(m)].fullPivLu().inverse());
    information += weights.back();
    weighted += weights.back() * images[static_cast<std::size_t>(m)].pose;
  }
  const Eigen::Matrix<double, 6, 1> mean = information.fullPivLu().solve(weighted);
  double q = 0.0;
  for (std::size_t k = 0; k < members.size(); ++k) {
    const Eigen::Matrix<double, 6, 1> d = images[static_cast<std::size_t>(members[k])].pose - mean;
    q += d.dot(weights[k] * d);
  }
  return q;
}

// Two clusters of images (2-means in the per-image pose, Mahalanobis with each image's
// covariance), seeded by the most disagreeing pair; returns the larger cluster.
std::vector<int> largerOfTwoClusters(const std::vector<ImagePose>& images, const Covariances& covariance,
                                     const Eigen::MatrixXd& statistic) {
  const int n = static_cast<int>(images.size());
  Eigen::Index a = 0, b = 0;
  statistic.maxCoeff(&a, &b);
  std::array<Eigen::Matrix<double, 6, 1>, 2> centre = {images[static_cast<std::size_t>(a)].pose,
                                                       images[static_cast<std::size_t>(b)].pose};
  std::vector<int> label(static_cast<std::size_t>(n), 0);
  for (int iteration = 0; iteration < 20; ++iteration) {
    std::array<Eigen::Matrix<double, 6, 6>, 2> information{Eigen::Matrix<double, 6, 6>::Zero(),
                                                           Eigen::Matrix<double, 6, 6>::Zero()};
    std::array<Eigen::Matrix<double, 6, 1>, 2> weighted{Eigen::Matrix<double, 6, 1>::Zero(),
                                                        Eigen::Matrix<double, 6, 1>::Zero()};
    for (int j = 0; j < n; ++j) {
      const auto& image = images[static_cast<std::size_t>(j)];
      const Eigen::Matrix<double, 6, 6> weight = covariance[static_cast<std::size_t>(j)].fullPivLu().inverse();
      const Eigen::Matrix<double, 6, 1> d0 = image.pose - centre[0], d1 = image.pose - centre[1];
      const int c = d0.dot(weight * d0) <= d1.dot(weight * d1) ? 0 : 1;
      label[static_cast<std::size_t>(j)] = c;
      information[static_cast<std::size_t>(c)] += weight;
      weighted[static_cast<std::size_t>(c)] += weight * image.pose;
    }
    for (int c = 0; c < 2; ++c)
      if (information[static_cast<std::size_t>(c)].trace() > 0.0)
        centre[static_cast<std::size_t>(c)] =
            information[static_cast<std::size_t>(c)].fullPivLu().solve(weighted[static_cast<std::size_t>(c)]);
  }
  std::array<std::vector<int>, 2> clusters;
  for (int j = 0; j < n; ++j) clusters[static_cast<std::size_t>(label[static_cast<std::size_t>(j)])].push_back(j);
  if (clusters[0].empty() || clusters[1].empty()) {  // no second cluster: the seed stands apart
    std::vector<int> rest;
    for (int j = 0; j < n; ++j)
      if (j != static_cast<int>(b)) rest.push_back(j);
    return rest;
  }
  return clusters[0].size() >= clusters[1].size() ? clusters[0] : clusters[1];
}

// Largest set of mutually agreeing images: from each seed, its agreeing neighbours, pruned of
// the member with most disagreements until every pair agrees.
std::vector<int> largestConsistentGroup(const Eigen::MatrixXd& statistic, double threshold) {
  const int n = static_cast<int>(statistic.rows());
  std::vector<int> best;
  double best_worst = 0.0;
  for (int seed = 0; seed < n; ++seed) {
    std::vector<int> group;
    for (int k = 0; k < n; ++k)
      if (statistic(seed, k) <= threshold) group.push_back(k);
    while (true) {
      int worst = -1, worst_count = 0;
      double worst_sum = 0.0;
      for (const int a : group) {
        int count = 0;
        double sum = 0.0;
        for (const int b : group) {
          count += statistic(a, b) > threshold ? 1 : 0;
          sum += statistic(a, b);
        }
        if (count > worst_count || (count == worst_count && count > 0 && sum > worst_sum)) {
          worst = a;
          worst_count = count;
          worst_sum = sum;
        }
      }
      if (worst < 0) break;
      group.erase(std::find(group.begin(), group.end(), worst));
    }
    double group_worst = 0.0;
    for (const int a : group)
      for (const int b : group) group_worst = std::max(group_worst, statistic(a, b));
    if (group.size() > best.size() || (group.size() == best.size() && group_worst < best_worst)) {
      best = group;
      best_worst = group_worst;
    }
  }
  return best;
}

void markDuplicates(const std::vector<Detection>& detections, const std::vector<std::string>& names,
                    const IntegrityOptions& options, IntegrityResult* result) {
  std::map<int, std::vector<int>> copies;  // first frame → its copies
  for (std::size_t j = 0; j < detections.size(); ++j) {
    if (!detections[j].found) continue;
    for (std::size_t k = 0; k < j; ++k)
      if (detections[k].found && result->duplicate_of[k] < 0 &&
          sameFeatures(detections[j], detections[k], options.duplicate_tolerance_px)) {
        result->duplicate_of[j] = static_cast<int>(k);
        result->use[j] = false;
        copies[static_cast<int>(k)].push_back(static_cast<int>(j));
        break;
      }
  }
  for (const auto& [first, list] : copies)
    result->notes.push_back(std::to_string(list.size()) + " frame(s) identical to " +
                            shortName(names, static_cast<std::size_t>(first)) + " (features equal to " +
                            toleranceText(options.duplicate_tolerance_px) +
                            " px) counted once: " + nameList(names, list));
}

// The images outside `group` fail the pose (or, split allowed and a majority kept, are left
// out), named with the evidence.
void decide(const std::vector<ImagePose>& images, const Eigen::MatrixXd& statistic, const std::vector<int>& group,
            const std::string& evidence, const std::vector<std::string>& names, const IntegrityOptions& options,
            IntegrityResult* result) {
  const int n = static_cast<int>(images.size());
  std::vector<int> kept, moved;
  for (int a = 0; a < n; ++a) {
    const int index = images[static_cast<std::size_t>(a)].index;
    if (std::find(group.begin(), group.end(), a) != group.end())
      kept.push_back(index);
    else
      moved.push_back(index);
  }
  if (moved.empty()) return;
  std::ostringstream text;
  text.precision(3);
  text << "the images do not show one static pose (the robot or the target moved, or an image belongs to "
          "another pose): "
       << nameList(names, moved) << " disagree with " << nameList(names, kept) << " (" << evidence
       << "pairwise pose difference chi-square up to " << statistic.maxCoeff() << ", 6 dof, threshold "
       << result->threshold << ")";
  result->moved = moved;
  const bool majority = 2 * kept.size() > static_cast<std::size_t>(n);
  if (options.split == SplitPolicy::KeepLargest && majority) {
    for (const int j : moved) result->use[static_cast<std::size_t>(j)] = false;
    result->notes.push_back(text.str() + "; kept the largest consistent group, left out: " + nameList(names, moved));
    return;
  }
  result->consistent = false;
  result->error = text.str() + (options.split == SplitPolicy::KeepLargest
                                    ? "; no consistent group holds more than half of the images"
                                    : "; --split-moving keep-largest keeps the largest consistent group");
}

}  // namespace

double chiSquareEvenUpperQuantile(int dof, double tail) {
  if (!(tail > 0.0 && tail < 1.0)) throw std::invalid_argument("chi-square tail probability must be in (0, 1)");
  if (dof < 2 || dof % 2 != 0) throw std::invalid_argument("chi-square degrees of freedom must be even and >= 2");
  // Survival function of χ² with even dof k: e^{−x/2} Σ_{i<k/2} (x/2)^i / i!.
  const auto survival = [dof](double x) {
    double term = 1.0, sum = 1.0;
    for (int i = 1; i < dof / 2; ++i) sum += (term *= 0.5 * x / i);
    return std::exp(-0.5 * x) * sum;
  };
  double low = 0.0, high = 1.0;
  while (survival(high) > tail) high *= 2.0;
  for (int i = 0; i < 200 && high - low > 1e-12 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (survival(middle) > tail ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

double chiSquare6UpperQuantile(double tail) { return chiSquareEvenUpperQuantile(6, tail); }

IntegrityResult checkStaticPose(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Detection>& detections, const std::vector<std::string>& names,
                                const IntegrityOptions& options) {
  IntegrityResult result;
  result.duplicate_of.assign(detections.size(), -1);
  result.use.assign(detections.size(), true);
  for (std::size_t j = 0; j < detections.size(); ++j) result.use[j] = detections[j].found;
  if (!options.enabled) return result;
  markDuplicates(detections, names, options, &result);

  // Per-image poses of the unique frames (the camera's covariance is not needed here).
  calibration::Camera bare = camera;
  bare.covariance.resize(0, 0);
  std::vector<ImagePose> images;
  for (std::size_t j = 0; j < detections.size(); ++j) {
    if (!result.use[j]) continue;
    ImagePose image;
    image.index = static_cast<int>(j);
    if (fitImage(bare, points, detections[j], &image))
      images.push_back(std::move(image));
    else
      result.notes.push_back(shortName(names, j) + ": no pose from this image alone; not tested for motion");
  }
  result.tested_images = static_cast<int>(images.size());
  if (images.size() < 2) return result;

  // Pairwise χ² of the per-image pose differences: a first pass with the robust noise (two
  // views would inflate a mean-based one) finds the consistent group; the noise is then
  // re-estimated within that group (mean, exact degrees of freedom) and the test repeated.
  // Half of the false-alarm budget α goes to the pairwise tests (Bonferroni over the pairs),
  // half to the global homogeneity test below.
  const int n = static_cast<int>(images.size());
  const double pairs = 0.5 * n * (n - 1);
  const bool global = n >= 3;
  result.threshold = chiSquare6UpperQuantile(options.false_alarm / (global ? 2.0 : 1.0) / pairs);
  std::vector<int> everyone(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a) everyone[static_cast<std::size_t>(a)] = a;
  Eigen::MatrixXd statistic =
      pairwiseStatistics(images, poseCovariances(images, observationNoise(images, everyone, detections, true)));
  std::vector<int> group = largestConsistentGroup(statistic, result.threshold);
  result.noise_covariance = observationNoise(images, group.size() >= 2 ? group : everyone, detections, false);
  const Covariances covariance = poseCovariances(images, result.noise_covariance);
  statistic = pairwiseStatistics(images, covariance);
  group = largestConsistentGroup(statistic, result.threshold);
  std::ostringstream evidence;
  evidence.precision(3);
  if (global) {
    result.global_threshold = chiSquareEvenUpperQuantile(6 * (n - 1), options.false_alarm / 2.0);
    result.global_statistic = homogeneity(images, covariance, everyone);
    if (static_cast<int>(group.size()) == n && result.global_statistic > result.global_threshold)
      group = largerOfTwoClusters(images, covariance, statistic);
    evidence << "homogeneity chi-square of the per-image poses " << result.global_statistic << " (" << 6 * (n - 1)
             << " dof, threshold " << result.global_threshold << "), ";
  }
  for (const int a : group)
    for (const int b : group) result.max_statistic = std::max(result.max_statistic, statistic(a, b));
  decide(images, statistic, group, evidence.str(), names, options, &result);
  return result;
}

}  // namespace mire::metrology
