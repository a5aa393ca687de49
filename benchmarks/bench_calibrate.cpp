// mire's calibration vs OpenCV on the same synthetic points (run by hand):
//  1. flat board, 0.1 px noise: time ratio and errors to truth vs cv::calibrateCamera;
//  2. board bowed by 0.3 mm: mire flat, mire --refine-target, cv::calibrateCamera and
//     cv::calibrateCameraRO (iFixedPoint = far corner of the first row).
#include "mire/calibration/calibrate.hpp"

#include "../tests/common/synthetic_calibration.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double medianSeconds(int repeats, const std::function<void()>& work) {
  std::vector<double> times;
  for (int i = 0; i < repeats; ++i) {
    const auto start = Clock::now();
    work();
    times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct Scene {
  std::vector<mire::test::SyntheticView> views;
  std::vector<std::vector<Eigen::Vector2d>> pixels;
};

double worstIntrinsicError(const std::vector<double>& estimate, const std::vector<double>& truth) {
  double worst = 0.0;
  for (int i = 0; i < 4; ++i) worst = std::max(worst, std::abs(estimate[i] - truth[i]));
  return worst;
}

struct OpenCvResult {
  std::vector<double> params;
  std::vector<cv::Point3f> new_points;
  double rms = 0.0;
};

OpenCvResult runOpenCv(const Scene& scene, const std::vector<Eigen::Vector3d>& nominal, int fixed_point) {
  // calibrateCameraRO needs every view to hold the same points: only full views are used then.
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (std::size_t v = 0; v < scene.views.size(); ++v) {
    if (fixed_point > 0 && scene.views[v].ids.size() != nominal.size()) continue;
    object.emplace_back();
    image.emplace_back();
    for (std::size_t k = 0; k < scene.views[v].ids.size(); ++k) {
      const auto& p = nominal[scene.views[v].ids[k]];
      object.back().emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      image.back().emplace_back(static_cast<float>(scene.pixels[v][k].x()), static_cast<float>(scene.pixels[v][k].y()));
    }
  }
  cv::Mat camera_matrix, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  OpenCvResult result;
  const auto criteria = cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, DBL_EPSILON);
  if (fixed_point > 0) {
    cv::Mat new_points;
    result.rms = cv::calibrateCameraRO(object, image, cv::Size(1024, 768), fixed_point, camera_matrix, distortion,
                                       rvecs, tvecs, new_points, 0, criteria);
    for (int i = 0; i < static_cast<int>(new_points.total()); ++i)
      result.new_points.push_back(new_points.at<cv::Point3f>(i));
  } else {
    result.rms =
        cv::calibrateCamera(object, image, cv::Size(1024, 768), camera_matrix, distortion, rvecs, tvecs, 0, criteria);
  }
  result.params = {camera_matrix.at<double>(0, 0), camera_matrix.at<double>(1, 1), camera_matrix.at<double>(0, 2),
                   camera_matrix.at<double>(1, 2)};
  for (int i = 0; i < 5; ++i) result.params.push_back(distortion.at<double>(i));
  return result;
}

std::vector<mire::calibration::CalibrationView> toViews(const Scene& scene) {
  std::vector<mire::calibration::CalibrationView> views;
  for (std::size_t v = 0; v < scene.views.size(); ++v) views.push_back({"", scene.views[v].ids, scene.pixels[v]});
  return views;
}

}  // namespace

int main() {
  const auto truth = mire::test::referenceCamera();
  const auto nominal = mire::test::gridTarget(11, 8, 0.02);
  const int repeats = 5;

  {
    Scene scene;
    scene.views = mire::test::makeViews(truth, nominal, 25, 7);
    scene.pixels = mire::test::noisyPixels(scene.views, 0.1, 11);
    mire::calibration::CalibrationResult mire_result;
    OpenCvResult cv_result;
    const double mire_time = medianSeconds(
        repeats, [&] { mire_result = mire::calibration::calibrateCamera(nominal, toViews(scene), 1024, 768); });
    const double cv_time = medianSeconds(repeats, [&] { cv_result = runOpenCv(scene, nominal, 0); });
    std::printf("flat board, 25 views (partial views included), 0.1 px noise, model opencv5:\n");
    std::printf("  mire calibrate     %7.1f ms  worst |fx fy cx cy error| %.4f px  rms %.4f px\n", mire_time * 1e3,
                worstIntrinsicError(mire_result.camera.params, truth.params), mire_result.camera.rms_px);
    std::printf("  cv::calibrateCamera%7.1f ms  worst |fx fy cx cy error| %.4f px  rms %.4f px\n", cv_time * 1e3,
                worstIntrinsicError(cv_result.params, truth.params), cv_result.rms);
    std::printf("  time ratio mire / OpenCV = %.2f\n", mire_time / cv_time);
  }

  {
    const double sag = 0.3e-3;
    const auto bowed = mire::test::gridTarget(11, 8, 0.02, sag);
    Scene scene;
    scene.views = mire::test::makeViews(truth, bowed, 40, 17, 40.0, 0.40, 0.25);
    scene.pixels = mire::test::noisyPixels(scene.views, 0.05, 19);
    mire::calibration::CalibrationOptions refine;
    refine.refine_target = true;
    mire::calibration::CalibrationResult flat, refined;
    OpenCvResult cv_flat, cv_ro;
    const double flat_time =
        medianSeconds(repeats, [&] { flat = mire::calibration::calibrateCamera(nominal, toViews(scene), 1024, 768); });
    const double refined_time = medianSeconds(
        repeats, [&] { refined = mire::calibration::calibrateCamera(nominal, toViews(scene), 1024, 768, refine); });
    // Same complete views as calibrateCameraRO gets, for a like-for-like comparison.
    Scene complete;
    for (std::size_t v = 0; v < scene.views.size(); ++v)
      if (scene.views[v].ids.size() == bowed.size()) {
        complete.views.push_back(scene.views[v]);
        complete.pixels.push_back(scene.pixels[v]);
      }
    mire::calibration::CalibrationResult refined_complete;
    const double refined_complete_time = medianSeconds(repeats, [&] {
      refined_complete = mire::calibration::calibrateCamera(nominal, toViews(complete), 1024, 768, refine);
    });
    double mire_complete_z = 0.0;
    for (std::size_t i = 0; i < bowed.size(); ++i)
      mire_complete_z += std::pow(refined_complete.target_points[i].z() - bowed[i].z(), 2);
    const double cv_flat_time = medianSeconds(repeats, [&] { cv_flat = runOpenCv(scene, nominal, 0); });
    const double cv_ro_time = medianSeconds(repeats, [&] { cv_ro = runOpenCv(scene, nominal, 10); });
    double mire_z = 0.0, cv_z = 0.0;
    for (std::size_t i = 0; i < bowed.size(); ++i) {
      mire_z += std::pow(refined.target_points[i].z() - bowed[i].z(), 2);
      if (!cv_ro.new_points.empty()) cv_z += std::pow(std::abs(cv_ro.new_points[i].z) - bowed[i].z(), 2);
    }
    int full_views = 0;
    for (const auto& v : scene.views) full_views += v.ids.size() == bowed.size() ? 1 : 0;
    std::printf("board bowed by %.2f mm, 40 views (%d complete: calibrateCameraRO uses only those), 0.05 px noise:\n",
                sag * 1e3, full_views);
    std::printf("  mire flat           %7.1f ms  worst |fx fy cx cy error| %.3f px  rms %.4f px\n", flat_time * 1e3,
                worstIntrinsicError(flat.camera.params, truth.params), flat.camera.rms_px);
    std::printf(
        "  mire --refine-target%7.1f ms  worst |fx fy cx cy error| %.3f px  rms %.4f px  bow z error rms %.4f mm\n",
        refined_time * 1e3, worstIntrinsicError(refined.camera.params, truth.params), refined.camera.rms_px,
        std::sqrt(mire_z / bowed.size()) * 1e3);
    std::printf(
        "  mire --refine-target, complete views only %7.1f ms  worst |fx fy cx cy error| %.3f px  bow z error rms "
        "%.4f mm\n",
        refined_complete_time * 1e3, worstIntrinsicError(refined_complete.camera.params, truth.params),
        std::sqrt(mire_complete_z / bowed.size()) * 1e3);
    std::printf("  cv::calibrateCamera %7.1f ms  worst |fx fy cx cy error| %.3f px  rms %.4f px\n", cv_flat_time * 1e3,
                worstIntrinsicError(cv_flat.params, truth.params), cv_flat.rms);
    std::printf(
        "  cv::calibrateCameraRO (complete views) %7.1f ms  worst |fx fy cx cy error| %.3f px  rms %.4f px  bow z "
        "error rms %.4f mm "
        "(|z|: OpenCV's gauge sign)\n",
        cv_ro_time * 1e3, worstIntrinsicError(cv_ro.params, truth.params), cv_ro.rms,
        std::sqrt(cv_z / bowed.size()) * 1e3);
    std::printf("  time ratio mire refine / calibrateCameraRO on the same complete views = %.2f\n",
                refined_complete_time / cv_ro_time);
  }
  return 0;
}
