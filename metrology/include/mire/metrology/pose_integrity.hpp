#pragma once
// Static-pose integrity (doc/measurement.md, "Imperfect campaigns"): do the images of one pose folder show one
// static pose? A pose folder is averaged as if it did (feature_averaging.hpp), so a robot that
// crept, or an image from another pose, would otherwise give a confident wrong pose.
//
//  1. Duplicates: an image whose features equal an earlier image's (same ids, every pixel within
//     `duplicate_tolerance_px`) is a copy of that frame and carries no independent information:
//     it is counted once (left out of the average), never called an outlier.
//  2. Per-image pose p_j (estimatePose on image j's features alone, exact nonlinear fit).
//  3. Noise of one observation: the per-image fit residuals r_ij, minus each feature's mean
//     residual over the images (the detector's sub-pixel bias is common to every image of a
//     static pose and cancels there), pooled into one 2×2 covariance Σ with
//     (n − 1)(2N − 6) degrees of freedom, clipped at 5 robust σ.
//  4. Pairwise test: with I_j = J_jᵀ Σ⁻¹ J_j the pose information of image j (J_j the
//     reprojection Jacobian of its features at the pooled pose),
//        T_jk = (p_j − p_k)ᵀ (I_j⁻¹ + I_k⁻¹)⁻¹ (p_j − p_k)  ~  χ²(6)  for a static pose.
//     A common bias moves p_j and p_k alike and cancels in the difference. Images j, k agree
//     when T_jk ≤ χ²₆ quantile at 1 − α/(2P), P = n(n − 1)/2 pairs (Bonferroni).
//  5. Global homogeneity (n ≥ 3), which pools every image and so sees a small motion of a
//     group that no single pair shows: Q = Σ_j (p_j − p̄)ᵀ C_j⁻¹ (p_j − p̄), p̄ the weighted
//     mean, C_j = I_j⁻¹; static: Q ~ χ²(6(n − 1)); threshold at 1 − α/2. A static pose fails
//     4 or 5 with probability ≤ α (default 1e-3).
//  6. The largest group of mutually agreeing images is found (pairwise; when only Q fails, the
//     larger of two clusters of the per-image poses); when it is not every image, the pose
//     fails naming the images outside it (or, with SplitPolicy::KeepLargest, keeps the group
//     when it holds more than half the images, and lists the rest).
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/detection.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mire::metrology {

enum class SplitPolicy { Fail, KeepLargest };

struct IntegrityOptions {
  bool enabled = true;
  double false_alarm = 1e-3;  // α: probability of failing a genuinely static pose
  double duplicate_tolerance_px = 1e-9;
  SplitPolicy split = SplitPolicy::Fail;
};

struct IntegrityResult {
  bool consistent = true;          // every (unique) image agrees, or the split was allowed
  std::string error;               // when !consistent: names the images that disagree
  std::vector<std::string> notes;  // duplicates counted once, images left out by a split
  std::vector<int> duplicate_of;   // per input image: index of the earlier identical frame, or −1
  std::vector<int> moved;          // input indices outside the largest consistent group
  std::vector<bool> use;           // per input image: enters the average
  double threshold = 0.0;          // χ²₆ threshold applied to each pair
  double max_statistic = 0.0;      // largest T_jk among the images used (0 when < 2 images)
  double global_statistic = 0.0;   // Q over every tested image (0 when < 3 images)
  double global_threshold = 0.0;   // χ² with 6(n − 1) dof at 1 − α/2
  int tested_images = 0;           // unique images with a per-image pose
  Eigen::Matrix2d noise_covariance = Eigen::Matrix2d::Zero();  // Σ of one observation (px²)
};

// `detections`: one per image (found or not), `names` their names for messages.
IntegrityResult checkStaticPose(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Detection>& detections, const std::vector<std::string>& names,
                                const IntegrityOptions& options = {});

// The upper quantile of χ² with an even number k of degrees of freedom: P(χ²_k > q) = tail, by
// bisection on the closed-form survival function e^{−x/2} Σ_{i<k/2} (x/2)^i / i!.
double chiSquareEvenUpperQuantile(int dof, double tail);
double chiSquare6UpperQuantile(double tail);

}  // namespace mire::metrology
