// `mire plan --camera` acceptance study (doc/plan-and-select.md, "--camera"), run by hand:
// 15 poses planned for h4-12 with the demo's camera and target and the demo's mounting (the
// simulated H4's camera below the workspace, the board centred under the effector), every
// planned pose rendered (the demo's blur and sensor noise, several images each) and measured
// as `mire measure` does (metrology::measurePose); then (1) every corner of every planned pose
// is found, (2) the σ `measure` reports against the σ the plan predicted, per component and
// per √trace (translation, rotation). First the detector's random and systematic error is
// measured on 10 other (not planned) candidate poses: the defaults of --pixel-sigma,
// --systematic-px and the board model's A,B (--systematic-board) come from there.
// Usage: bench_plan_camera [measure_camera.yaml ("" or absent: the true reference camera)]
//                          [images_per_pose=10] [pixel_sigma=<plan default>]
//                          [systematic_px (given: the Constant model; absent or "": plan's default BoardImage model)]
//                          [candidates=10000]
// The images are rendered with the true reference camera; the planning and the measurement use
// the given camera (e.g. the demo's calibrated camera.yaml, with its covariance).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mire/calibration/camera_formats.hpp"
#include "mire/datasets/data_dir.hpp"
#include "mire/datasets/h4_true_robot.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/pipeline/camera_plan.hpp"
#include "mire/support/constants.hpp"

namespace {

namespace mech = mire::mechanism;
namespace metro = mire::metrology;
using Sigma6 = Eigen::Matrix<double, 6, 1>;
using mire::support::kPi;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The demo's mounting (datasets/src/mechanism_image_campaign.cpp): the board centred under the effector.
mech::MountingGuess demoMounting(const metro::Target& target) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : target.points()) centroid += p;
  centroid /= static_cast<double>(target.points().size());
  mech::MountingGuess mounting;
  mounting.bTc = mire::datasets::defaultBaseTCamera();
  mounting.mTe = mire::datasets::defaultMarkerTEffector();
  mounting.mTe.translation().x() = centroid.x();
  mounting.mTe.translation().y() = centroid.y();
  return mounting;
}

// Renders one pose `images` times (one render, independent sensor noise, as the demo's
// campaign) and measures it as `mire measure` does.
metro::PoseMeasurement renderAndMeasure(const mire::datasets::Renderer& renderer,
                                        const mire::datasets::MechanismImageCampaignSpec& spec,
                                        const mire::calibration::Camera& camera, const metro::Target& target,
                                        const Eigen::Isometry3d& cTm, int images, std::size_t seed) {
  const mire::datasets::Rendering r = renderer.render(cTm);
  const cv::Mat sigma = mire::datasets::noiseSigma(r.radiance, spec.noise);
  std::vector<cv::Mat> frames;
  std::vector<std::string> names;
  for (int i = 0; i < images; ++i) {
    frames.push_back(mire::datasets::addNoiseWithSigma(r.radiance, sigma, 1000 * seed + static_cast<std::size_t>(i)));
    names.push_back("img" + std::to_string(i));
  }
  return metro::measurePose(camera, target, frames, names);
}

// The detector's error per feature and axis on these images: random (one image, from the
// scatter over the pose's images) and systematic (what the fit's reduced χ² adds beyond the
// random part of the mean: σ_eff² = χ²·σ_px²/n = σ_px²/n + σ_sys²).
struct DetectorNoise {
  double random_px = 0.0, systematic_px = 0.0;
};
DetectorNoise detectorNoise(const metro::PoseMeasurement& m, int images) {
  const double random2 = 0.5 * m.features.pooled_covariance.trace();
  const double effective2 = std::max(1.0, m.estimate.reduced_chi2) * random2 / images;
  return {std::sqrt(random2), std::sqrt(std::max(0.0, effective2 - random2 / images))};
}

struct Comparison {
  std::vector<double> component_ratios, trace_ratios;
  int complete = 0, poses = 0;
};

// Measures one planned pose, prints predicted vs reported σ and accumulates the ratios
// reported/predicted.
void measurePlannedPose(const mire::datasets::Renderer& renderer,
                        const mire::datasets::MechanismImageCampaignSpec& spec, const mire::calibration::Camera& camera,
                        const metro::Target& target, const Eigen::Isometry3d& cTm, const Sigma6& predicted,
                        const metro::PredictionOptions& prediction, std::size_t k, Comparison* c) {
  const int images = prediction.images;
  const metro::PoseMeasurement m = renderAndMeasure(renderer, spec, camera, target, cTm, images, k);
  ++c->poses;
  if (!m.ok) {
    std::printf("p%03zu  FAILED: %s\n", k + 1, m.error.c_str());
    return;
  }
  const auto n = static_cast<int>(m.features.size());
  if (n == static_cast<int>(target.points().size())) ++c->complete;
  const Sigma6 reported = metro::PoseEstimate::sigmas(m.estimate.covariance);
  const DetectorNoise noise = detectorNoise(m, images);
  const metro::Visibility v = metro::targetVisibility(camera, target, cTm);
  const metro::BoardImageGeometry g = metro::boardImageGeometry(camera, target.points(), cTm);
  const double in_plane = std::atan2(cTm.linear()(1, 0), cTm.linear()(0, 0)) * 180 / kPi;
  std::printf(
      "p%03zu  corners %d/%zu  chi2 %.1f  detector random %.4f px, systematic %.4f px  (distance %.3f m, "
      "tilt %.1f deg, in-plane angle %.1f deg, margin %.0f px, square %.2f px, edge angle %.1f deg, "
      "predicted systematic %.4f px)\n",
      k + 1, n, target.points().size(), m.estimate.reduced_chi2, noise.random_px, noise.systematic_px,
      cTm.translation().norm(), v.tilt_deg, in_plane, v.min_margin_px, g.square_px, g.edge_angle_rad * 180 / kPi,
      prediction.systematicSigma(g.square_px, g.edge_angle_rad));
  std::printf("      predicted  %.4f %.4f %.4f mm  %.5f %.5f %.5f deg\n", predicted[0] * 1e3, predicted[1] * 1e3,
              predicted[2] * 1e3, predicted[3] * 180 / kPi, predicted[4] * 180 / kPi, predicted[5] * 180 / kPi);
  std::printf("      reported   %.4f %.4f %.4f mm  %.5f %.5f %.5f deg  ratio", reported[0] * 1e3, reported[1] * 1e3,
              reported[2] * 1e3, reported[3] * 180 / kPi, reported[4] * 180 / kPi, reported[5] * 180 / kPi);
  for (int i = 0; i < 6; ++i) {
    c->component_ratios.push_back(reported[i] / predicted[i]);
    std::printf(" %.3f", reported[i] / predicted[i]);
  }
  const double rt = reported.head<3>().norm() / predicted.head<3>().norm();
  const double rr = reported.tail<3>().norm() / predicted.tail<3>().norm();
  c->trace_ratios.push_back(rt);
  c->trace_ratios.push_back(rr);
  std::printf("  sqrt-trace t %.3f r %.3f\n", rt, rr);
}

// Least-squares fit of the BoardImage model (pose_prediction.hpp) on the calibration poses:
// σ_sys · s / s_ref = a + b cos 4φ; printed with the fit residual, beside the 1/s-only fit (b = 0).
void fitBoardImageModel(const std::vector<double>& systematic, const std::vector<double>& square,
                        const std::vector<double>& angle) {
  const double reference = metro::PredictionOptions().reference_square_px;
  const auto n = static_cast<Eigen::Index>(systematic.size());
  Eigen::MatrixXd a(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    a(i, 0) = 1.0;
    a(i, 1) = std::cos(4.0 * angle[k]);
    y[i] = systematic[k] * square[k] / reference;
  }
  const Eigen::Vector2d ab = a.colPivHouseholderQr().solve(y);
  const double mean_only = y.mean();
  const double rms_ab = std::sqrt((a * ab - y).squaredNorm() / static_cast<double>(n));
  const double rms_mean = std::sqrt((y.array() - mean_only).square().sum() / static_cast<double>(n));
  std::printf(
      "BoardImage fit at s_ref %.0f px: a %.4f px, b %.4f px (rms %.4f px); 1/s only: a %.4f px (rms %.4f px)\n",
      reference, ab[0], ab[1], rms_ab, mean_only, rms_mean);
}

// The detector's noise measured on `count` visible candidates that are not planned (every
// k-th one): the medians, what `--pixel-sigma` and `--systematic-px` default to.
DetectorNoise calibrateNoise(const mire::datasets::Renderer& renderer,
                             const mire::datasets::MechanismImageCampaignSpec& spec,
                             const mire::calibration::Camera& camera, const metro::Target& target,
                             const mech::CandidateInformation& info, const std::vector<int>& design, int images,
                             int count) {
  std::vector<double> random, systematic, square, angle;
  const std::size_t stride = info.observations.size() / static_cast<std::size_t>(count);
  for (std::size_t j = stride / 2; j < info.observations.size() && static_cast<int>(random.size()) < count; j += stride) {
    if (std::find(design.begin(), design.end(), static_cast<int>(j)) != design.end()) continue;
    const metro::PoseMeasurement m =
        renderAndMeasure(renderer, spec, camera, target, mech::toIsometry(info.observations[j].cTm), images, 500 + j);
    if (!m.ok) continue;
    const DetectorNoise d = detectorNoise(m, images);
    const metro::BoardImageGeometry g =
        metro::boardImageGeometry(camera, target.points(), mech::toIsometry(info.observations[j].cTm));
    random.push_back(d.random_px);
    systematic.push_back(d.systematic_px);
    square.push_back(g.square_px);
    angle.push_back(g.edge_angle_rad);
    std::printf("  calibration pose %zu: systematic %.4f px, square %.2f px, edge angle %.1f deg\n", j, d.systematic_px,
                g.square_px, g.edge_angle_rad * 180 / kPi);
  }
  fitBoardImageModel(systematic, square, angle);
  std::printf("detector on %zu other poses: random %.4f px per image [%.4f, %.4f], systematic %.4f px [%.4f, %.4f]\n",
              random.size(), median(random), *std::min_element(random.begin(), random.end()),
              *std::max_element(random.begin(), random.end()), median(systematic),
              *std::min_element(systematic.begin(), systematic.end()),
              *std::max_element(systematic.begin(), systematic.end()));
  return {median(random), median(systematic)};
}

double worst(const std::vector<double>& ratios) {
  double w = 1.0;
  for (const double r : ratios)
    if (std::abs(std::log(r)) > std::abs(std::log(w))) w = r;
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  const auto t0 = std::chrono::steady_clock::now();
  mire::datasets::MechanismImageCampaignSpec spec = mire::datasets::MechanismImageCampaignSpec::reference("h4");
  const mire::calibration::Camera truth = mire::calibration::readCamera(spec.camera_file);
  const mire::calibration::Camera camera = argc > 1 && argv[1][0] != 0 ? mire::calibration::readCamera(argv[1]) : truth;
  const metro::Target target = metro::Target::fromFile(spec.target_file);
  mire::pipeline::CameraPlanOptions options;
  options.prediction.images = argc > 2 ? std::stoi(argv[2]) : 10;
  if (argc > 3) options.prediction.pixel_sigma = std::stod(argv[3]);
  if (argc > 4 && argv[4][0] != 0) {  // a constant systematic error instead of the BoardImage model
    options.prediction.systematic_px = std::stod(argv[4]);
    options.prediction.systematic_model = metro::SystematicModel::Constant;
  }
  const int candidates = argc > 5 ? std::stoi(argv[5]) : 10000;

  const mech::DesignModel model = mech::makeDesignModel("h4-12");
  const mech::Mechanism& m = *model.registered.mechanism;
  const Eigen::VectorXd g = model.registered.nominal.values();
  const mech::Workspace workspace = mech::protocolWorkspace(m, g);
  const mech::MountingGuess mounting = demoMounting(target);
  const auto poses = mech::generateCandidatePoses(m, g, workspace, candidates, 1);
  const mire::pipeline::CameraCandidates visible =
      mire::pipeline::visibleCandidates(m, mounting, camera, target, poses, options);
  mech::DesignOptions design_options;
  design_options.count = 15;
  const mire::pipeline::CameraPoseModel camera_model = mire::pipeline::cameraPoseModel(camera, target, options);
  const mech::CandidateInformation info = mech::candidateInformation(model, mounting, visible.visible, design_options,
                                                                     camera_model.covariance, camera_model.shared);
  const mech::DesignReport report = mech::planExperiment(info, design_options);
  const auto predicted = mire::pipeline::plannedPoseSigmas(info, report.design, camera, target, options);
  const double plan_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  mire::pipeline::CameraPlanSummary summary{options,         poses.size(),    visible.visible.size(),
                                            visible.outside, visible.oblique, predicted};
  std::printf("%s", mire::pipeline::cameraPlanText(summary).c_str());
  std::printf("plan: %.2f s wall; median geometric sigma ratio plan/random %.3f\n\n", plan_seconds,
              report.median_ratio_plan_random);

  const mire::datasets::Renderer renderer(truth, target, spec.render);
  calibrateNoise(renderer, spec, camera, target, info, report.design, options.prediction.images, 10);
  Comparison c;
  for (std::size_t k = 0; k < report.design.size(); ++k) {
    const auto& cTm = info.observations[static_cast<std::size_t>(report.design[k])].cTm;
    measurePlannedPose(renderer, spec, camera, target, mech::toIsometry(cTm), predicted[k], options.prediction, k, &c);
  }
  std::printf("\nall corners found in %d of %d planned poses\n", c.complete, c.poses);
  std::printf("reported/predicted sigma, per component (%zu): median %.3f, worst %.3f, range [%.3f, %.3f]\n",
              c.component_ratios.size(), median(c.component_ratios), worst(c.component_ratios),
              *std::min_element(c.component_ratios.begin(), c.component_ratios.end()),
              *std::max_element(c.component_ratios.begin(), c.component_ratios.end()));
  std::printf("reported/predicted sqrt-trace (t and r, %zu): median %.3f, worst %.3f\n", c.trace_ratios.size(),
              median(c.trace_ratios), worst(c.trace_ratios));
  std::printf("total %.1f s wall\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}
