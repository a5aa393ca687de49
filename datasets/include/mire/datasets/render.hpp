#pragma once
// Synthetic images of a planar target seen by a distorted camera, with their exact ground
// truth (doc/simulation.md). Rendering is an exact per-pixel INVERSE mapping: pixel -> normalised ray
// (exact undistortion) -> point (X, Y) on the target plane (homography [r1 r2 t]^-1) ->
// albedo, averaged over n x n sub-samples per pixel (box-filter antialiasing). Rods (a robot's
// legs, doc/legs.md) may stand in front of or behind the target: each sample keeps the nearest
// surface its ray meets.
// Frames and pixel convention: doc/conventions.md (cTm maps target M to camera C,
// integer pixel coordinates at pixel centres).
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/target.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace mire::datasets {

// Exact normalised rays (x, y) with (x, y, 1) the direction, at the pixel CORNERS
// (u, v) = (i - 0.5, j - 0.5), i in [0, width], j in [0, height]. Built once per camera
// (Newton undistortion to 1e-15, warm-started along rows); inside a pixel the ray is
// interpolated bilinearly from its 4 corners (error measured by maxInterpolationErrorPx).
class RayGrid {
 public:
  explicit RayGrid(const calibration::Camera& camera);

  int width() const { return width_; }
  int height() const { return height_; }
  // Exact ray at corner (i, j); NaN where the undistortion did not converge.
  const Eigen::Vector2d& corner(int i, int j) const { return rays_[static_cast<std::size_t>(j) * (width_ + 1) + i]; }
  // Ray at (u, v) in [-0.5, width - 0.5] x [-0.5, height - 0.5], bilinear between corners
  // (error up to 3.3e-4 px in the reference camera's corners, see the test).
  Eigen::Vector2d interpolate(double u, double v) const;
  // The bilinear ray refined by one Newton step on the distortion: quadratic convergence
  // takes the error below 1e-9 px. What the renderer samples.
  Eigen::Vector2d ray(double u, double v) const { return refine(interpolate(u, v), u, v); }
  Eigen::Vector2d refine(const Eigen::Vector2d& guess, double u, double v) const;
  // The same to the same accuracy, cheaper for many rays in one pixel: two steps with a
  // fixed inverse Jacobian of the distortion, inverseJacobian(ray near the pixel).
  Eigen::Vector2d refine(const Eigen::Vector2d& guess, double u, double v, const Eigen::Matrix2d& inverse_jacobian) const;
  Eigen::Matrix2d inverseJacobian(const Eigen::Vector2d& ray) const;

  // Largest |project(ray) - (u, v)| in pixels over `samples_per_side`^2 sub-pixel positions
  // of every `pixel_stride`-th pixel (the image corners, where the distortion is strongest,
  // are always included); ray = interpolate(u, v), or when `refined` what the renderer samples
  // (refine with the inverse Jacobian at the pixel's centre).
  double maxInterpolationErrorPx(const calibration::Camera& camera, int pixel_stride, int samples_per_side,
                                 bool refined) const;

 private:
  // Distorted (ray) minus the distorted normalised point of pixel (u, v).
  Eigen::Vector2d distortionResidual(const Eigen::Vector2d& ray, double u, double v) const;

  int width_ = 0;
  int height_ = 0;
  std::vector<Eigen::Vector2d> rays_;
  std::vector<double> params_;  // the camera's fx fy cx cy + distortion
  calibration::LensModel lens_ = calibration::LensModel::OpenCV;
};

enum class Vignetting { None, Cos4, Polynomial };

struct RenderOptions {
  int supersampling = 4;              // n: n x n sub-samples per pixel (1 = point sampling)
  bool adaptive = true;               // supersample only pixels near an edge (exact for features > 1 px)
  double dark_level = 25.0;           // grey level (0-255) of the target's dark parts
  double light_level = 225.0;         // grey level of the target's white paper
  double background_level = 110.0;    // uniform background beyond the paper
  bool cluttered_background = false;  // random shapes instead of the uniform background
  double blur_sigma_px = 0.0;         // defocus: Gaussian blur sigma in pixels (0 = sharp)
  Vignetting vignetting = Vignetting::None;
  // Polynomial vignetting: gain = 1 + a1 r^2 + a2 r^4 + ..., r the distorted normalised
  // radius ((u - cx) / fx, (v - cy) / fy). Cos4: gain = cos^4 of the ray's angle to the axis.
  std::vector<double> vignetting_coefficients;
  std::uint64_t seed = 0;  // the cluttered background's shapes
  // Rods: a matte grey lit from the camera, `rod_level` where the surface faces the camera,
  // darkened by Lambert's cosine to (1 − rod_shading)·rod_level at the silhouette. Darker than
  // the background and the paper, so that both silhouette edges contrast with both.
  double rod_level = 80.0;
  double rod_shading = 0.4;
};

// A rod: a finite cylinder with flat ends, its axis from `from` to `to` in the CAMERA frame [m].
struct Rod {
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
};

// Sensor noise, added to a clean radiance image (so that the 10 images of one static pose
// share one render, paper §5).
struct NoiseOptions {
  double gaussian_sigma = 0.0;  // additive read noise, grey levels
  // Shot noise: electrons per grey level; the signal I gets variance I / gain (Gaussian
  // approximation of Poisson(I * gain) / gain). 0 = no shot noise.
  double shot_noise_gain = 0.0;
};

// Where each target feature (Target::points(), same order) projects: Camera::project of
// cTm * P. For circles that is the projected CENTRE, not the centre of the imaged ellipse.
struct FeatureTruth {
  std::vector<Eigen::Vector2d> pixels;  // NaN when behind the camera
  std::vector<bool> visible;            // in front, inside the image, within the lens's field
  std::size_t visibleCount() const;
};

FeatureTruth projectFeatures(const calibration::Camera& camera, const metrology::Target& target,
                             const Eigen::Isometry3d& camera_T_target);

struct Rendering {
  cv::Mat radiance;  // CV_32F, grey levels before noise and quantisation
  cv::Mat image;     // CV_8U, radiance rounded (noise-free image)
  FeatureTruth truth;
  int supersampled_pixels = 0;  // how many pixels got n x n samples (adaptive mode)
};

class TargetAlbedo;  // grey level of the printed target at (X, Y) (render_albedo.cpp)

// Renders one camera + target, for any number of poses. Thread-safe const methods.
class Renderer {
 public:
  Renderer(calibration::Camera camera, metrology::Target target, RenderOptions options = {});
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // The target, and in front of or behind it the rods (none: the target alone, the same bytes
  // as before rods existed). Throws std::invalid_argument for a degenerate rod.
  Rendering render(const Eigen::Isometry3d& camera_T_target, const std::vector<Rod>& rods = {}) const;

  const calibration::Camera& camera() const { return camera_; }
  const metrology::Target& target() const { return target_; }
  const RenderOptions& options() const { return options_; }
  const RayGrid& rays() const { return *rays_; }

 private:
  calibration::Camera camera_;
  metrology::Target target_;
  RenderOptions options_;
  std::unique_ptr<RayGrid> rays_;
  std::unique_ptr<TargetAlbedo> albedo_;
  cv::Mat background_;  // CV_32F background image (uniform or cluttered)
  cv::Mat vignetting_;  // CV_32F gain per pixel, empty if none
};

// Adds noise to `radiance` (CV_32F) and quantises to 8 bits. Deterministic for a seed.
cv::Mat addNoise(const cv::Mat& radiance, const NoiseOptions& noise, std::uint64_t seed);

// The same in two steps, for several noisy images of one render: the per-pixel noise σ
// (read and shot noise, CV_32F), then one noisy image; addNoiseWithSigma(r, noiseSigma(r, n), s)
// equals addNoise(r, n, s).
cv::Mat noiseSigma(const cv::Mat& radiance, const NoiseOptions& noise);
cv::Mat addNoiseWithSigma(const cv::Mat& radiance, const cv::Mat& sigma, std::uint64_t seed);

// Rounds and clamps a CV_32F radiance image to CV_8U.
cv::Mat quantize(const cv::Mat& radiance);

}  // namespace mire::datasets
