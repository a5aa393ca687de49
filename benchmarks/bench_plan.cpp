// `mire plan` acceptance study (doc/plan-and-select.md), run by hand:
//  for each model, N planned poses (Ds-optimal, DETMAX over the candidates of the protocol
//  workspace) against random N-subsets and random 71-subsets of the same candidates:
//  predicted σ of every geometric parameter, and the actual spread of the identified values over
//  repeated simulated campaigns (true geometry = nominal with 1 mm / 0.5° errors, pose noise
//  0.2 mm / 0.03°); timing of the choice of 15 among 10⁴ candidates for model 12.
// Usage: bench_plan [campaigns=30] [models=h4-12,delta,gough-stewart]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/identification.hpp"

using namespace mire::mechanism;

namespace {

double seconds(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// RMS effector position error of the identified geometry at 100 poses spread over the
// candidates (FKM of the true joints), the common rigid motion removed as the plan's
// predicted positioning σ does.
double positionError(const Mechanism& m, const Eigen::VectorXd& truth, const Eigen::VectorXd& identified,
                     const CandidateInformation& info) {
  std::vector<Eigen::Vector3d> p, e;
  const std::size_t stride = std::max<std::size_t>(1, info.poses.size() / 100);
  for (std::size_t j = 0; j < info.poses.size(); j += stride) {
    const Eigen::VectorXd& X = info.poses[j];
    const IkmResult q = m.inverseKinematics(truth, m.poseToTransform(X));
    if (!q.reachable()) continue;
    const FkmResult f = m.forwardKinematics(identified, q.joints, X);
    if (!f.converged) continue;
    p.push_back(X.head<3>());
    e.push_back(f.pose.head<3>() - X.head<3>());
  }
  const auto n = static_cast<Eigen::Index>(p.size());
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& x : p) c += x / static_cast<double>(n);
  Eigen::MatrixXd B(3 * n, 6);
  Eigen::VectorXd y(3 * n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector3d d = p[static_cast<std::size_t>(j)] - c;
    B.block(3 * j, 0, 3, 3).setIdentity();
    B.block(3 * j, 3, 3, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
    y.segment<3>(3 * j) = e[static_cast<std::size_t>(j)];
  }
  const Eigen::VectorXd residual = y - B * B.colPivHouseholderQr().solve(y);
  return std::sqrt(residual.squaredNorm() / static_cast<double>(n));
}

// One simulated campaign at the given candidate poses: the errors of the identified free geometric values.
std::optional<Eigen::VectorXd> identifiedGeometry(const DesignModel& model, const MountingGuess& mounting,
                                                  const CandidateInformation& info, const std::vector<int>& design,
                                                  unsigned seed) {
  const Mechanism& m = *model.registered.mechanism;
  const ParameterSet truth = mire::datasets::perturbed(model.registered.nominal, seed);
  std::mt19937 rng(seed + 99);
  std::normal_distribution<double> normal;
  const double st = 0.2e-3, sr = 0.03 * 3.14159265358979323846 / 180.0;
  std::vector<PoseObservation> obs;
  for (int j : design) {
    const Eigen::Isometry3d bTe = m.poseToTransform(info.poses[static_cast<std::size_t>(j)]);
    PoseObservation o;
    o.id = std::to_string(obs.size() + 1);
    const IkmResult q = m.inverseKinematics(truth.values(), bTe);
    if (!q.reachable()) return std::nullopt;
    o.joints = q.joints;
    o.cTm = toPoseVector(mounting.bTc.inverse() * bTe * mounting.mTe.inverse());
    for (int k = 0; k < 3; ++k) o.cTm[k] += st * normal(rng);
    for (int k = 3; k < 6; ++k) o.cTm[k] += sr * normal(rng);
    PoseCovariance c = PoseCovariance::Zero();
    c.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
    o.covariance = c;
    obs.push_back(o);
  }
  try {
    IdentificationModel initial = initialModelFor(model, obs);
    // Hold the same parameters as the plan (its gauge), so the spreads compare like with like.
    for (std::size_t i = 0; i < initial.parameters.size(); ++i) {
      const std::string& n = initial.parameters[i].name;
      const bool free_in_plan = std::find(info.free_names.begin(), info.free_names.end(), n) != info.free_names.end();
      if (!free_in_plan && initial.parameters.tieLeader(i) == i) initial.parameters.setFixed(n, true);
    }
    IdentificationOptions options;
    options.compute_identifiability = false;
    const IdentificationResult r = identify(initial, obs, options);
    if (!r.converged) return std::nullopt;
    Eigen::VectorXd out(info.geometric_free + 1);
    out[info.geometric_free] = positionError(m, truth.values(), r.model.geometricValues(), info);
    for (int k = 0; k < info.geometric_free; ++k) {
      const std::string& n = info.free_names[static_cast<std::size_t>(k)];
      out[k] = r.model.parameters.value(n) - truth.value(n);  // the error: truths differ per campaign
    }
    return out;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Per-parameter RMS error of the identified values over `campaigns` campaigns.
Eigen::VectorXd actualSpread(const DesignModel& model, const MountingGuess& mounting, const CandidateInformation& info,
                             const std::function<std::vector<int>(int)>& design_of, int campaigns, int* used) {
  std::vector<Eigen::VectorXd> values;
  for (int c = 0; c < campaigns; ++c)
    if (auto v = identifiedGeometry(model, mounting, info, design_of(c), 500u + static_cast<unsigned>(c)))
      values.push_back(*v);
  *used = static_cast<int>(values.size());
  // RMS error (truth known): the actual spread the predicted σ should match.
  Eigen::VectorXd sq = Eigen::VectorXd::Zero(info.geometric_free + 1);
  for (const auto& v : values) sq += v.cwiseAbs2() / std::max<double>(1, static_cast<double>(values.size()));
  return sq.cwiseSqrt();
}

std::vector<int> randomSubset(int n, int count, std::mt19937& rng) {
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(static_cast<std::size_t>(count));
  return all;
}

double medianRatio(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int G) {
  std::vector<double> r;
  for (int k = 0; k < G; ++k)
    if (std::isfinite(a[k] / b[k])) r.push_back(a[k] / b[k]);
  return median(r);
}

void study(const std::string& name, int count, int candidates, int campaigns) {
  const DesignModel model = makeDesignModel(name);
  const Mechanism& m = *model.registered.mechanism;
  const Workspace w = protocolWorkspace(m, model.registered.nominal.values());
  const MountingGuess mounting = defaultMountingGuess(w);
  auto t0 = std::chrono::steady_clock::now();
  const std::clock_t total0 = std::clock();
  const auto poses = generateCandidatePoses(m, model.registered.nominal.values(), w, candidates, 1);
  const double t_generate = seconds(t0);
  DesignOptions options;
  options.count = count;
  t0 = std::chrono::steady_clock::now();
  const CandidateInformation info = candidateInformation(model, mounting, poses, options);
  const double t_info = seconds(t0);
  std::printf("CPU time candidates + information: %.3f s\n", double(std::clock() - total0) / CLOCKS_PER_SEC);
  t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const std::vector<int> chosen = chooseDesign(info, options);
  const double cpu_choice = double(std::clock() - c0) / CLOCKS_PER_SEC;
  const DesignReport report = planExperiment(info, options);
  const double t_report = seconds(t0);
  const int G = info.geometric_free;
  std::printf("\n== %s: %d planned of %d candidates, %d free (%d geometric) ==\n", name.c_str(), count, candidates,
              static_cast<int>(info.free_names.size()), G);
  std::printf("wall time (loaded machine): candidates %.3f s, information %.3f s, choice %.3f s, report %.3f s\n",
              t_generate, t_info, report.seconds, t_report - report.seconds);
  std::printf("CPU time of the choice alone: %.3f s (%zu poses)\n", cpu_choice, chosen.size());
  std::printf("predicted: median sigma ratio plan/random(%d) = %.3f\n", count, report.median_ratio_plan_random);
  // 71 random poses (the paper's largest random subset) against the plan.
  std::mt19937 rng(7);
  std::vector<std::vector<double>> s71(static_cast<std::size_t>(G));
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd s = designSigma(info, randomSubset(static_cast<int>(poses.size()), 71, rng));
    for (int i = 0; i < G; ++i) s71[static_cast<std::size_t>(i)].push_back(s[i]);
  }
  Eigen::VectorXd sigma71(G);
  for (int i = 0; i < G; ++i) sigma71[i] = median(s71[static_cast<std::size_t>(i)]);
  std::printf("predicted: median sigma ratio plan(%d)/random(71) = %.3f\n", count,
              medianRatio(report.sigma_plan, sigma71, G));
  std::printf("predicted positioning sigma: plan %.4f mm, random %.4f mm\n", report.position_sigma_plan_rms * 1e3,
              report.position_sigma_random_rms * 1e3);
  if (campaigns <= 0) return;
  int used_plan = 0, used_random = 0;
  const Eigen::VectorXd spread_plan = actualSpread(
      model, mounting, info, [&](int) { return report.design; }, campaigns, &used_plan);
  std::mt19937 rng2(11);
  std::vector<std::vector<int>> random_designs;
  for (int c = 0; c < campaigns; ++c)
    random_designs.push_back(randomSubset(static_cast<int>(poses.size()), count, rng2));
  const Eigen::VectorXd spread_random = actualSpread(
      model, mounting, info, [&](int c) { return random_designs[static_cast<std::size_t>(c)]; }, campaigns, &used_random);
  std::printf("actual spread over %d / %d campaigns: median ratio plan/random = %.3f\n", used_plan, used_random,
              medianRatio(spread_plan, spread_random, G));
  std::printf("actual/predicted spread of the plan: median %.3f\n", medianRatio(spread_plan, report.sigma_plan, G));
  std::printf(
      "positioning (rigid motion removed, RMS over 100 poses and the campaigns): plan actual %.4f mm vs "
      "predicted %.4f mm; random actual %.4f mm vs predicted %.4f mm\n",
      spread_plan[G] * 1e3, report.position_sigma_plan_rms * 1e3, spread_random[G] * 1e3,
      report.position_sigma_random_rms * 1e3);
  std::printf("  %-8s %12s %12s %12s %12s\n", "param", "pred plan", "act plan", "pred rand", "act rand");
  for (int i = 0; i < G; ++i) {
    const Unit u = report.units[static_cast<std::size_t>(i)];
    std::printf("  %-8s %12.5g %12.5g %12.5g %12.5g %s\n", report.names[static_cast<std::size_t>(i)].c_str(),
                toDisplay(u, report.sigma_plan[i]), toDisplay(u, spread_plan[i]), toDisplay(u, report.sigma_random[i]),
                toDisplay(u, spread_random[i]), displayUnitName(u).c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 30;
  std::string models = argc > 2 ? argv[2] : "h4-12,delta,gough-stewart";
  std::stringstream list(models);
  for (std::string name; std::getline(list, name, ',');) {
    if (name == "h4-12") {
      study(name, 15, 10000, campaigns);
    } else if (name == "delta") {
      study(name, 10, 2000, campaigns);
    } else {
      study(name, 15, 2000, campaigns);
    }
  }
  return 0;
}
