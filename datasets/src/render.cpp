// Inverse-mapping renderer of a planar target through a distorted camera (render.hpp).
#include "mire/datasets/render.hpp"

#include "render_rods.hpp"
#include "target_albedo.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mire::datasets {
namespace {

constexpr float kOffPaper = -1.0f;

// Deterministic per-pixel random stream (SplitMix64): the jitter depends on the pixel only,
// so renders do not depend on the thread schedule.
std::uint64_t pixelHash(int i, int j) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 32) ^ static_cast<std::uint32_t>(i) ^
         0x6A09E667F3BCC909ULL;
}
double unitJitter(std::uint64_t* state) {
  std::uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;  // [0, 1)
}

// Random shapes behind the target (a "cluttered" scene), drawn antialiased once per renderer.
cv::Mat clutteredBackground(int width, int height, double level, std::uint64_t seed) {
  cv::Mat canvas(height, width, CV_8U, cv::Scalar(std::clamp(level, 0.0, 255.0)));
  cv::RNG rng(seed);
  const int count = 60;
  const int size = std::max(width, height);
  for (int n = 0; n < count; ++n) {
    const cv::Scalar grey(rng.uniform(20, 236));
    const cv::Point2f centre(rng.uniform(0.0f, static_cast<float>(width)), rng.uniform(0.0f, static_cast<float>(height)));
    const float extent = rng.uniform(0.02f, 0.15f) * static_cast<float>(size);
    switch (rng.uniform(0, 3)) {
      case 0:
        cv::circle(canvas, centre, static_cast<int>(extent / 2), grey, cv::FILLED, cv::LINE_AA);
        break;
      case 1: {
        const cv::RotatedRect rect(centre, cv::Size2f(extent, extent * rng.uniform(0.2f, 1.0f)),
                                   rng.uniform(0.0f, 180.0f));
        cv::Point2f corners[4];
        rect.points(corners);
        std::vector<cv::Point> polygon;
        for (const auto& corner : corners) polygon.emplace_back(cvRound(corner.x), cvRound(corner.y));
        cv::fillConvexPoly(canvas, polygon, grey, cv::LINE_AA);
        break;
      }
      default: {
        std::vector<cv::Point> triangle;
        triangle.reserve(3);
        for (int k = 0; k < 3; ++k)
          triangle.emplace_back(cvRound(centre.x + rng.uniform(-extent, extent)),
                                cvRound(centre.y + rng.uniform(-extent, extent)));
        cv::fillConvexPoly(canvas, triangle, grey, cv::LINE_AA);
        break;
      }
    }
  }
  cv::Mat background;
  canvas.convertTo(background, CV_32F);
  return background;
}

cv::Mat vignettingGain(const calibration::Camera& camera, const RayGrid& rays, const RenderOptions& options) {
  if (options.vignetting == Vignetting::None) return {};
  cv::Mat gain(camera.height, camera.width, CV_32F);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      double value = 1.0;
      if (options.vignetting == Vignetting::Cos4) {
        const Eigen::Vector2d ray = rays.interpolate(u, v);
        const double cos2 = 1.0 / (1.0 + ray.squaredNorm());
        value = std::isfinite(cos2) ? cos2 * cos2 : 0.0;
      } else {
        const double x = (u - camera.cx()) / camera.fx(), y = (v - camera.cy()) / camera.fy();
        const double r2 = x * x + y * y;
        double power = r2;
        for (const double coefficient : options.vignetting_coefficients) value += coefficient * power, power *= r2;
      }
      gain.at<float>(v, u) = static_cast<float>(std::max(0.0, value));
    }
  }
  return gain;
}

// The target's level seen along a ray (x, y, 1), or kOffPaper when the ray misses it. The ray
// meets the plane z_M = 0 at (X, Y) with s·(x, y, 1) = [r1 r2 t]·(X, Y, 1):
// (X, Y, 1)/s = [r1 r2 t]^-1 (x, y, 1), in front of the camera when 1/s > 0; s is the depth z.
// With rods, the nearest surface: a rod unless the paper is hit in front of it.
class SceneSampler {
 public:
  SceneSampler(const Eigen::Isometry3d& camera_T_target, const TargetAlbedo& albedo, const RodScene& rods)
      : albedo_(albedo), rods_(rods) {
    Eigen::Matrix3d plane_to_ray;
    plane_to_ray << camera_T_target.linear().col(0), camera_T_target.linear().col(1), camera_T_target.translation();
    ray_to_plane_ = plane_to_ray.inverse();
  }
  float operator()(const Eigen::Vector2d& ray) const {
    if (!ray.allFinite()) return kOffPaper;
    const Eigen::Vector3d q = ray_to_plane_ * Eigen::Vector3d(ray.x(), ray.y(), 1.0);
    const float paper = q.z() > 0.0 ? albedo_(q.x() / q.z(), q.y() / q.z()) : kOffPaper;
    double rod_depth = 0.0;
    float rod_level = 0.0f;
    if (rods_.empty() || !rods_.nearest(ray, &rod_depth, &rod_level)) return paper;
    return paper >= 0.0f && 1.0 / q.z() < rod_depth ? paper : rod_level;
  }

 private:
  Eigen::Matrix3d ray_to_plane_;
  const TargetAlbedo& albedo_;
  const RodScene& rods_;
};

// Pass 1: one exact sample at every pixel corner ((height + 1) × (width + 1)).
cv::Mat cornerLevels(const RayGrid& rays, const SceneSampler& sample, int width, int height) {
  cv::Mat corner_level(height + 1, width + 1, CV_32F);
  cv::parallel_for_(cv::Range(0, height + 1), [&](const cv::Range& range) {
    for (int j = range.start; j < range.end; ++j) {
      float* row = corner_level.ptr<float>(j);
      for (int i = 0; i <= width; ++i) row[i] = sample(rays.corner(i, j));
    }
  });
  return corner_level;
}

// Pixels whose corners disagree hold an edge; their 8 neighbours too may hold a small piece
// of a feature (e.g. a square's corner) that misses every corner, so dilate. Non-adaptive
// rendering supersamples every pixel.
cv::Mat pixelsToSupersample(const cv::Mat& corner_level, bool adaptive) {
  const int height = corner_level.rows - 1, width = corner_level.cols - 1;
  cv::Mat edge(height, width, CV_8U);
  for (int j = 0; j < height; ++j) {
    const float* top = corner_level.ptr<float>(j);
    const float* bottom = corner_level.ptr<float>(j + 1);
    auto* out = edge.ptr<std::uint8_t>(j);
    for (int i = 0; i < width; ++i)
      out[i] = (top[i] != top[i + 1] || top[i] != bottom[i] || top[i] != bottom[i + 1]) ? 255 : 0;
  }
  cv::Mat supersample = edge;
  if (adaptive)
    cv::dilate(edge, supersample, cv::Mat());
  else
    supersample.setTo(255);
  return supersample;
}

// Mean level of pixel (i, j) over n x n sub-samples, one jittered in each cell of an n x n
// grid over the pixel (stratified sampling), rays interpolated bilinearly between the corners
// and refined by two Newton steps with the pixel's Jacobian (exact to < 1e-9 px). Why
// jitter: with a fixed grid, a straight edge's coverage is quantised the same way in every
// pixel along it (axis-aligned: steps of 1/n), a coherent error of up to 1/(2n) px in the
// edge's position that no corner or ellipse fit averages out (measured 0.12 px RMS on
// corners); per-pixel jitter makes it incoherent noise. Off the paper: the background.
float supersampledLevel(const RayGrid& rays, const SceneSampler& sample, int i, int j, int n, float background) {
  const Eigen::Vector2d& c00 = rays.corner(i, j);
  const Eigen::Vector2d& c10 = rays.corner(i + 1, j);
  const Eigen::Vector2d& c01 = rays.corner(i, j + 1);
  const Eigen::Vector2d& c11 = rays.corner(i + 1, j + 1);
  // One inverse Jacobian per pixel, at its centre (RayGrid::refine).
  const Eigen::Matrix2d inverse_jacobian = rays.inverseJacobian(0.25 * (c00 + c10 + c01 + c11));
  double sum = 0.0;
  std::uint64_t state = pixelHash(i, j);
  for (int sv = 0; sv < n; ++sv) {
    for (int su = 0; su < n; ++su) {
      const double a = (su + unitJitter(&state)) / n;
      const double b = (sv + unitJitter(&state)) / n;
      const Eigen::Vector2d left = (1.0 - b) * c00 + b * c01;
      const Eigen::Vector2d right = (1.0 - b) * c10 + b * c11;
      const float level = sample(rays.refine((1.0 - a) * left + a * right, i - 0.5 + a, j - 0.5 + b, inverse_jacobian));
      sum += level < 0.0f ? background : level;
    }
  }
  return static_cast<float>(sum / (n * n));
}

}  // namespace

std::size_t FeatureTruth::visibleCount() const {
  return static_cast<std::size_t>(std::count(visible.begin(), visible.end(), true));
}

FeatureTruth projectFeatures(const calibration::Camera& camera, const metrology::Target& target,
                             const Eigen::Isometry3d& camera_T_target) {
  FeatureTruth truth;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector3d& point : target.points()) {
    const Eigen::Vector3d in_camera = camera_T_target * point;
    Eigen::Vector2d pixel(nan, nan);
    bool visible = camera.project(in_camera, &pixel);
    if (!visible) pixel = Eigen::Vector2d(nan, nan);
    visible = visible && pixel.x() >= -0.5 && pixel.x() <= camera.width - 0.5 && pixel.y() >= -0.5 &&
              pixel.y() <= camera.height - 0.5;
    if (visible) {
      // Beyond the lens's monotonic range a far-off point can fold back into the image:
      // it is visible only if undistorting its pixel gives its own ray back.
      Eigen::Vector2d ray;
      visible = camera.unproject(pixel, &ray) &&
                (ray - in_camera.head<2>() / in_camera.z()).norm() < 1e-9 * (1.0 + ray.norm());
    }
    truth.pixels.push_back(pixel);
    truth.visible.push_back(visible);
  }
  return truth;
}

Renderer::Renderer(calibration::Camera camera, metrology::Target target, RenderOptions options)
    : camera_(std::move(camera)), target_(std::move(target)), options_(std::move(options)) {
  camera_.validate();
  if (options_.supersampling < 1 || options_.supersampling > 16)
    throw std::invalid_argument("supersampling must be between 1 and 16, not " + std::to_string(options_.supersampling));
  if (!(options_.blur_sigma_px >= 0.0)) throw std::invalid_argument("blur_sigma_px must be >= 0");
  if (!(options_.rod_level >= 0.0) || !(options_.rod_shading >= 0.0 && options_.rod_shading <= 1.0))
    throw std::invalid_argument("rod_level must be >= 0 and rod_shading in [0, 1]");
  rays_ = std::make_unique<RayGrid>(camera_);
  albedo_ = std::make_unique<TargetAlbedo>(target_, static_cast<float>(options_.dark_level),
                                           static_cast<float>(options_.light_level));
  background_ = options_.cluttered_background
                    ? clutteredBackground(camera_.width, camera_.height, options_.background_level, options_.seed)
                    : cv::Mat(camera_.height, camera_.width, CV_32F, cv::Scalar(options_.background_level));
  vignetting_ = vignettingGain(camera_, *rays_, options_);
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

// Stages: exact levels at the pixel corners, the pixels that hold an edge, then every pixel
// (pass 2: uniform pixels take their corners' level, the others are supersampled), blur,
// vignetting and quantisation.
Rendering Renderer::render(const Eigen::Isometry3d& camera_T_target, const std::vector<Rod>& rods) const {
  const int width = camera_.width, height = camera_.height;
  const RodScene rod_scene(rods, options_);
  const SceneSampler sample(camera_T_target, *albedo_, rod_scene);
  const cv::Mat corner_level = cornerLevels(*rays_, sample, width, height);
  const cv::Mat supersample = pixelsToSupersample(corner_level, options_.adaptive);
  Rendering result;
  result.radiance.create(height, width, CV_32F);
  const int n = options_.supersampling;
  std::vector<int> counts(static_cast<std::size_t>(height), 0);
  cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& range) {
    for (int j = range.start; j < range.end; ++j) {
      float* out = result.radiance.ptr<float>(j);
      const float* background = background_.ptr<float>(j);
      const auto* flags = supersample.ptr<std::uint8_t>(j);
      for (int i = 0; i < width; ++i) {
        if (!flags[i]) {
          const float level = corner_level.at<float>(j, i);
          out[i] = level < 0.0f ? background[i] : level;
          continue;
        }
        ++counts[static_cast<std::size_t>(j)];
        out[i] = supersampledLevel(*rays_, sample, i, j, n, background[i]);
      }
    }
  });
  for (const int count : counts) result.supersampled_pixels += count;

  if (options_.blur_sigma_px > 0.0)
    cv::GaussianBlur(result.radiance, result.radiance, cv::Size(), options_.blur_sigma_px, options_.blur_sigma_px,
                     cv::BORDER_REFLECT);
  if (!vignetting_.empty()) cv::multiply(result.radiance, vignetting_, result.radiance);
  result.image = quantize(result.radiance);
  result.truth = projectFeatures(camera_, target_, camera_T_target);
  return result;
}

cv::Mat quantize(const cv::Mat& radiance) {
  cv::Mat image;
  radiance.convertTo(image, CV_8U);  // rounds to nearest and saturates to [0, 255]
  return image;
}

cv::Mat noiseSigma(const cv::Mat& radiance, const NoiseOptions& noise) {
  if (radiance.type() != CV_32F) throw std::invalid_argument("noiseSigma expects a CV_32F radiance image");
  if (!(noise.gaussian_sigma >= 0.0) || !(noise.shot_noise_gain >= 0.0))
    throw std::invalid_argument("noise sigma and gain must be >= 0");
  // Read noise N(0, σ²) plus shot noise: Poisson(I·g)/g has mean I and variance I/g, and at
  // these signal levels its Gaussian approximation is indistinguishable. The sum of the two
  // independent Gaussians is one Gaussian of variance σ² + I/g.
  cv::Mat variance;
  cv::max(radiance, 0.0, variance);
  variance *= noise.shot_noise_gain > 0.0 ? 1.0 / noise.shot_noise_gain : 0.0;
  variance += noise.gaussian_sigma * noise.gaussian_sigma;
  cv::Mat sigma;
  cv::sqrt(variance, sigma);
  return sigma;
}

cv::Mat addNoiseWithSigma(const cv::Mat& radiance, const cv::Mat& sigma, std::uint64_t seed) {
  if (radiance.type() != CV_32F || sigma.type() != CV_32F || radiance.size() != sigma.size())
    throw std::invalid_argument("addNoiseWithSigma expects CV_32F radiance and sigma images of one size");
  cv::RNG rng(seed);
  cv::Mat noisy(radiance.size(), CV_32F);
  rng.fill(noisy, cv::RNG::NORMAL, 0.0, 1.0);  // one normal draw per pixel
  cv::multiply(noisy, sigma, noisy);
  noisy += radiance;
  return quantize(noisy);
}

cv::Mat addNoise(const cv::Mat& radiance, const NoiseOptions& noise, std::uint64_t seed) {
  return addNoiseWithSigma(radiance, noiseSigma(radiance, noise), seed);
}

}  // namespace mire::datasets
