// bench_chain's H4 study (chain_study.hpp; doc/studies/2026-11-24-chain-study-h4.md):
// each chain renders a new campaign of the demo's camera and an exactly-model-12 H4 (the demo's
// error sizes 5 mm / 2° / 5°, unmodelled defects set to zero), then runs the pipeline as
// `mire demo` does — calibrate from the images, measure the 81 poses from their images with the
// shared-term side file, identify model 12 (variant D) — and scores every stage against the
// simulator's truth: calibration error/σ, pose error/σ, identification error/σ with and without
// the shared calibration term.
// Even chains: the same robot (robot seed 2004); odd chains: a different random robot each.
// Camera placement: drawn anew per chain (default), or the demo's for every chain ("fixed").
#include "chain_prediction.hpp"
#include "chain_statistics.hpp"
#include "chain_study.hpp"

#include "mire/calibration/calibrate.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/shared_term_csv.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/image_folders.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/side_files.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mire::bench {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

// Everything scored over the chains.
struct Study {
  Samples calibration_z;                  // camera parameter: error/σ
  std::vector<double> calibration_chi2;   // Mahalanobis of the camera error, per chain
  Samples pose_z, pose_z_independent;     // component: error/σ (full σ), (error − D Δk)/σ_noise
  std::vector<double> pose_reduced_chi2;  // per pose
  std::vector<double> pose_mahalanobis, pose_mahalanobis_independent;  // eᵀΣ⁻¹e / 6 per pose
  // Mean product of two poses' whitened independent errors (the calibration's error removed),
  // per chain: 0 when the poses' errors are independent; poses of the same orientation θ, others.
  std::vector<double> pose_correlation_same_theta, pose_correlation_other_theta;
  Samples z_before, z_after, abs_error;              // identified parameter: error/σ, |error| (display units)
  Samples z_corrected;                               // the same refitted with the calibration error removed, σ before
  Samples z_corrected_unscaled;                      // the same against √diag (AᵀA)⁻¹ (no misfit scaling)
  Samples sigma_fit, sigma_alignment, sigma_shared;  // σ components (display units)
  std::map<std::string, std::string> unit;           // display unit per parameter
  std::vector<std::string> names;                    // identified parameters in order
  std::vector<std::string> method;
  std::vector<double> chi2_dof, ident_chi2_before, ident_chi2_after, value_shift;
  PredictionScores prediction;  // what `mire fkm` predicts from the true joints
  int chains = 0, failed = 0;
};

// A camera placement per chain: the demo's (datasets::defaultBaseTCamera) turned about the
// base's z axis by any angle, tilted by up to 2° and moved by up to 20 mm, so that the target's
// features fall on other pixels and the detector's systematic error differs between chains.
Eigen::Isometry3d drawnPlacement(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double degree = support::kRadiansPerDegree;
  Eigen::Isometry3d base_T_camera = datasets::defaultBaseTCamera();
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(180.0 * degree * unit(rng), Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(2.0 * degree * unit(rng), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(2.0 * degree * unit(rng), Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  base_T_camera.linear() = turn * base_T_camera.linear();
  base_T_camera.translation() += 0.02 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  return base_T_camera;
}

datasets::MechanismImageCampaignSpec chainSpec(int chain, int images_per_pose, bool draw_placement) {
  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference("h4");
  spec.seed = 19000 + static_cast<std::uint64_t>(chain);  // new images and encoder noise
  spec.robot_seed = chain % 2 == 0 ? 2004 : 5000 + static_cast<std::uint64_t>(chain);
  spec.unmodelled_defects = false;
  spec.images_per_pose = images_per_pose;
  spec.line_points = 3;  // the lines (V3) are not used here
  if (draw_placement) spec.base_T_camera = drawnPlacement(spec.seed);
  return spec;
}

// Stage 1, as `mire demo`: detection in every calibration image, bundle adjustment (OpenCV5).
calibration::Camera calibrate(const datasets::MechanismImageCampaign& campaign, const metrology::Target& target,
                              Study& study) {
  const pipeline::CalibrationFolder folder = pipeline::detectCalibrationFolder(target, campaign.calibration_images(), 0);
  calibration::CalibrationOptions options;
  options.model = calibration::DistortionModel::OpenCV5;
  const calibration::Camera camera =
      calibration::calibrateCamera(target.points(), folder.views, folder.width, folder.height, options).camera;
  const auto names = camera.parameterNames();
  const auto sigmas = camera.sigmas();
  Eigen::VectorXd error(static_cast<Eigen::Index>(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    error[static_cast<Eigen::Index>(i)] = camera.params[i] - campaign.camera.params[i];
    study.calibration_z[names[i]].push_back(error[static_cast<Eigen::Index>(i)] / sigmas[i]);
  }
  study.calibration_chi2.push_back(mahalanobis(error, camera.covariance));
  return camera;
}

// Mean w_j·w_k / 6 over pose pairs of the same orientation θ and of different ones.
void scoreCorrelation(const std::vector<Eigen::Matrix<double, 6, 1>>& whitened, const std::vector<double>& theta,
                      Study& study) {
  double same = 0.0, other = 0.0;
  int same_pairs = 0, other_pairs = 0;
  for (std::size_t j = 0; j < whitened.size(); ++j)
    for (std::size_t k = j + 1; k < whitened.size(); ++k) {
      const double product = whitened[j].dot(whitened[k]) / 6.0;
      const bool same_theta = std::abs(theta[j] - theta[k]) < 1e-6;
      (same_theta ? same : other) += product;
      ++(same_theta ? same_pairs : other_pairs);
    }
  study.pose_correlation_same_theta.push_back(same / std::max(1, same_pairs));
  study.pose_correlation_other_theta.push_back(other / std::max(1, other_pairs));
}

// Stage 2, as `mire demo`/`mire measure`: one pose per folder, poses.csv + covariance + shared
// term; each pose scored against the true cTm, and with the calibration's own error removed
// (e − D_j Δk, the true Δk known here) against the independent part of its covariance.
void measure(const datasets::MechanismImageCampaign& campaign, const calibration::Camera& camera,
             const metrology::Target& target, const Eigen::VectorXd& camera_error, const fs::path& poses_csv,
             Study& study) {
  metrology::MeasurementOptions options;
  options.integrity.split = metrology::SplitPolicy::KeepLargest;
  static const char* const components[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  std::vector<metrology::MeasuredPose> measured;
  std::vector<Eigen::Matrix<double, 6, 1>> whitened;
  std::vector<double> theta;
  const auto measurements = pipeline::measurePoseFolders(camera, target, campaign.pose_images(), options, 0);
  for (const auto& pose : measurements) {
    const auto& m = pose.measurement;
    if (!m.ok) continue;
    measured.emplace_back(pose.pose_id, m.features.images_used, pose.images_total, m.estimate);
    const Eigen::Isometry3d truth = campaign.trueCameraTMarker(pose.pose_id);
    Eigen::Matrix<double, 6, 1> error;
    error << m.estimate.translation - truth.translation(),
        m.estimate.rotation_vector - metrology::rotationVector(truth.linear());
    const Eigen::Matrix<double, 6, 1> independent = error - m.estimate.intrinsics_sensitivity * camera_error;
    for (int k = 0; k < 6; ++k) {
      study.pose_z[components[k]].push_back(error[k] / std::sqrt(m.estimate.covariance(k, k)));
      study.pose_z_independent[components[k]].push_back(independent[k] / std::sqrt(m.estimate.covariance_noise(k, k)));
    }
    study.pose_reduced_chi2.push_back(m.estimate.reduced_chi2);
    study.pose_mahalanobis.push_back(mahalanobis(error, m.estimate.covariance) / 6.0);
    study.pose_mahalanobis_independent.push_back(mahalanobis(independent, m.estimate.covariance_noise) / 6.0);
    whitened.push_back(m.estimate.covariance_noise.llt().matrixL().solve(independent));
    const auto index = std::find(campaign.pose_ids.begin(), campaign.pose_ids.end(), pose.pose_id);
    theta.push_back(campaign.commanded[static_cast<std::size_t>(index - campaign.pose_ids.begin())][3]);
  }
  scoreCorrelation(whitened, theta, study);
  metrology::writePosesCsv(poses_csv, measured);
  metrology::writePosesCovarianceCsv(mire::support::covarianceSidePath(poses_csv), measured);
  metrology::writeSharedTermCsv(mire::support::sharedTermSidePath(poses_csv), camera, measured,
                                pipeline::sharedDetectorBias(camera, target, measurements, options));
}

// The simulator's truth in the identified parameters' order (z_BC in the model's z_ME gauge,
// paper eq. 24), as `mire demo` scores it.
Eigen::VectorXd truthOf(const mech::IdentificationResult& result, const datasets::MechanismImageCampaign& campaign) {
  const auto& p = result.model.parameters;
  Eigen::VectorXd truth(static_cast<Eigen::Index>(p.size()));
  truth << campaign.robot.geometry.values(), result.model.external.valuesFrom(campaign.bTc, campaign.mTe);
  truth[static_cast<Eigen::Index>(p.index("z_BC"))] +=
      truth[static_cast<Eigen::Index>(p.index("z_ME"))] - p.value("z_ME");
  return truth;
}

// Stage 3, as `mire identify` (variant D = model 12): without the shared term ("before"), then
// with it propagated by refits of the whole estimator ("after").
// Diagnostic (truth known here): the refit on poses with the calibration's own error removed,
// cTm_j − D_j Δk, is scored against the σ without the shared term.
void identify(const datasets::MechanismImageCampaign& campaign, const fs::path& poses_csv,
              const Eigen::VectorXd& camera_error, Study& study) {
  const pipeline::ModelChoice choice = pipeline::chooseModel("h4-12", "D");
  const pipeline::PoseSet set = pipeline::readPoseSet(pipeline::PoseSetFiles::beside(poses_csv, campaign.joints_file()),
                                                      mech::makeRegisteredModel("h4-12").mechanism->jointColumnNames());
  const std::vector<mech::PoseObservation>& poses = set.observations.poses;
  if (!set.shared) throw std::runtime_error(poses_csv.string() + ": no shared-term side file");
  const mech::SharedPoseTerm& shared = *set.shared;
  const pipeline::InitialModel initial = pipeline::initialModel(choice, poses);
  const mech::IdentificationResult before = pipeline::fit(choice, initial, poses, {});
  mech::IdentificationResult after = before;
  pipeline::addSharedTerm(choice, initial, poses, shared, after);
  if (static_cast<Eigen::Index>(shared.names.size()) < camera_error.size())
    throw std::runtime_error("the shared-term file does not hold every camera parameter");
  std::vector<mech::PoseObservation> corrected_poses = poses;
  for (mech::PoseObservation& pose : corrected_poses)
    pose.cTm -= shared.sensitivity.at(pose.id).leftCols(camera_error.size()) * camera_error;
  const mech::IdentificationResult corrected =
      pipeline::fit(choice, pipeline::initialModel(choice, corrected_poses), corrected_poses, {});
  const Eigen::VectorXd truth = truthOf(before, campaign);
  const auto& p = before.model.parameters;
  const auto free = static_cast<Eigen::Index>(before.free_names.size());
  // An angle may come out a turn away from the truth (ψ_BC near ±180° with a drawn placement).
  const auto errorOf = [&](double value, std::size_t i) {
    const double e = value - truth[static_cast<Eigen::Index>(i)];
    return p[i].unit == mech::Unit::Radian ? std::remainder(e, 2.0 * support::kPi) : e;
  };
  Eigen::VectorXd error(free);
  double shift = 0.0;
  for (Eigen::Index f = 0; f < free; ++f) {
    const std::string& name = before.free_names[static_cast<std::size_t>(f)];
    const std::size_t i = p.index(name);
    error[f] = errorOf(p[i].value, i);
    shift = std::max(shift, std::abs(after.model.parameters[i].value - p[i].value));
    study.z_before[name].push_back(error[f] / before.sigma[static_cast<Eigen::Index>(i)]);
    study.z_after[name].push_back(error[f] / after.sigma[static_cast<Eigen::Index>(i)]);
    const double corrected_error = errorOf(corrected.model.parameters[i].value, i);
    const double unscaled2 = before.information_inverse(f, f);
    study.z_corrected[name].push_back(corrected_error / before.sigma[static_cast<Eigen::Index>(i)]);
    study.z_corrected_unscaled[name].push_back(corrected_error / std::sqrt(unscaled2));
    study.abs_error[name].push_back(std::abs(mech::toDisplay(p[i].unit, error[f])));
    study.unit[name] = mech::displayUnitName(p[i].unit);
    const double alignment2 = after.termCovariance(mech::CovarianceTerm::kAlignment)(f, f);
    const double fit2 = after.covariance(f, f) - alignment2 - after.termCovariance(mech::CovarianceTerm::kShared)(f, f);
    study.sigma_fit[name].push_back(mech::toDisplay(p[i].unit, std::sqrt(std::max(0.0, fit2))));
    study.sigma_alignment[name].push_back(mech::toDisplay(p[i].unit, std::sqrt(std::max(0.0, alignment2))));
    study.sigma_shared[name].push_back(
        mech::toDisplay(p[i].unit, std::sqrt(after.termCovariance(mech::CovarianceTerm::kShared)(f, f))));
  }
  study.names = before.free_names;
  study.chi2_dof.push_back(before.chi2 / std::max(1, before.dof));
  study.method.push_back(before.covarianceMethod());
  study.ident_chi2_before.push_back(mahalanobis(error, before.covariance) / static_cast<double>(free));
  study.ident_chi2_after.push_back(mahalanobis(error, after.covariance) / static_cast<double>(free));
  study.value_shift.push_back(shift);
  Eigen::Index worst = 0;
  for (Eigen::Index f = 1; f < free; ++f)
    if (std::abs(study.z_after[study.names[static_cast<std::size_t>(f)]].back()) >
        std::abs(study.z_after[study.names[static_cast<std::size_t>(worst)]].back()))
      worst = f;
  std::vector<Eigen::VectorXd> joints;
  std::vector<Eigen::Isometry3d> cTm;
  for (std::size_t i = 0; i < campaign.commanded.size(); ++i) {
    const Eigen::VectorXd q = campaign.robot.joints(campaign.commanded[i]);
    if (q.size() == 0) throw std::runtime_error("the true robot does not reach a protocol pose");
    joints.push_back(q);
    cTm.push_back(campaign.trueCameraTMarker(campaign.pose_ids[i]));
  }
  scorePredictions(mech::predictionModelFrom("h4-12", after), joints, cTm, study.prediction);
  std::printf("  largest |error/sigma| with the shared term: %s %.2f\n",
              study.names[static_cast<std::size_t>(worst)].c_str(),
              study.z_after[study.names[static_cast<std::size_t>(worst)]].back());
}

void runChain(int chain, int images_per_pose, bool draw_placement, const fs::path& work, Study& study) {
  const datasets::MechanismImageCampaignSpec spec = chainSpec(chain, images_per_pose, draw_placement);
  const fs::path dir = work / ("chain" + std::to_string(chain));
  const double start = processCpuSeconds();
  const auto wall = std::chrono::steady_clock::now();
  const datasets::MechanismImageCampaign campaign = datasets::generateMechanismImageCampaign(spec, dir / "campaign");
  const metrology::Target target = metrology::Target::fromFile(campaign.target_file());
  const double simulated = processCpuSeconds();
  const calibration::Camera camera = calibrate(campaign, target, study);
  Eigen::VectorXd camera_error(static_cast<Eigen::Index>(camera.params.size()));
  for (std::size_t i = 0; i < camera.params.size(); ++i)
    camera_error[static_cast<Eigen::Index>(i)] = camera.params[i] - campaign.camera.params[i];
  measure(campaign, camera, target, camera_error, dir / "poses.csv", study);
  const double measured = processCpuSeconds();
  identify(campaign, dir / "poses.csv", camera_error, study);
  const double done = processCpuSeconds();
  ++study.chains;
  std::printf(
      "chain %2d (robot seed %llu): CPU s simulate %.1f, calibrate+measure %.1f, identify %.1f; wall %.1f s; "
      "chi2/dof %.2f (%s), identification Mahalanobis/p before %.2f after %.2f\n",
      chain, static_cast<unsigned long long>(*spec.robot_seed), simulated - start, measured - simulated,
      done - measured, std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count(),
      study.chi2_dof.back(), study.method.back().c_str(), study.ident_chi2_before.back(), study.ident_chi2_after.back());
  std::fflush(stdout);
  fs::remove_all(dir / "campaign");  // 0.6 GB of images per chain
}

void printStages(const Study& s) {
  std::printf("\nStage 1, calibration (camera truth known): error/sigma per camera parameter over %d chains\n", s.chains);
  std::printf("  %-6s %8s %8s\n", "param", "std", "RMS");
  for (const auto& [name, z] : s.calibration_z) std::printf("  %-6s %8.3f %8.3f\n", name.c_str(), stddev(z), rms(z));
  std::printf("  Mahalanobis chi2 of the camera error / n: mean %.2f (1 if the covariance is right)\n",
              mean(s.calibration_chi2) / static_cast<double>(s.calibration_z.size()));
  std::printf(
      "\nStage 2, poses (%zu poses): RMS(error/sigma) per component; full sigma | calibration error removed, "
      "independent sigma\n",
      s.pose_reduced_chi2.size());
  for (const char* c : {"tx", "ty", "tz", "rx", "ry", "rz"})
    std::printf("  %-3s %8.3f | %8.3f\n", c, rms(s.pose_z.at(c)), rms(s.pose_z_independent.at(c)));
  std::printf("  pose fit reduced chi2: median %.2f\n", median(s.pose_reduced_chi2));
  std::printf("  6-D Mahalanobis / 6 per pose: mean %.3f full sigma, %.3f calibration error removed (1 if honest)\n",
              mean(s.pose_mahalanobis), mean(s.pose_mahalanobis_independent));
  std::printf(
      "  correlation of two poses' whitened independent errors (0 if independent): same theta %.4f +- %.4f, "
      "other theta %.4f +- %.4f (mean +- sd over chains)\n",
      mean(s.pose_correlation_same_theta), stddev(s.pose_correlation_same_theta), mean(s.pose_correlation_other_theta),
      stddev(s.pose_correlation_other_theta));
}

void printIdentification(const Study& s) {
  std::printf("\nStage 3, identification model 12 (variant D): error/sigma over %d chains (%d failed)\n", s.chains,
              s.failed);
  std::printf("  %-8s %-4s | %-17s | %-17s | %-17s | %s\n", "param", "unit", "without shared", "with shared",
              "no calib: sc, unsc", "median |error|");
  std::printf("  %-8s %-4s | %8s %8s | %8s %8s | %8s %8s |\n", "", "", "std", "RMS", "std", "RMS", "RMS", "RMS");
  const auto inside = [](const std::vector<double>& z) { return stddev(z) >= 0.8 && stddev(z) <= 1.25 ? 1 : 0; };
  int inside_before = 0, inside_after = 0;
  for (const auto& name : s.names) {
    const auto& b = s.z_before.at(name);
    const auto& a = s.z_after.at(name);
    inside_before += inside(b);
    inside_after += inside(a);
    std::printf("  %-8s %-4s | %8.3f %8.3f | %8.3f %8.3f | %8.3f %8.3f | %.4g\n", name.c_str(), s.unit.at(name).c_str(),
                stddev(b), rms(b), stddev(a), rms(a), rms(s.z_corrected.at(name)), rms(s.z_corrected_unscaled.at(name)),
                median(s.abs_error.at(name)));
  }
  std::printf(
      "\n  median sigma components with the shared term (display units): fit | axis alignment | "
      "shared; RMS error\n");
  for (const auto& name : s.names) {
    std::vector<double> errors;
    for (std::size_t c = 0; c < s.z_after.at(name).size(); ++c) errors.push_back(s.abs_error.at(name)[c]);
    std::printf("  %-8s %10.4g %10.4g %10.4g | RMS |error| %10.4g\n", name.c_str(), median(s.sigma_fit.at(name)),
                median(s.sigma_alignment.at(name)), median(s.sigma_shared.at(name)), rms(errors));
  }
  std::printf(
      "  no calib: refitted on poses with the true calibration error removed (cTm - D dk), against the sigma "
      "without the shared term: as printed (sc) and (A^T A)^-1 without the misfit scaling (unsc)\n");
  std::printf("  std(error/sigma) in [0.8, 1.25]: %d of %zu without the shared term, %d with it\n", inside_before,
              s.names.size(), inside_after);
  std::printf("  identification Mahalanobis chi2 / p: mean %.2f without, %.2f with (1 if honest)\n",
              mean(s.ident_chi2_before), mean(s.ident_chi2_after));
  printPredictionScores(s.prediction);
  std::printf("  fit chi2/dof: median %.2f; largest value change from adding the shared term: %.3g (SI)\n",
              median(s.chi2_dof), *std::max_element(s.value_shift.begin(), s.value_shift.end()));
}

}  // namespace

int runH4ChainStudy(const ChainRun& run) {
  Study study;
  std::printf(
      "%d chains, %d images per pose, exactly-model-12 H4 (demo error sizes, no unmodelled defects), "
      "robot seed 2004 on even chains, a new one on odd chains; camera placement %s; work dir %s\n",
      run.chains, run.images_per_pose, run.draw_placement ? "drawn per chain" : "the demo's", run.work.string().c_str());
  if (runChains(run, study,
                [&](int chain) { runChain(chain, run.images_per_pose, run.draw_placement, run.work, study); }) < 2)
    return 1;
  printStages(study);
  printIdentification(study);
  std::printf("\nprocess CPU %.0f s\n", processCpuSeconds());
  return 0;
}

}  // namespace mire::bench
