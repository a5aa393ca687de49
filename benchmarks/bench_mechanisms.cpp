// Delta and Gough–Stewart (and H4) studies of doc/mechanisms.md, run by hand:
//  1. σ check: 40 exact-model campaigns (1 mm / 0.5° errors, 0.2 mm / 0.03° pose noise),
//     std((estimate − truth)/σ) of every identified parameter, target [0.8, 1.25];
//  2. `fkm --frame camera` on 20 held-out poses: RMS(predicted − noise-free cTm) / predicted σ;
//  3. timing of one identification (CPU, median of 21);
//  4. identify on 10⁴ and 10⁵ H4 poses (linear in N).
// Usage: bench_mechanisms [campaigns=40] [skip_scaling=0]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "sample_statistics.hpp"

using namespace mire::mechanism;
using mire::datasets::Campaign;
using mire::datasets::simulateCampaign;

namespace {

double cpuMs(const std::function<void()>& f, int repeats = 21) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const std::clock_t t0 = std::clock();
    f();
    ms.push_back(1e3 * double(std::clock() - t0) / CLOCKS_PER_SEC);
  }
  std::nth_element(ms.begin(), ms.begin() + repeats / 2, ms.end());
  return ms[static_cast<std::size_t>(repeats / 2)];
}

void sigmaStudy(const std::string& name, int campaigns) {
  std::map<std::string, std::vector<double>> normalised;
  std::vector<double> ratio_t, ratio_r;
  double rms_t = 0, sig_t = 0, rms_r = 0, sig_r = 0;
  int held = 0, rank = 0, params = 0;
  std::string gauge_names;
  for (int c = 0; c < campaigns; ++c) {
    // 81 (H4, hexapod) or 27 (Delta) identification poses + 20 held-out ones.
    Campaign all =
        simulateCampaign(name, 100 + static_cast<unsigned>(c), 0.2e-3, 0.03 * mire::datasets::kCampaignDeg, 20);
    std::vector<PoseObservation> train(all.poses.begin(), all.poses.end() - 20);
    IdentificationModel model = makeInitialModel(all.model.mechanism, all.model.nominal, train, all.model.external_form);
    const GaugeAnalysis gauge = fixGauge(model, train);
    IdentificationResult result = identify(model, train);
    const auto mean_orientation_covariance = alignTranslatingTarget(result, train);
    rank = gauge.report.rank;
    params = static_cast<int>(gauge.report.parameter_names.size());
    if (c == 0)
      for (const auto& g : gauge.gauge) gauge_names += " " + g;
    for (const std::string& n : gauge.identified) {
      if (!all.truth.contains(n)) continue;
      const double s = result.sigmaOf(n);
      normalised[n].push_back((result.model.parameters.value(n) - all.truth.value(n)) / s);
    }
    const PredictionModel prediction = predictionModelFrom(name, result, mean_orientation_covariance);
    double ce = 0, cs = 0;
    for (std::size_t j = all.poses.size() - 20; j < all.poses.size(); ++j) {
      const PosePrediction p = predictPose(prediction, all.poses[j].joints);
      if (!p.converged) continue;
      const Eigen::Isometry3d truth = all.bTc.inverse() * all.bTe[j] * all.mTe.inverse();
      const Eigen::Isometry3d predicted = toIsometry(p.cTm);
      const Eigen::Vector3d dt = predicted.translation() - truth.translation();
      const Eigen::AngleAxisd dr(truth.linear().transpose() * predicted.linear());
      PoseVector tv = toPoseVector(truth);
      if ((tv.tail<3>() - p.cTm.tail<3>()).norm() > 1.0 && tv.tail<3>().norm() > 1.0)
        tv.tail<3>() *= 1.0 - 2.0 * 3.14159265358979323846 / tv.tail<3>().norm();  // same rotation, nearest vector
      for (int k = 0; k < 6; ++k)
        (k < 3 ? ratio_t : ratio_r).push_back((p.cTm[k] - tv[k]) / std::sqrt(p.cTm_covariance(k, k)));
      rms_t += dt.squaredNorm();
      rms_r += dr.angle() * dr.angle();
      sig_t += p.cTm_covariance.topLeftCorner<3, 3>().trace();
      // rotation-vector covariance ≈ covariance of the small rotation error
      sig_r += p.cTm_covariance.bottomRightCorner<3, 3>().trace();
      ce += dt.squaredNorm();
      cs += p.cTm_covariance.topLeftCorner<3, 3>().trace();
      ++held;
    }
    if (std::getenv("MIRE_BENCH_VERBOSE"))
      std::printf("  campaign %d: position RMS %.4f mm, sigma %.4f mm\n", c, 1e3 * std::sqrt(ce / 20),
                  1e3 * std::sqrt(cs / 20));
  }
  std::printf("\n== %s: %d campaigns; rank %d of %d free parameters (gauge:%s)\n", name.c_str(), campaigns, rank,
              params, gauge_names.c_str());
  double lo = 1e9, hi = 0;
  for (const auto& [n, v] : normalised) {
    const double s = mire::test::sampleStandardDeviation(v);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    std::printf("  %-8s std(error/sigma) %.3f\n", n.c_str(), s);
  }
  std::printf("  identified parameters: std(error/sigma) in [%.3f, %.3f] (target [0.8, 1.25])\n", lo, hi);
  std::printf(
      "  fkm --frame camera, %d held-out poses: RMS position error %.4f mm vs predicted sigma %.4f mm "
      "(ratio %.2f); RMS rotation error %.5f deg vs predicted %.5f deg (ratio %.2f)\n",
      held, 1e3 * std::sqrt(rms_t / held), 1e3 * std::sqrt(sig_t / held), std::sqrt(rms_t / sig_t),
      57.29578 * std::sqrt(rms_r / held), 57.29578 * std::sqrt(sig_r / held), std::sqrt(rms_r / sig_r));
  std::printf(
      "  fkm --frame camera, per component: position std(error/sigma) %.3f, rotation-vector std(error/sigma) %.3f "
      "(target [0.8, 1.25])\n",
      mire::test::sampleStandardDeviation(ratio_t), mire::test::sampleStandardDeviation(ratio_r));
}

void timing(const std::string& name) {
  const Campaign c = simulateCampaign(name, 7);
  IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
  fixGauge(model, c.poses);
  IdentificationResult result;
  const double ms = cpuMs([&] { result = identify(model, c.poses); });
  const double init_ms = cpuMs(
      [&] {
        IdentificationModel m = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
        fixGauge(m, c.poses);
      },
      5);
  std::printf(
      "%-14s identify: %zu poses, %zu free of %zu parameters: %.2f ms CPU median (%d iterations); "
      "mounting from the data + gauge analysis: %.2f ms\n",
      name.c_str(), c.poses.size(), result.free_names.size(), result.model.parameters.size(), ms, result.iterations,
      init_ms);
}

void scaling() {
  double previous = 0;
  for (int n : {10000, 100000}) {
    const Campaign c = simulateCampaign("h4-12", 9, 0.2e-3, 0.03 * mire::datasets::kCampaignDeg, 0, n);
    const std::clock_t t0 = std::clock();
    const IdentificationModel model =
        makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, ExternalForm::AxisAligned);
    const IdentificationResult result = identify(model, c.poses);
    const double s = double(std::clock() - t0) / CLOCKS_PER_SEC;
    std::printf("h4-12 identify on %d poses (initial mounting + weighted identification): %.2f s CPU%s\n", n, s,
                previous > 0 ? (" (" + std::to_string(s / previous) + "x the 10^4 time; limit 10x)").c_str() : "");
    previous = s;
    (void)result;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 40;
  const bool skip_scaling = argc > 2 && std::atoi(argv[2]) != 0;
  for (const char* name : {"delta", "gough-stewart", "h4-12"}) timing(name);
  for (const char* name : {"delta", "delta-legs", "gough-stewart", "h4-12"}) sigmaStudy(name, campaigns);
  if (!skip_scaling) scaling();
  return 0;
}
