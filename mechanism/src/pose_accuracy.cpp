// ISO 9283 pose accuracy and repeatability, distance accuracy, straightness (pose_accuracy.hpp).
#include "mire/mechanism/pose_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "mire/mechanism/evaluation.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"
#include "pose_accuracy_stats.hpp"

namespace mire::mechanism {
namespace {

struct PositionCycles {
  std::string name;
  Eigen::Isometry3d commanded = Eigen::Isometry3d::Identity();
  std::vector<const AccuracySample*> cycles;
};

// Positions in first-appearance order, each with its cycles in file order.
std::vector<PositionCycles> groupByPosition(const std::vector<AccuracySample>& samples) {
  std::vector<PositionCycles> positions;
  std::map<std::string, std::size_t> index;
  for (const AccuracySample& s : samples) {
    const auto [it, inserted] = index.emplace(s.position, positions.size());
    if (inserted) positions.push_back({s.position, s.commanded, {}});
    PositionCycles& p = positions[it->second];
    const IsoPose offset = isoDeviation(p.commanded, s.commanded);
    if (offset.head<3>().norm() > 1e-6 || offset.tail<3>().norm() > 1e-6)
      throw std::invalid_argument("pose '" + s.id + "': position '" + s.position +
                                  "' is commanded elsewhere than at its first cycle (by " +
                                  support::formatNumber(offset.head<3>().norm() * 1e3, 4) + " mm, " +
                                  support::formatNumber(offset.tail<3>().norm(), 4) + " rad)");
    p.cycles.push_back(&s);
  }
  for (const PositionCycles& p : positions)
    if (p.cycles.size() < 2)
      throw std::invalid_argument("position '" + p.name + "' has " + std::to_string(p.cycles.size()) +
                                  " cycle: ISO 9283 repeatability needs at least 2 (30 recommended)");
  return positions;
}

std::string mm(double metres) { return support::formatNumber(metres * 1e3, 3) + " mm"; }
std::string deg(double radians) { return support::formatNumber(radians / support::kRadiansPerDegree, 3) + " deg"; }

// A figure at or below what the noise alone gives 95 % of the time is not resolved.
void warnUnresolved(std::vector<std::string>& warnings, const std::string& figure, double value, const NoiseOnly& noise,
                    bool angle) {
  if (noise.p95 <= 0.0 || value > noise.p95) return;
  const auto show = [angle](double v) { return angle ? deg(v) : mm(v); };
  warnings.push_back(figure + " = " + show(value) + " is within what the measurement's noise alone gives (95 % up to " +
                     show(noise.p95) + "): the measurement does not resolve it");
}

void addNoiseOnly(PositionAccuracy& out, const std::vector<IsoPoseCovariance>& covariances,
                  const AccuracyOptions& options) {
  detail::NoiseDraws draws(covariances, options.seed);
  std::vector<double> ap_p, rp_l;
  std::array<std::vector<double>, 3> ap_abc, rp_abc;
  for (int r = 0; r < options.noise_draws; ++r) {
    const detail::PoseStatistics s = detail::poseStatistics(draws.draw());
    ap_p.push_back(s.ap_p);
    rp_l.push_back(s.rp_l);
    for (std::size_t k = 0; k < 3; ++k) {
      ap_abc[k].push_back(std::abs(s.ap_abc[static_cast<Eigen::Index>(k)]));
      rp_abc[k].push_back(3.0 * s.s_abc[static_cast<Eigen::Index>(k)]);
    }
  }
  out.noise_ap_p = detail::summarize(ap_p);
  out.noise_rp_l = detail::summarize(rp_l);
  for (std::size_t k = 0; k < 3; ++k) {
    out.noise_ap_abc[k] = detail::summarize(ap_abc[k]);
    out.noise_rp_abc[k] = detail::summarize(rp_abc[k]);
  }
}

PositionAccuracy accuracyOf(const PositionCycles& p, const AccuracyOptions& options) {
  PositionAccuracy out;
  out.position = p.name;
  out.cycles = static_cast<int>(p.cycles.size());
  out.commanded = isoPose(p.commanded);
  std::vector<IsoPose> deviations;
  std::vector<IsoPoseCovariance> covariances;
  IsoPoseCovariance mean_covariance = IsoPoseCovariance::Zero();  // of the mean deviation
  for (const AccuracySample* s : p.cycles) {
    deviations.push_back(isoDeviation(p.commanded, s->attained));
    covariances.push_back(s->covariance);
    mean_covariance += s->covariance;
  }
  const double n = static_cast<double>(p.cycles.size());
  mean_covariance /= n * n;
  const detail::PoseStatistics s = detail::poseStatistics(deviations);
  out.barycentre = out.commanded;
  out.barycentre.head<3>() += s.ap_xyz;
  out.barycentre.tail<3>() += s.ap_abc;
  out.ap_p = s.ap_p;
  out.ap_xyz = s.ap_xyz;
  out.ap_abc = s.ap_abc;
  out.sigma_ap_xyz = mean_covariance.diagonal().head<3>().cwiseSqrt();
  out.sigma_ap_abc = mean_covariance.diagonal().tail<3>().cwiseSqrt();
  // First order along the deviation; at AP_p = 0 the norm's spread is the noise-only one.
  const Eigen::Vector3d u = s.ap_p > 0.0 ? Eigen::Vector3d(s.ap_xyz / s.ap_p) : Eigen::Vector3d::UnitX();
  out.sigma_ap_p = std::sqrt(std::max(0.0, u.dot(mean_covariance.topLeftCorner<3, 3>() * u)));
  out.l_mean = s.l_mean;
  out.s_l = s.s_l;
  out.rp_l = s.rp_l;
  out.s_abc = s.s_abc;
  out.rp_abc = 3.0 * s.s_abc;
  addNoiseOnly(out, covariances, options);
  warnUnresolved(out.warnings, "AP_p", out.ap_p, out.noise_ap_p, false);
  warnUnresolved(out.warnings, "RP_l", out.rp_l, out.noise_rp_l, false);
  const char* names[3] = {"a", "b", "c"};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto e = static_cast<Eigen::Index>(k);
    warnUnresolved(out.warnings, std::string("AP_") + names[k], std::abs(out.ap_abc[e]), out.noise_ap_abc[k], true);
    warnUnresolved(out.warnings, std::string("RP_") + names[k], out.rp_abc[e], out.noise_rp_abc[k], true);
  }
  return out;
}

DistanceAccuracy distanceOf(const PositionCycles& a, const PositionCycles& b, const AccuracyOptions& options) {
  DistanceAccuracy out;
  out.from = a.name;
  out.to = b.name;
  const std::size_t n = std::min(a.cycles.size(), b.cycles.size());
  out.cycles = static_cast<int>(n);
  out.d_commanded = (a.commanded.translation() - b.commanded.translation()).norm();
  std::vector<double> d;
  std::vector<Eigen::Vector3d> v;
  std::vector<IsoPoseCovariance> covariances;  // of cycle j's difference (positions only)
  double variance = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    v.push_back(a.cycles[j]->attained.translation() - b.cycles[j]->attained.translation());
    d.push_back(v.back().norm());
    IsoPoseCovariance c = IsoPoseCovariance::Zero();
    c.topLeftCorner<3, 3>() =
        a.cycles[j]->covariance.topLeftCorner<3, 3>() + b.cycles[j]->covariance.topLeftCorner<3, 3>();
    covariances.push_back(c);
    const Eigen::Vector3d u = v.back().normalized();
    variance += u.dot(c.topLeftCorner<3, 3>() * u);
  }
  const detail::MeanSpread ms = detail::meanSpread(d);
  out.d_mean = ms.mean;
  out.ad_p = ms.mean - out.d_commanded;  // §7.4.1
  out.sigma_ad_p = std::sqrt(variance) / static_cast<double>(n);
  out.s_d = ms.s;
  out.rd = 3.0 * ms.s;  // §7.4.2
  // A perfect robot: every cycle at the mean difference, seen through the noise.
  Eigen::Vector3d v_mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : v) v_mean += x;
  v_mean /= static_cast<double>(n);
  detail::NoiseDraws draws(covariances, options.seed);
  std::vector<double> ad, rd;
  for (int r = 0; r < options.noise_draws; ++r) {
    std::vector<double> dn;
    for (const IsoPose& e : draws.draw()) dn.push_back((v_mean + e.head<3>()).norm());
    const detail::MeanSpread m = detail::meanSpread(dn);
    ad.push_back(std::abs(m.mean - v_mean.norm()));
    rd.push_back(3.0 * m.s);
  }
  out.noise_ad_p = detail::summarize(ad);
  out.noise_rd = detail::summarize(rd);
  warnUnresolved(out.warnings, "|AD_p|", std::abs(out.ad_p), out.noise_ad_p, false);
  warnUnresolved(out.warnings, "RD", out.rd, out.noise_rd, false);
  return out;
}

// Distances of points to their least-squares line (fitLine): RMS and largest.
std::pair<double, double> lineDistances(const std::vector<Eigen::Vector3d>& points) {
  const FittedLine line = fitLine(points);
  double sum_sq = 0.0, largest = 0.0;
  for (const auto& p : points) {
    const double d = line.distance(p);
    sum_sq += d * d;
    largest = std::max(largest, d);
  }
  return {std::sqrt(sum_sq / static_cast<double>(points.size())), largest};
}

}  // namespace

std::vector<PositionAccuracy> poseAccuracy(const std::vector<AccuracySample>& samples, const AccuracyOptions& options) {
  std::vector<PositionAccuracy> out;
  for (const PositionCycles& p : groupByPosition(samples)) out.push_back(accuracyOf(p, options));
  return out;
}

std::vector<DistanceAccuracy> distanceAccuracy(const std::vector<AccuracySample>& samples,
                                               const AccuracyOptions& options) {
  const std::vector<PositionCycles> positions = groupByPosition(samples);
  std::vector<DistanceAccuracy> out;
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (std::size_t k = i + 1; k < positions.size(); ++k)
      out.push_back(distanceOf(positions[i], positions[k], options));
  return out;
}

LineStraightness lineStraightness(const std::string& line, const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<Eigen::Matrix3d>& covariances, const AccuracyOptions& options) {
  if (points.size() < 3)
    throw std::invalid_argument("line '" + line + "' has " + std::to_string(points.size()) +
                                " points: straightness needs at least 3");
  if (!covariances.empty() && covariances.size() != points.size())
    throw std::invalid_argument("line '" + line + "': one covariance per point expected");
  LineStraightness out;
  out.line = line;
  out.points = static_cast<int>(points.size());
  std::tie(out.rms, out.max) = lineDistances(points);
  if (!covariances.empty()) {
    // A perfectly straight motion: the points' projections on their line, seen through the noise.
    const FittedLine fitted = fitLine(points);
    std::vector<IsoPoseCovariance> six;
    for (const Eigen::Matrix3d& c : covariances) {
      IsoPoseCovariance s = IsoPoseCovariance::Zero();
      s.topLeftCorner<3, 3>() = c;
      six.push_back(s);
    }
    detail::NoiseDraws draws(six, options.seed);
    std::vector<double> rms, largest;
    for (int r = 0; r < options.noise_draws; ++r) {
      const std::vector<IsoPose> e = draws.draw();
      std::vector<Eigen::Vector3d> straight;
      for (std::size_t j = 0; j < points.size(); ++j) straight.push_back(fitted.projection(points[j]) + e[j].head<3>());
      const auto [a, b] = lineDistances(straight);
      rms.push_back(a);
      largest.push_back(b);
    }
    out.noise_rms = detail::summarize(rms);
    out.noise_max = detail::summarize(largest);
  }
  out.rms_beyond_noise = std::sqrt(std::max(0.0, out.rms * out.rms - out.noise_rms.mean * out.noise_rms.mean));
  warnUnresolved(out.warnings, "straightness", out.rms, out.noise_rms, false);
  return out;
}

}  // namespace mire::mechanism
