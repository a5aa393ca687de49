// bench_chain's study of the Delta and the Gough–Stewart (chain_study.hpp;
// doc/studies/2026-11-24-chain-study-delta-gough-stewart.md). Each chain renders
// a new campaign of `mire demo --mechanism` (new calibration images, pose images and encoder
// noise) of a true robot that is exactly of the identified model (no plate tilt; unit encoder
// gains and no eccentricity), seen by the demo's camera placed anew (a few cm, a few degrees),
// then runs the demo's pipeline — calibrateStage, measureStage (poses.csv with the shared-term
// side file), the gauged initial model, the fit without and with the shared calibration term —
// and scores every stage against the simulator's truth: calibration error/σ, pose error/σ, and
// every free parameter's error/σ against the truth in the identification's gauge. Diagnostics
// (the truth known): the fit's term from the true pose errors, and from the pose errors the
// detector's true feature errors cause, split into a per-feature constant, an image field and
// the rest (doc/studies/2026-11-25-delta-gauge-120-chains.md).
// delta: legs that differ, model `delta-legs` (the mounting values are the gauge on most chains);
// delta-same-legs: identical legs, model `delta` (6 free mounting values); gough-stewart: model
// `gough-stewart`. The shared term is computed twice: as `mire identify` does (its refits
// re-initialise the gauge parameters) and with the refits holding the main fit's gauge
// (doc/uncertainty.md explains the difference).
// Even chains: the demo's robot (robot seed 2004); odd chains: a different random robot each.
#include "chain_prediction.hpp"
#include "chain_statistics.hpp"
#include "chain_study.hpp"

#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/target.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/pipeline/scored_stages.hpp"
#include "mire/support/constants.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace mire::bench {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

constexpr double kDegree = support::kRadiansPerDegree;
// The camera placement's perturbation per chain: U(−1, 1) × 3 cm along each base axis and
// × 3° about each camera axis (smaller when a target feature would leave the image).
constexpr double kShiftM = 0.03, kTurnRad = 3.0 * kDegree;

// Everything scored over the chains.
struct Study {
  std::string mechanism, model;
  Samples calibration_z;                  // camera parameter: error/σ
  std::vector<double> calibration_chi2;   // Mahalanobis of the camera error / n, per chain
  Samples pose_z, pose_z_independent;     // component: error/σ (full σ), (error − D Δk)/σ_independent
  std::vector<double> pose_whitened_all;  // per chain: the demo's whitened RMS over all components
  Samples z_before, z_after, abs_error;   // free parameter: error/σ, |error| (display units)
  Samples z_held;                         // error/σ with the shared term, refits in the main fit's gauge
  // Refitted with the calibration error removed (Δk known here): against the σ without the shared
  // term and against the fit's own term of the σ with it; the rest of the error (the calibration's
  // part) against the shared term (gauge held).
  Samples z_corrected, z_corrected_fit, z_calibration_part;
  Samples sigma_fit, sigma_alignment, sigma_shared;  // σ components with the shared term (display)
  Samples sigma_shared_held;                         // the shared term, refits in the main fit's gauge
  // The fit's term from the true independent pose errors over the modelled one (variance ratios):
  // per pose (block-diagonal) and realized (all poses together, cross-pose correlation included).
  Samples oracle_block_ratio, oracle_realized_ratio;
  // The same realized term without the pose errors' scale error, u_j,t ≈ (s₀ + s₁ (z_j − z̄)/z̄) t_j
  // (a target-scale-like error every pose shares, constant and growing with the distance), and
  // s₀, s₁ per chain.
  Samples oracle_unscaled_ratio;
  std::array<Samples, 4> oracle_detector_ratio;
  std::vector<double> oracle_scale, oracle_scale_slope;
  std::map<std::string, std::string> unit;  // display unit per parameter
  std::set<std::string> mounting;           // the free mounting parameters
  std::vector<std::string> names;           // free parameters, in first-seen order
  std::vector<std::string> method_before, method_after;
  std::vector<double> chi2_dof, ident_chi2_before, ident_chi2_after, ident_chi2_held;
  PredictionScores prediction;  // what `mire fkm` predicts from the true joints
  std::vector<double> cpu_simulate, cpu_measure, cpu_identify, wall, shift_mm, turn_deg;
  int chains = 0, failed = 0;
};

datasets::MechanismImageCampaignSpec chainSpec(const std::string& study, int chain, int images_per_pose) {
  const bool same_legs = study == "delta-same-legs";
  datasets::MechanismImageCampaignSpec spec =
      datasets::MechanismImageCampaignSpec::reference(same_legs ? "delta" : study);
  spec.delta_legs_differ = !same_legs;
  spec.seed = 19000 + static_cast<std::uint64_t>(chain);  // new images and encoder noise
  spec.robot_seed = chain % 2 == 0 ? 2004 : 5000 + static_cast<std::uint64_t>(chain);
  spec.unmodelled_defects = false;
  spec.images_per_pose = images_per_pose;
  spec.line_points = 3;  // the lines (V3) are not used here
  return spec;
}

// The demo's camera placement moved by `scale` × (3 cm, 3°) in a direction drawn from `seed`.
Eigen::Isometry3d perturbedPlacement(const std::string& mechanism, std::uint64_t seed, double scale) {
  std::mt19937_64 rng(seed ^ 0x5bd1e995ULL);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d placement = datasets::mechanismBaseTCamera(mechanism);
  const Eigen::Vector3d shift(u(rng), u(rng), u(rng)), turn(u(rng), u(rng), u(rng));
  placement.translation() += scale * kShiftM * shift;
  placement.linear() = placement.linear() * (Eigen::AngleAxisd(scale * kTurnRad * turn.x(), Eigen::Vector3d::UnitX()) *
                                             Eigen::AngleAxisd(scale * kTurnRad * turn.y(), Eigen::Vector3d::UnitY()) *
                                             Eigen::AngleAxisd(scale * kTurnRad * turn.z(), Eigen::Vector3d::UnitZ()))
                                                .toRotationMatrix();
  return placement;
}

// The campaign with the chain's camera placement. When the generator reports a target feature
// outside the image, another direction is drawn, and every second attempt the size shrinks by √2.
datasets::MechanismImageCampaign generateCampaign(datasets::MechanismImageCampaignSpec spec, const fs::path& dir,
                                                  Study& study) {
  const Eigen::Isometry3d demo = datasets::mechanismBaseTCamera(spec.mechanism);
  for (int attempt = 0;; ++attempt) {
    const double scale = std::pow(0.5, 0.5 * (attempt / 2));
    spec.base_T_camera = perturbedPlacement(spec.mechanism, spec.seed + 1000003ULL * attempt, scale);
    try {
      datasets::MechanismImageCampaign campaign = datasets::generateMechanismImageCampaign(spec, dir);
      study.shift_mm.push_back(1e3 * (spec.base_T_camera->translation() - demo.translation()).norm());
      study.turn_deg.push_back(Eigen::AngleAxisd(demo.linear().transpose() * spec.base_T_camera->linear()).angle() /
                               kDegree);
      return campaign;
    } catch (const std::runtime_error& e) {
      if (attempt >= 9 || std::string(e.what()).find("leaves the image") == std::string::npos) throw;
      std::printf("  camera placement attempt %d (size x%.2f): %s\n", attempt + 1, scale, e.what());
    }
  }
}

// Stage 1 (calibrateStage's summary against the true camera): error/σ per parameter and the
// Mahalanobis χ²/n of the whole camera error; returns the error Δk.
Eigen::VectorXd scoreCalibration(const pipeline::CalibrationScore& calibration, Study& study) {
  Eigen::VectorXd error(static_cast<Eigen::Index>(calibration.names.size()));
  for (std::size_t i = 0; i < calibration.names.size(); ++i) {
    error[static_cast<Eigen::Index>(i)] = calibration.estimate[i] - calibration.truth[i];
    study.calibration_z[calibration.names[i]].push_back(error[static_cast<Eigen::Index>(i)] / calibration.sigma[i]);
  }
  study.calibration_chi2.push_back(mahalanobis(error, calibration.covariance) / static_cast<double>(error.size()));
  return error;
}

// ∂cTm/∂k of pose `id` over the camera's n parameters (the shared-term file's leading columns;
// the detector's modes follow them).
Eigen::MatrixXd cameraSensitivity(const pipeline::PoseSet& data, const std::string& id, Eigen::Index n) {
  return data.shared->sensitivity.at(id).leftCols(n);
}

// Stage 2, read back from poses.csv and its side files as identify reads them: each pose against
// the true cTm with its full σ, and with the calibration's own error removed (e − D_j Δk, Δk
// known here) against the independent part Σ_j − D_j Σ_k D_jᵀ.
void scorePoses(const datasets::MechanismImageCampaign& campaign, const pipeline::PoseSet& data,
                const std::vector<std::string>& camera_names, const Eigen::VectorXd& camera_error, Study& study) {
  if (!data.shared || data.shared->names.size() < camera_names.size() ||
      !std::equal(camera_names.begin(), camera_names.end(), data.shared->names.begin()))
    throw std::runtime_error("the shared-term file does not hold the calibrated camera's parameters");
  static const char* const components[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  for (const mech::PoseObservation& pose : data.observations.poses) {
    const mech::PoseVector error = pose.cTm - mech::toPoseVector(campaign.trueCameraTMarker(pose.id));
    const Eigen::MatrixXd D = cameraSensitivity(data, pose.id, camera_error.size());
    const mech::PoseVector independent = error - D * camera_error;
    const auto n = camera_error.size();
    const Eigen::MatrixXd independent_covariance =
        *pose.covariance - D * data.shared->covariance.topLeftCorner(n, n) * D.transpose();
    for (int k = 0; k < 6; ++k) {
      study.pose_z[components[k]].push_back(error[k] / std::sqrt((*pose.covariance)(k, k)));
      study.pose_z_independent[components[k]].push_back(independent[k] / std::sqrt(independent_covariance(k, k)));
    }
  }
}

// Stage 3's fits, all from the same gauged initial model: without the shared term (as `mire
// identify --independent-poses`), with it (as `mire demo --mechanism`), and — a diagnostic, the
// truth known here — on the poses with the calibration's own error removed.
struct ChainFits {
  mech::IdentificationResult before, after, held, with_shared_unaligned, corrected;
  mech::ParameterSet truth;
  Eigen::VectorXd oracle_block, oracle_realized;  // variances, free parameters
  Eigen::VectorXd oracle_unscaled;                // realized, the scale error removed
  double oracle_scale = 0.0, oracle_scale_slope = 0.0;
  // Realized, from the pose errors the detector's true feature errors cause (true camera): all of
  // them, their per-feature constant part, their smooth image field, the rest.
  std::array<Eigen::VectorXd, 4> oracle_detector;
};

// Pose errors the detector's true feature errors (averaged features − true projection) cause,
// split into parts: [0] all, [1] the per-feature mean over the poses, [2] a quadratic field over
// the image fitted to all errors, [3] the rest.
std::map<std::string, std::array<mech::PoseVector, 4>> detectorPoseErrors(
    const datasets::MechanismImageCampaign& campaign, const metrology::Target& target,
    const std::vector<pipeline::PoseFolderMeasurement>& measured) {
  const calibration::Camera& camera = campaign.camera;
  const auto& points = target.points();
  struct Pose {
    std::string id;
    const metrology::AveragedFeatures* f;
    Eigen::Isometry3d T;
    std::vector<Eigen::Vector2d> error, at;
  };
  std::vector<Pose> poses;
  std::map<int, Eigen::Vector2d> sum;
  std::map<int, int> count;
  for (const pipeline::PoseFolderMeasurement& pose : measured) {
    if (!pose.measurement.ok) continue;
    const metrology::AveragedFeatures& f = pose.measurement.features;
    Pose p{pose.pose_id, &f, campaign.trueCameraTMarker(pose.pose_id), {}, {}};
    for (std::size_t i = 0; i < f.size(); ++i) {
      Eigen::Vector2d projected;
      camera.project(p.T * points[static_cast<std::size_t>(f.ids[i])], &projected);
      p.error.push_back(f.pixels[i] - projected);
      p.at.push_back(
          Eigen::Vector2d((projected.x() - camera.cx()) / camera.fx(), (projected.y() - camera.cy()) / camera.fy()));
      sum.try_emplace(f.ids[i], Eigen::Vector2d::Zero()).first->second += p.error.back();
      ++count[f.ids[i]];
    }
    poses.push_back(std::move(p));
  }
  // Quadratic field: 6 terms per axis, least squares over every feature of every pose.
  const auto basis = [](const Eigen::Vector2d& x) {
    Eigen::Matrix<double, 6, 1> b;
    b << 1.0, x.x(), x.y(), x.x() * x.x(), x.x() * x.y(), x.y() * x.y();
    return b;
  };
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 2> rhs = Eigen::Matrix<double, 6, 2>::Zero();
  for (const Pose& p : poses)
    for (std::size_t i = 0; i < p.error.size(); ++i) {
      const auto b = basis(p.at[i]);
      normal += b * b.transpose();
      rhs += b * p.error[i].transpose();
    }
  const Eigen::Matrix<double, 6, 2> field = normal.ldlt().solve(rhs);
  std::map<std::string, std::array<mech::PoseVector, 4>> out;
  for (const Pose& p : poses) {
    const Eigen::MatrixXd S = metrology::featureSensitivity(camera, points, *p.f, p.T);
    const auto n = static_cast<Eigen::Index>(p.error.size());
    Eigen::VectorXd parts[4] = {Eigen::VectorXd(2 * n), Eigen::VectorXd(2 * n), Eigen::VectorXd(2 * n),
                                Eigen::VectorXd(2 * n)};
    for (Eigen::Index i = 0; i < n; ++i) {
      const int id = p.f->ids[static_cast<std::size_t>(i)];
      const Eigen::Vector2d e = p.error[static_cast<std::size_t>(i)];
      const Eigen::Vector2d constant = sum[id] / count[id];
      const Eigen::Vector2d smooth = field.transpose() * basis(p.at[static_cast<std::size_t>(i)]);
      parts[0].segment<2>(2 * i) = e;
      parts[1].segment<2>(2 * i) = constant;
      parts[2].segment<2>(2 * i) = smooth;
      parts[3].segment<2>(2 * i) = e - constant - smooth;
    }
    std::array<mech::PoseVector, 4> pose_parts;
    for (int k = 0; k < 4; ++k) pose_parts[static_cast<std::size_t>(k)] = S * parts[k];
    out[p.id] = pose_parts;
  }
  return out;
}

// Diagnostic, the truth known: the fit's term from the true independent pose errors
// u_j = e_j − D_j Δk, through the linearized estimator H⁻¹ Σ_j A_jᵀ W_j J_p,j u_j: per pose
// (Σ_j of the score's outer product, what per-pose covariances can describe) and realized (the
// square of the sum, whose mean over chains holds the cross-pose correlation too).
void oracleFitTerm(const datasets::MechanismImageCampaign& campaign, const pipeline::PoseSet& data,
                   const Eigen::VectorXd& camera_error, const metrology::Target& target,
                   const std::vector<pipeline::PoseFolderMeasurement>& measured, ChainFits& fits) {
  const auto detector_errors = detectorPoseErrors(campaign, target, measured);
  std::array<Eigen::VectorXd, 4> detector_total;
  const mech::IdentificationResult& r = fits.with_shared_unaligned;
  const int J = r.model.mechanism->jointCount();
  const Eigen::MatrixXd J_rad = mech::identificationJacobian(r.model, data.observations.poses);
  const Eigen::VectorXd g = r.model.geometricValues(), e = r.model.externalValues();
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(J_rad.cols(), J_rad.cols());
  Eigen::VectorXd total = Eigen::VectorXd::Zero(J_rad.cols()), scale_total = total;
  for (auto& t : detector_total) t = total;
  // The true independent pose errors u_j, and the scale error u_t ≈ (s₀ + s₁ (z − z̄)/z̄) t,
  // constant and growing with the distance, fitted to them: X_j [s₀ s₁]ᵀ.
  std::vector<mech::PoseVector> errors;
  double z_mean = 0.0;
  for (const mech::PoseObservation& pose : data.observations.poses) {
    errors.push_back(pose.cTm - mech::toPoseVector(campaign.trueCameraTMarker(pose.id)) -
                     cameraSensitivity(data, pose.id, camera_error.size()) * camera_error);
    z_mean += pose.cTm[2] / static_cast<double>(data.observations.poses.size());
  }
  const auto regressor = [z_mean](const mech::PoseVector& cTm) {
    Eigen::Matrix<double, 3, 2> X;
    X << cTm.head<3>(), cTm.head<3>() * (cTm[2] - z_mean) / z_mean;
    return X;
  };
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (std::size_t j = 0; j < data.observations.poses.size(); ++j) {
    const Eigen::Matrix<double, 3, 2> X = regressor(data.observations.poses[j].cTm);
    normal += X.transpose() * X;
    rhs += X.transpose() * errors[j].head<3>();
  }
  const Eigen::Vector2d scale = normal.ldlt().solve(rhs);
  fits.oracle_scale = scale[0];
  fits.oracle_scale_slope = scale[1];
  for (std::size_t j = 0; j < data.observations.poses.size(); ++j) {
    if (!r.poses.at(j).used) continue;
    const mech::PoseObservation& pose = data.observations.poses[j];
    const Eigen::MatrixXd& W = r.whitening.at(j);
    const Eigen::MatrixXd A_j = W * J_rad.middleRows(static_cast<Eigen::Index>(j) * J, J);
    const Eigen::MatrixXd Jp = r.model.mechanism->jointJacobianWrtPose(r.model.external, g, e, pose.cTm);
    const Eigen::VectorXd score = A_j.transpose() * (W * (Jp * errors[j]));
    meat += score * score.transpose();
    total += score;
    mech::PoseVector scaled = mech::PoseVector::Zero();
    scaled.head<3>() = regressor(pose.cTm) * scale;
    scale_total += A_j.transpose() * (W * (Jp * scaled));
    for (std::size_t k = 0; k < 4; ++k)
      detector_total[k] += A_j.transpose() * (W * (Jp * detector_errors.at(pose.id)[k]));
  }
  const Eigen::MatrixXd& H_inv = r.information_inverse;
  fits.oracle_block = (H_inv * meat * H_inv).diagonal();
  fits.oracle_realized = (H_inv * total).array().square();
  fits.oracle_unscaled = (H_inv * (total - scale_total)).array().square();
  for (std::size_t k = 0; k < 4; ++k) fits.oracle_detector[k] = (H_inv * detector_total[k]).array().square();
}

ChainFits identifyChain(const datasets::MechanismImageCampaign& campaign, const pipeline::PoseSet& data,
                        const std::string& model, const Eigen::VectorXd& camera_error, const metrology::Target& target,
                        const std::vector<pipeline::PoseFolderMeasurement>& measured) {
  const pipeline::ModelChoice choice = pipeline::chooseModel(model, "");
  const std::vector<mech::PoseObservation>& poses = data.observations.poses;
  const pipeline::InitialModel initial = pipeline::initialModel(choice, poses);
  ChainFits fits;
  fits.before = pipeline::fit(choice, initial, poses, std::nullopt);
  fits.after = fits.before;
  fits.held = fits.before;
  if (data.shared) {
    pipeline::IdentifyOptions reinitialised;
    reinitialised.refit_gauge = pipeline::RefitGauge::Reinitialised;
    pipeline::addSharedTerm(choice, initial, poses, *data.shared, fits.after, reinitialised);
    pipeline::addSharedTerm(choice, initial, poses, *data.shared, fits.held);
  }
  fits.with_shared_unaligned = fits.after;  // its σ components, before the target's rows turn
  oracleFitTerm(campaign, data, camera_error, target, measured, fits);
  std::vector<mech::PoseObservation> corrected_poses = data.observations.poses;
  for (mech::PoseObservation& pose : corrected_poses)
    pose.cTm -= cameraSensitivity(data, pose.id, camera_error.size()) * camera_error;
  fits.corrected = pipeline::fit(choice, initial, corrected_poses, std::nullopt);
  mech::alignTranslatingTarget(fits.before, data.observations.poses);  // as the demo, before scoring
  mech::alignTranslatingTarget(fits.after, data.observations.poses);
  mech::alignTranslatingTarget(fits.held, data.observations.poses);
  mech::alignTranslatingTarget(fits.corrected, corrected_poses);
  fits.truth = pipeline::truthInGauge(campaign, initial, poses);
  return fits;
}

// The campaign's true joints and target poses, for chain_prediction.hpp.
void scorePredictions(const datasets::MechanismImageCampaign& campaign, const std::string& model,
                      const mech::IdentificationResult& result, Study& study) {
  const mech::Mechanism& truth = campaign.robot.mechanism();
  std::vector<Eigen::VectorXd> joints;
  std::vector<Eigen::Isometry3d> cTm;
  for (const Eigen::VectorXd& X : campaign.commanded) {
    const Eigen::Isometry3d bTe = truth.poseToTransform(X);
    joints.push_back(truth.inverseKinematics(campaign.robot.geometry.values(), bTe).joints);
    cTm.push_back(campaign.bTc.inverse() * bTe * campaign.mTe.inverse());
  }
  mire::bench::scorePredictions(mech::predictionModelFrom(model, result), joints, cTm, study.prediction);
}

// The fit's own term of the σ² with the shared term (free parameter f): the rest of the
// covariance once the axis-alignment and shared terms are taken out.
double fitVariance(const mech::IdentificationResult& with_shared, Eigen::Index f) {
  const double alignment2 = with_shared.termCovariance(mech::CovarianceTerm::kAlignment)(f, f);
  const double shared2 = with_shared.termCovariance(mech::CovarianceTerm::kShared)(f, f);
  return std::max(0.0, with_shared.covariance(f, f) - alignment2 - shared2);
}

// The σ components of the fit with the shared term (display units): the fit's own term, the
// axis-alignment term, the shared calibration term.
void recordSigmaComponents(const mech::IdentificationResult& with_shared, Study& study) {
  const mech::ParameterSet& p = with_shared.model.parameters;
  for (std::size_t f = 0; f < with_shared.free_names.size(); ++f) {
    const auto e = static_cast<Eigen::Index>(f);
    const std::string& name = with_shared.free_names[f];
    const mech::Unit unit = p[p.index(name)].unit;
    const double alignment2 = with_shared.termCovariance(mech::CovarianceTerm::kAlignment)(e, e);
    const double shared2 = with_shared.termCovariance(mech::CovarianceTerm::kShared)(e, e);
    study.sigma_fit[name].push_back(mech::toDisplay(unit, std::sqrt(fitVariance(with_shared, e))));
    study.sigma_alignment[name].push_back(mech::toDisplay(unit, std::sqrt(alignment2)));
    study.sigma_shared[name].push_back(mech::toDisplay(unit, std::sqrt(shared2)));
  }
}

// Every free parameter's error/σ against the truth in the gauge, before and after the shared
// term; the whole error's Mahalanobis χ²/p.
void scoreIdentification(const ChainFits& fits, Study& study) {
  const mech::IdentificationResult& before = fits.before;
  const mech::ParameterSet& p = before.model.parameters;
  const auto free = static_cast<Eigen::Index>(before.free_names.size());
  Eigen::VectorXd error(free);
  for (Eigen::Index f = 0; f < free; ++f) {
    const std::string& name = before.free_names[static_cast<std::size_t>(f)];
    const std::size_t i = p.index(name);
    const auto e = static_cast<Eigen::Index>(i);
    error[f] = p[i].value - fits.truth.value(name);
    if (study.unit.count(name) == 0) study.names.push_back(name);
    if (static_cast<int>(i) >= before.model.geometricCount()) study.mounting.insert(name);
    study.unit[name] = mech::displayUnitName(p[i].unit);
    study.z_before[name].push_back(error[f] / before.sigma[e]);
    study.z_after[name].push_back(error[f] / fits.after.sigma[e]);
    study.z_held[name].push_back(error[f] / fits.held.sigma[e]);
    study.sigma_shared_held[name].push_back(
        mech::toDisplay(p[i].unit, std::sqrt(fits.held.termCovariance(mech::CovarianceTerm::kShared)(f, f))));
    const double corrected_error = fits.corrected.model.parameters[i].value - fits.truth.value(name);
    study.z_corrected[name].push_back(corrected_error / before.sigma[e]);
    study.z_corrected_fit[name].push_back(corrected_error / std::sqrt(fitVariance(fits.with_shared_unaligned, f)));
    study.z_calibration_part[name].push_back((error[f] - corrected_error) /
                                             std::sqrt(fits.held.termCovariance(mech::CovarianceTerm::kShared)(f, f)));
    study.abs_error[name].push_back(std::abs(mech::toDisplay(p[i].unit, error[f])));
    const double modelled = fitVariance(fits.with_shared_unaligned, f);
    study.oracle_block_ratio[name].push_back(fits.oracle_block[f] / modelled);
    study.oracle_realized_ratio[name].push_back(fits.oracle_realized[f] / modelled);
    study.oracle_unscaled_ratio[name].push_back(fits.oracle_unscaled[f] / modelled);
    for (std::size_t k = 0; k < 4; ++k)
      study.oracle_detector_ratio[k][name].push_back(fits.oracle_detector[k][f] / modelled);
  }
  study.oracle_scale.push_back(fits.oracle_scale);
  study.oracle_scale_slope.push_back(fits.oracle_scale_slope);
  recordSigmaComponents(fits.with_shared_unaligned, study);
  study.chi2_dof.push_back(before.chi2 / std::max(1, before.dof));
  study.method_before.push_back(before.covarianceMethod());
  study.method_after.push_back(fits.after.covarianceMethod());
  study.ident_chi2_before.push_back(mahalanobis(error, before.covariance) / static_cast<double>(free));
  study.ident_chi2_after.push_back(mahalanobis(error, fits.after.covariance) / static_cast<double>(free));
  study.ident_chi2_held.push_back(mahalanobis(error, fits.held.covariance) / static_cast<double>(free));
  Eigen::Index worst = 0;
  std::string free_mounting;
  for (Eigen::Index f = 0; f < free; ++f) {
    const std::string& name = before.free_names[static_cast<std::size_t>(f)];
    if (std::abs(study.z_held[name].back()) >
        std::abs(study.z_held[before.free_names[static_cast<std::size_t>(worst)]].back()))
      worst = f;
    if (study.mounting.count(name)) free_mounting += " " + name;
    if (std::abs(study.z_held[name].back()) > 2.5)
      std::printf("  |error/sigma| > 2.5: %s %.2f\n", name.c_str(), study.z_held[name].back());
  }
  const std::string& name = before.free_names[static_cast<std::size_t>(worst)];
  std::printf("  largest |error/sigma| with the shared term: %s %.2f (error %.4g, display units); free mounting:%s\n",
              name.c_str(), study.z_held[name].back(), mech::toDisplay(p[p.index(name)].unit, error[worst]),
              free_mounting.empty() ? " none" : free_mounting.c_str());
}

void runChain(int chain, int images_per_pose, const fs::path& work, Study& study) {
  const datasets::MechanismImageCampaignSpec spec = chainSpec(study.mechanism, chain, images_per_pose);
  const fs::path dir = work / ("chain" + std::to_string(chain));
  const double start = processCpuSeconds();
  const auto wall = std::chrono::steady_clock::now();
  const datasets::MechanismImageCampaign campaign = generateCampaign(spec, dir / "campaign", study);
  const metrology::Target target = metrology::Target::fromFile(campaign.target_file());
  const double simulated = processCpuSeconds();
  pipeline::CalibrationScore calibration;
  const calibration::Camera camera =
      pipeline::calibrateStage(campaign.calibration_images(), campaign.camera, target, dir, calibration);
  pipeline::MeasurementScore measurement;
  const std::vector<pipeline::PoseFolderMeasurement> measurements = pipeline::measureStage(
      campaign.pose_images(), [&](const std::string& id) { return campaign.trueCameraTMarker(id); }, camera, target,
      dir / "poses.csv", measurement);
  const double measured = processCpuSeconds();
  pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(dir / "poses.csv", campaign.joints_file());
  files.lines = campaign.lines_file();
  const pipeline::PoseSet data = pipeline::readPoseSet(files, campaign.robot.mechanism().jointColumnNames());
  const Eigen::VectorXd camera_error = scoreCalibration(calibration, study);
  scorePoses(campaign, data, calibration.names, camera_error, study);
  study.pose_whitened_all.push_back(measurement.whitened_error_rms_all);
  const ChainFits fits = identifyChain(campaign, data, study.model, camera_error, target, measurements);
  scoreIdentification(fits, study);
  scorePredictions(campaign, study.model, fits.held, study);
  const double done = processCpuSeconds();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  ++study.chains;
  study.cpu_simulate.push_back(simulated - start);
  study.cpu_measure.push_back(measured - simulated);
  study.cpu_identify.push_back(done - measured);
  study.wall.push_back(seconds);
  std::printf(
      "chain %2d (robot seed %llu, camera moved %.1f mm / %.2f deg): CPU s simulate %.1f, calibrate+measure %.1f, "
      "identify %.1f; wall %.1f s; %d of %d poses; detector bias %.4f px of %.4f px (%.1f std, %d modes); chi2/dof "
      "%.2f (%s); Mahalanobis/p without %.2f with %.2f (gauge "
      "held %.2f); largest camera-frame prediction error %.3f mm\n",
      chain, static_cast<unsigned long long>(*spec.robot_seed), study.shift_mm.back(), study.turn_deg.back(),
      simulated - start, measured - simulated, done - measured, seconds, measurement.measured, measurement.total,
      measurement.detector_bias.sigma_px, measurement.detector_bias.feature_error_rms_px,
      measurement.detector_bias.significance, static_cast<int>(measurement.detector_bias.names.size()),
      study.chi2_dof.back(), study.method_before.back().c_str(), study.ident_chi2_before.back(),
      study.ident_chi2_after.back(), study.ident_chi2_held.back(), study.prediction.largest_mm.back());
  std::fflush(stdout);
  fs::remove_all(dir);  // 0.1–0.6 GB of images per chain
}

void printStages(const Study& s) {
  std::printf("\nStage 1, calibration (camera truth known): error/sigma per camera parameter over %d chains\n", s.chains);
  std::printf("  %-6s %8s %8s\n", "param", "std", "RMS");
  for (const auto& [name, z] : s.calibration_z) std::printf("  %-6s %8.3f %8.3f\n", name.c_str(), stddev(z), rms(z));
  std::printf("  Mahalanobis chi2 of the camera error / n: mean %.2f (1 if the covariance is right)\n",
              mean(s.calibration_chi2));
  std::printf(
      "\nStage 2, poses (%zu poses): RMS(error/sigma) per component; full sigma | calibration error removed, "
      "independent sigma\n",
      s.pose_z.at("tx").size());
  for (const char* c : {"tx", "ty", "tz", "rx", "ry", "rz"})
    std::printf("  %-3s %8.3f | %8.3f\n", c, rms(s.pose_z.at(c)), rms(s.pose_z_independent.at(c)));
  std::printf("  whitened with the cross-pose covariance (the demo's score), all components: mean over chains %.3f\n",
              mean(s.pose_whitened_all));
}

// [0.8, 1.25] counts per group (geometric, mounting) for one σ, over the parameters free in at
// least half the chains (the pivoted QR may choose another gauge on some chains).
void printCounts(const Study& s, const Samples& z, const char* label) {
  int total[2] = {0, 0}, inside[2] = {0, 0}, rare = 0;
  for (const auto& name : s.names) {
    if (2 * static_cast<int>(z.at(name).size()) < s.chains) {
      ++rare;
      continue;
    }
    const int group = s.mounting.count(name) ? 1 : 0;
    const double spread = stddev(z.at(name));
    ++total[group];
    inside[group] += spread >= 0.8 && spread <= 1.25;
  }
  std::printf(
      "  std(error/sigma) in [0.8, 1.25], %s: geometric %d of %d, mounting %d of %d (%d free on fewer than half "
      "the chains not counted)\n",
      label, inside[0], total[0], inside[1], total[1], rare);
}

void printIdentificationTable(const Study& s) {
  std::printf("  %-8s %-4s %3s | %-17s | %-17s | %-17s | %-26s | %s\n", "param", "unit", "n", "without shared",
              "shared, re-initialised", "shared, held (cmd)", "no calib: sc, fit; calib", "median |error|");
  std::printf("  %-8s %-4s %3s | %8s %8s | %8s %8s | %8s %8s | %8s %8s %8s |\n", "", "", "", "std", "RMS", "std", "RMS",
              "std", "RMS", "RMS", "RMS", "RMS");
  for (const auto& name : s.names) {
    const auto& b = s.z_before.at(name);
    const auto& a = s.z_after.at(name);
    const auto& h = s.z_held.at(name);
    std::printf("  %-8s %-4s %3zu | %8.3f %8.3f | %8.3f %8.3f | %8.3f %8.3f | %8.3f %8.3f %8.3f | %.4g%s\n",
                name.c_str(), s.unit.at(name).c_str(), b.size(), stddev(b), rms(b), stddev(a), rms(a), stddev(h),
                rms(h), rms(s.z_corrected.at(name)), rms(s.z_corrected_fit.at(name)), rms(s.z_calibration_part.at(name)),
                median(s.abs_error.at(name)), s.mounting.count(name) ? "  (mounting)" : "");
  }
}

void printIdentification(const Study& s) {
  std::printf("\nStage 3, identification %s: error/sigma against the truth in the gauge over %d chains (%d failed)\n",
              s.model.c_str(), s.chains, s.failed);
  printIdentificationTable(s);
  std::printf(
      "\n  median sigma components with the shared term (display units): fit | axis alignment | shared (cmd) | "
      "shared (gauge held); RMS error\n");
  for (const auto& name : s.names)
    std::printf("  %-8s %10.4g %10.4g %10.4g %10.4g | RMS |error| %10.4g\n", name.c_str(), median(s.sigma_fit.at(name)),
                median(s.sigma_alignment.at(name)), median(s.sigma_shared.at(name)),
                median(s.sigma_shared_held.at(name)), rms(s.abs_error.at(name)));
  std::printf(
      "\n  the fit's term from the true independent pose errors over the printed one, sqrt(mean variance ratio): "
      "per pose (block-diagonal) | realized (cross-pose correlation included) | realized without the pose "
      "errors' scale error (s0 + s1 (z - mean z) / mean z) t\n");
  for (const auto& name : s.names)
    std::printf("  %-8s %8.3f | %8.3f | %8.3f\n", name.c_str(), std::sqrt(mean(s.oracle_block_ratio.at(name))),
                std::sqrt(mean(s.oracle_realized_ratio.at(name))), std::sqrt(mean(s.oracle_unscaled_ratio.at(name))));
  std::printf(
      "\n  the fit's term realized from the pose errors the detector's true feature errors cause (true camera), over "
      "the printed one: all | per-feature constant | quadratic image field | rest\n");
  for (const auto& name : s.names)
    std::printf(
        "  %-8s %8.3f | %8.3f | %8.3f | %8.3f\n", name.c_str(), std::sqrt(mean(s.oracle_detector_ratio[0].at(name))),
        std::sqrt(mean(s.oracle_detector_ratio[1].at(name))), std::sqrt(mean(s.oracle_detector_ratio[2].at(name))),
        std::sqrt(mean(s.oracle_detector_ratio[3].at(name))));
  std::printf("  the pose errors' scale error per chain: s0 mean %.3g, RMS %.3g; s1 mean %.3g, RMS %.3g\n",
              mean(s.oracle_scale), rms(s.oracle_scale), mean(s.oracle_scale_slope), rms(s.oracle_scale_slope));
  std::printf(
      "  re-initialised: the refits re-initialise the gauge parameters on the shifted poses; held: the refits "
      "hold them at the main fit's values (`mire identify`, pipeline::RefitGauge)\n"
      "  no calib: refitted on poses with the true calibration error removed (cTm - D dk), against the sigma "
      "without the shared term (sc) and against the fit's own term of the sigma with it (fit); calib: the rest of "
      "the error (the calibration's part) against the shared term, gauge held\n");
  printCounts(s, s.z_before, "without the shared term");
  printCounts(s, s.z_after, "with it, gauge re-initialised");
  printCounts(s, s.z_held, "with it, gauge held");
  std::printf(
      "  identification Mahalanobis chi2 / p: mean %.2f without, %.2f re-initialised, %.2f gauge held (1 if honest); "
      "medians %.2f, %.2f, %.2f\n",
      mean(s.ident_chi2_before), mean(s.ident_chi2_after), mean(s.ident_chi2_held), median(s.ident_chi2_before),
      median(s.ident_chi2_after), median(s.ident_chi2_held));
  printPredictionScores(s.prediction);
  std::printf("  fit chi2/dof: median %.3f; sigma: %s (without), %s (with, re-initialised), first chain\n",
              median(s.chi2_dof), s.method_before.front().c_str(), s.method_after.front().c_str());
}

void printTimes(const Study& s) {
  std::printf(
      "\nper chain, median CPU s: simulate %.1f, calibrate+measure %.1f, identify %.2f; median wall %.1f s; camera "
      "moved median %.1f mm / %.2f deg\nprocess CPU %.0f s\n",
      median(s.cpu_simulate), median(s.cpu_measure), median(s.cpu_identify), median(s.wall), median(s.shift_mm),
      median(s.turn_deg), processCpuSeconds());
}

}  // namespace

int runMechanismChainStudy(const ChainRun& run) {
  Study study;
  study.mechanism = run.mechanism;
  // The true robot's exact model: its family's truth model (the Delta's legs differ: delta-legs),
  // or the `delta` model for identical legs.
  study.model =
      run.mechanism == "delta-same-legs" ? std::string("delta") : mech::mechanismFamily(run.mechanism).truth_model;
  std::printf(
      "%s: %d chains, %d images per pose, a true robot exactly of model %s (no unmodelled defects), robot seed "
      "2004 on even chains, a new one on odd chains, the camera placement moved per chain; work dir %s\n",
      run.mechanism.c_str(), run.chains, run.images_per_pose, study.model.c_str(), run.work.string().c_str());
  if (runChains(run, study, [&](int chain) { runChain(chain, run.images_per_pose, run.work, study); }) < 2) return 1;
  printStages(study);
  printIdentification(study);
  printTimes(study);
  return 0;
}

}  // namespace mire::bench
