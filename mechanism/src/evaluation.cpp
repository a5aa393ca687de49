// Evaluation criteria of paper §6 (see evaluation.hpp).
#include "mire/mechanism/evaluation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

namespace mire::mechanism {

JointResidualCriteria jointResidualCriteria(const IdentificationModel& model,
                                            const std::vector<PoseObservation>& validation) {
  JointResidualCriteria criteria;
  double sum = 0.0, sum_sq = 0.0;
  long count = 0;
  for (const PoseObservation& pose : validation) {
    const IkmResult predicted = model.predictJoints(pose.cTm);
    if (!predicted.reachable()) {
      criteria.unreachable.push_back(pose.id);
      continue;
    }
    const Eigen::VectorXd residual = pose.joints - predicted.joints;
    sum += residual.sum();
    sum_sq += residual.squaredNorm();
    count += residual.size();
    ++criteria.pose_count;
  }
  if (count > 0) {
    criteria.v1_rad = sum / static_cast<double>(count);
    criteria.v2_rad = std::sqrt(sum_sq / static_cast<double>(count));
  } else {
    criteria.v1_rad = criteria.v2_rad = std::numeric_limits<double>::quiet_NaN();
  }
  return criteria;
}

FittedLine fitLine(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) throw std::invalid_argument("straightness: needs at least 2 points");
  FittedLine line;
  for (const auto& p : points) line.centroid += p;
  line.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) scatter += (p - line.centroid) * (p - line.centroid).transpose();
  line.direction = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
  return line;
}

double straightness(const std::vector<Eigen::Vector3d>& points) {
  const FittedLine line = fitLine(points);
  double sum_sq = 0.0;
  for (const auto& p : points) sum_sq += (p - line.projection(p)).squaredNorm();
  return std::sqrt(sum_sq / static_cast<double>(points.size()));
}

StraightnessResult straightnessCriterion(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                         const std::vector<std::vector<Eigen::VectorXd>>& line_joints) {
  StraightnessResult result;
  const Eigen::VectorXd reference = mechanism.referencePose(geometric);
  for (std::size_t line = 0; line < line_joints.size(); ++line) {
    std::vector<Eigen::Vector3d> points;
    Eigen::VectorXd guess = reference;
    for (std::size_t k = 0; k < line_joints[line].size(); ++k) {
      FkmResult fkm = mechanism.forwardKinematics(geometric, line_joints[line][k], guess);
      if (!fkm.converged) fkm = mechanism.forwardKinematics(geometric, line_joints[line][k], reference);
      if (!fkm.converged) {
        result.ok = false;
        result.message =
            "FKM failed on line " + std::to_string(line + 1) + ", point " + std::to_string(k + 1) + ": " + fkm.message;
        break;
      }
      guess = fkm.pose;
      points.emplace_back(fkm.bTe.translation());
    }
    if (!result.ok) break;
    result.per_line_m.push_back(straightness(points));
    result.points.push_back(std::move(points));
  }
  if (result.ok && !result.per_line_m.empty())
    result.v3_m = std::accumulate(result.per_line_m.begin(), result.per_line_m.end(), 0.0) /
                  static_cast<double>(result.per_line_m.size());
  else
    result.v3_m = std::numeric_limits<double>::quiet_NaN();
  return result;
}

std::vector<Eigen::VectorXd> commandJoints(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                           const std::vector<Eigen::VectorXd>& poses) {
  std::vector<Eigen::VectorXd> joints;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const IkmResult ikm = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(poses[k]));
    if (!ikm.reachable())
      throw std::runtime_error("commanded pose " + std::to_string(k + 1) + " is out of the model's reach");
    joints.push_back(ikm.joints);
  }
  return joints;
}

std::vector<Eigen::VectorXd> squareCorners(const Eigen::Vector3d& centre, double side) {
  const double half = 0.5 * side;
  std::vector<Eigen::VectorXd> corners;
  for (const auto& [sx, sy] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}}) {
    Eigen::VectorXd pose(4);
    pose << centre.x() + sx * half, centre.y() + sy * half, centre.z(), 0.0;
    corners.push_back(pose);
  }
  return corners;
}

std::vector<double> squareSideErrors(const std::vector<Eigen::Vector3d>& reached, double side) {
  std::vector<double> errors;
  for (std::size_t k = 0; k < reached.size(); ++k) {
    const Eigen::Vector3d& a = reached[k];
    const Eigen::Vector3d& b = reached[(k + 1) % reached.size()];
    errors.push_back((b - a).head<2>().norm() - side);
  }
  return errors;
}

namespace {

void meanSigma(const std::vector<double>& values, double* mean, double* sigma) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  if (finite.empty()) {
    *mean = *sigma = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  *mean = std::accumulate(finite.begin(), finite.end(), 0.0) / static_cast<double>(finite.size());
  double sum_sq = 0.0;
  for (double v : finite) sum_sq += (v - *mean) * (v - *mean);
  *sigma = finite.size() > 1 ? std::sqrt(sum_sq / static_cast<double>(finite.size() - 1)) : 0.0;
}

}  // namespace
namespace {

constexpr int kMaxMonteCarloThreads = 256;  // the commands' --threads limit (doc/limits.md)

void checkMonteCarloOptions(const MonteCarloOptions& options, int n) {
  for (int size : options.subset_sizes)
    if (size < 1 || size >= n)
      throw std::invalid_argument("Monte-Carlo subset size " + std::to_string(size) + " must be in 1.." +
                                  std::to_string(n - 1) + " (the other poses validate)");
  if (options.repeats < 1) throw std::invalid_argument("Monte-Carlo repeats must be >= 1");
  // Each thread is a std::thread: 10^6 of them end in std::terminate (doc/limits.md: 0..256).
  if (options.threads < 0 || options.threads > kMaxMonteCarloThreads)
    throw std::invalid_argument("Monte-Carlo threads " + std::to_string(options.threads) + " must be in 0.." +
                                std::to_string(kMaxMonteCarloThreads) + " (0 = one)");
}

struct MonteCarloJob {
  std::size_t summary, run;
  std::vector<int> order;  // shuffled pose indices: first `size` identify, the rest validate
};

// Draws every subset first (one RNG stream): the outcome does not depend on the threads.
std::vector<MonteCarloJob> drawSubsets(MonteCarloStudy& study, const MonteCarloOptions& options, int n) {
  std::vector<MonteCarloJob> jobs;
  std::mt19937_64 rng(options.seed);
  study.summaries.resize(options.subset_sizes.size());
  for (std::size_t s = 0; s < options.subset_sizes.size(); ++s) {
    study.summaries[s].subset_size = options.subset_sizes[s];
    study.summaries[s].runs.resize(static_cast<std::size_t>(options.repeats));
    for (int r = 0; r < options.repeats; ++r) {
      std::vector<int> order(static_cast<std::size_t>(n));
      std::iota(order.begin(), order.end(), 0);
      std::shuffle(order.begin(), order.end(), rng);
      jobs.push_back({s, static_cast<std::size_t>(r), std::move(order)});
    }
  }
  return jobs;
}

// One run: identify on the subset, V1/V2 on the other poses, V3 on the lines.
void identifyAndValidate(MonteCarloRun& run, int size, const std::vector<int>& order,
                         const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                         const std::vector<std::vector<Eigen::VectorXd>>& line_joints,
                         const IdentificationOptions& run_options) {
  std::vector<PoseObservation> subset, validation;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const PoseObservation& pose = poses[static_cast<std::size_t>(order[k])];
    if (static_cast<int>(k) < size) {
      subset.push_back(pose);
      run.subset.push_back(pose.id);
    } else {
      validation.push_back(pose);
    }
  }
  try {
    const IdentificationResult result = identify(initial, subset, run_options);
    run.values = result.model.parameters.values();
    const JointResidualCriteria criteria = jointResidualCriteria(result.model, validation);
    run.v1_rad = criteria.v1_rad;
    run.v2_rad = criteria.v2_rad;
    run.v3_m = std::numeric_limits<double>::quiet_NaN();
    if (!line_joints.empty())
      run.v3_m = straightnessCriterion(*result.model.mechanism, result.model.geometricValues(), line_joints).v3_m;
    run.ok = result.converged && std::isfinite(run.v2_rad);
    if (!run.ok)
      run.error = result.converged ? "validation poses unreachable" : "did not converge: " + result.solver_report;
  } catch (const std::exception& e) {
    run.ok = false;
    run.error = e.what();
  }
}

// Runs jobs [0, count) on `thread_count` threads (the caller's included).
void runOnThreads(std::size_t count, int thread_count, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t j = next++; j < count; j = next++) job(j);
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < std::max(1, thread_count); ++t) threads.emplace_back(worker);
  worker();
  for (auto& thread : threads) thread.join();
}

// Mean and σ of the parameters and criteria over the successful runs of one subset size.
void summariseRuns(MonteCarloSummary& summary, Eigen::Index p) {
  std::vector<double> v1, v2, v3;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(p), sum_sq = Eigen::VectorXd::Zero(p);
  for (const MonteCarloRun& run : summary.runs) {
    if (!run.ok) {
      ++summary.runs_failed;
      continue;
    }
    ++summary.runs_ok;
    sum += run.values;
    v1.push_back(run.v1_rad);
    v2.push_back(run.v2_rad);
    v3.push_back(run.v3_m);
  }
  summary.mean = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::quiet_NaN());
  summary.sigma = summary.mean;
  if (summary.runs_ok > 0) {
    summary.mean = sum / summary.runs_ok;
    for (const MonteCarloRun& run : summary.runs)
      if (run.ok) sum_sq += (run.values - summary.mean).array().square().matrix();
    summary.sigma =
        summary.runs_ok > 1 ? (sum_sq / (summary.runs_ok - 1)).cwiseSqrt().eval() : Eigen::VectorXd::Zero(p).eval();
  }
  meanSigma(v1, &summary.v1_mean, &summary.v1_sigma);
  meanSigma(v2, &summary.v2_mean, &summary.v2_sigma);
  meanSigma(v3, &summary.v3_mean, &summary.v3_sigma);
}

}  // namespace

MonteCarloStudy runMonteCarloStudy(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                                   const std::vector<std::vector<Eigen::VectorXd>>& line_joints,
                                   const MonteCarloOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(poses.size());
  checkMonteCarloOptions(options, n);
  MonteCarloStudy study;
  study.parameter_names = initial.parameters.names();
  const std::vector<MonteCarloJob> jobs = drawSubsets(study, options, n);

  IdentificationOptions run_options = options.identification;
  run_options.compute_identifiability = false;
  runOnThreads(jobs.size(), options.threads, [&](std::size_t j) {
    const MonteCarloJob& job = jobs[j];
    MonteCarloSummary& summary = study.summaries[job.summary];
    identifyAndValidate(summary.runs[job.run], summary.subset_size, job.order, initial, poses, line_joints, run_options);
    if (options.on_run_done) options.on_run_done();
  });

  const auto p = static_cast<Eigen::Index>(study.parameter_names.size());
  for (MonteCarloSummary& summary : study.summaries) summariseRuns(summary, p);
  study.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return study;
}

}  // namespace mire::mechanism
