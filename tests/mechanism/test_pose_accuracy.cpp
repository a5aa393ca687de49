// ISO 9283 figures (doc/accuracy.md) against an independent implementation written here from
// the standard's formulas (other loops, asin for the pitch, an SVD for the line), and their σ
// against the spread of simulated measurements of cycles whose true attained poses are known.
#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <cmath>
#include <cstdio>
#include <random>

#include "mire/mechanism/pose_accuracy.hpp"

namespace mire::mechanism {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Eigen::Isometry3d pose(const Eigen::Vector3d& t, double a, double b, double c) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(c, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

// The ISO 9283 cube's diagonal plane (clause 6): P1 at the centre, P2..P5 towards the corners.
std::vector<Eigen::Isometry3d> isoPositions() {
  std::vector<Eigen::Isometry3d> out;
  const Eigen::Vector3d centre(0.02, -0.01, -0.65);
  const double h = 0.12;
  const Eigen::Vector3d corners[5] = {{0, 0, 0}, {-h, -h, h}, {h, h, h}, {h, h, -h}, {-h, -h, -h}};
  for (int k = 0; k < 5; ++k) out.push_back(pose(centre + 0.8 * corners[k], 0.0, 0.0, 20 * kDeg * (k - 2)));
  return out;
}

struct Cycles {
  std::vector<AccuracySample> measured, truth;
};

// 5 positions × `n` cycles: a robot with a per-position bias (`bias` m / rad) and scatter
// (`scatter`), measured with noise of covariance `noise` (of the ISO pose).
Cycles simulateCycles(unsigned seed, int n, double bias, double scatter, const IsoPoseCovariance& noise) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Eigen::LLT<IsoPoseCovariance> llt(noise);
  Cycles out;
  const auto positions = isoPositions();
  std::vector<IsoPose> biases;
  for (std::size_t p = 0; p < positions.size(); ++p) {
    IsoPose b;
    for (int k = 0; k < 6; ++k) b[k] = bias * normal(rng) * (k < 3 ? 1.0 : 0.5);
    biases.push_back(b);
  }
  for (int j = 0; j < n; ++j)
    for (std::size_t p = 0; p < positions.size(); ++p) {
      const IsoPose c = isoPose(positions[p]);
      IsoPose t = c + biases[p];
      for (int k = 0; k < 6; ++k) t[k] += scatter * normal(rng) * (k < 3 ? 1.0 : 0.5);
      IsoPose z;
      for (int k = 0; k < 6; ++k) z[k] = normal(rng);
      const IsoPose m = t + IsoPose(llt.matrixL() * z);
      AccuracySample s;
      s.id = "P" + std::to_string(p + 1) + "_" + std::to_string(j + 1);
      s.position = "P" + std::to_string(p + 1);
      s.commanded = positions[p];
      s.attained = pose(t.head<3>(), t[3], t[4], t[5]);
      out.truth.push_back(s);
      s.attained = pose(m.head<3>(), m[3], m[4], m[5]);
      s.covariance = noise;
      out.measured.push_back(s);
    }
  return out;
}

IsoPoseCovariance measurementNoise() {
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  a.diagonal() << 0.2e-3, 0.15e-3, 0.3e-3, 0.03 * kDeg, 0.02 * kDeg, 0.04 * kDeg;
  a(2, 0) = 0.1e-3;  // correlated x/z, as a camera's depth is
  a(5, 3) = 0.01 * kDeg;
  return a * a.transpose();
}

// ---- the independent implementation -------------------------------------------------------
struct Independent {
  double ap_p, apx, apy, apz, apa, apb, apc, rp_l, rpa, rpb, rpc;
};

double wrap(double angle) {
  while (angle > kPi) angle -= 2 * kPi;
  while (angle <= -kPi) angle += 2 * kPi;
  return angle;
}

void angles(const Eigen::Matrix3d& r, double& a, double& b, double& c) {
  b = -std::asin(r(2, 0));
  a = std::atan2(r(2, 1) / std::cos(b), r(2, 2) / std::cos(b));
  c = std::atan2(r(1, 0) / std::cos(b), r(0, 0) / std::cos(b));
}

Independent independent(const std::vector<AccuracySample>& samples, const std::string& position) {
  std::vector<const AccuracySample*> cyc;
  for (const auto& s : samples)
    if (s.position == position) cyc.push_back(&s);
  const double n = static_cast<double>(cyc.size());
  double xc = cyc[0]->commanded.translation().x(), yc = cyc[0]->commanded.translation().y(),
         zc = cyc[0]->commanded.translation().z();
  double ac, bc, cc;
  angles(cyc[0]->commanded.linear(), ac, bc, cc);
  double sx = 0, sy = 0, sz = 0, sa = 0, sb = 0, sc = 0;
  std::vector<double> da, db, dc;
  for (const auto* s : cyc) {
    sx += s->attained.translation().x();
    sy += s->attained.translation().y();
    sz += s->attained.translation().z();
    double a, b, c;
    angles(s->attained.linear(), a, b, c);
    da.push_back(wrap(a - ac));
    db.push_back(wrap(b - bc));
    dc.push_back(wrap(c - cc));
    sa += da.back();
    sb += db.back();
    sc += dc.back();
  }
  const double xb = sx / n, yb = sy / n, zb = sz / n;
  Independent r{};
  r.apx = xb - xc;
  r.apy = yb - yc;
  r.apz = zb - zc;
  r.ap_p = std::sqrt(r.apx * r.apx + r.apy * r.apy + r.apz * r.apz);
  r.apa = sa / n;
  r.apb = sb / n;
  r.apc = sc / n;
  std::vector<double> l;
  double lsum = 0;
  for (const auto* s : cyc) {
    const double dx = s->attained.translation().x() - xb, dy = s->attained.translation().y() - yb,
                 dz = s->attained.translation().z() - zb;
    l.push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
    lsum += l.back();
  }
  const double lbar = lsum / n;
  double ssl = 0, ssa = 0, ssb = 0, ssc = 0;
  for (std::size_t j = 0; j < l.size(); ++j) {
    ssl += (l[j] - lbar) * (l[j] - lbar);
    ssa += (da[j] - r.apa) * (da[j] - r.apa);
    ssb += (db[j] - r.apb) * (db[j] - r.apb);
    ssc += (dc[j] - r.apc) * (dc[j] - r.apc);
  }
  r.rp_l = lbar + 3 * std::sqrt(ssl / (n - 1));
  r.rpa = 3 * std::sqrt(ssa / (n - 1));
  r.rpb = 3 * std::sqrt(ssb / (n - 1));
  r.rpc = 3 * std::sqrt(ssc / (n - 1));
  return r;
}

TEST(PoseAccuracy, EqualsAnIndependentImplementation) {
  const Cycles c = simulateCycles(1, 30, 0.8e-3, 0.1e-3, measurementNoise());
  AccuracyOptions options;
  options.noise_draws = 200;
  const auto positions = poseAccuracy(c.measured, options);
  ASSERT_EQ(positions.size(), 5u);
  const double tol = 1e-9;  // 1e-6 mm; angles to 1e-9 rad
  for (const PositionAccuracy& p : positions) {
    EXPECT_EQ(p.cycles, 30);
    const Independent r = independent(c.measured, p.position);
    EXPECT_NEAR(p.ap_p, r.ap_p, tol) << p.position;
    EXPECT_NEAR(p.ap_xyz.x(), r.apx, tol);
    EXPECT_NEAR(p.ap_xyz.y(), r.apy, tol);
    EXPECT_NEAR(p.ap_xyz.z(), r.apz, tol);
    EXPECT_NEAR(p.ap_abc[0], r.apa, tol);
    EXPECT_NEAR(p.ap_abc[1], r.apb, tol);
    EXPECT_NEAR(p.ap_abc[2], r.apc, tol);
    EXPECT_NEAR(p.rp_l, r.rp_l, tol);
    EXPECT_NEAR(p.rp_abc[0], r.rpa, tol);
    EXPECT_NEAR(p.rp_abc[1], r.rpb, tol);
    EXPECT_NEAR(p.rp_abc[2], r.rpc, tol);
    EXPECT_GT(p.ap_p, 1e-4);  // the 0.8 mm bias is there to be found
  }

  // §7.4 between every pair, cycle j with cycle j.
  const auto distances = distanceAccuracy(c.measured, options);
  ASSERT_EQ(distances.size(), 10u);
  for (const DistanceAccuracy& d : distances) {
    std::vector<Eigen::Vector3d> pa, pb;
    Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
    for (const auto& s : c.measured) {
      if (s.position == d.from) {
        pa.push_back(s.attained.translation());
        ca = s.commanded.translation();
      }
      if (s.position == d.to) {
        pb.push_back(s.attained.translation());
        cb = s.commanded.translation();
      }
    }
    double sum = 0;
    std::vector<double> dj;
    for (std::size_t j = 0; j < pa.size(); ++j) {
      const Eigen::Vector3d v = pa[j] - pb[j];
      dj.push_back(std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z()));
      sum += dj.back();
    }
    const double mean = sum / static_cast<double>(dj.size());
    double ss = 0;
    for (double x : dj) ss += (x - mean) * (x - mean);
    const Eigen::Vector3d dc = ca - cb;
    EXPECT_NEAR(d.ad_p, mean - std::sqrt(dc.dot(dc)), tol) << d.from << "-" << d.to;
    EXPECT_NEAR(d.rd, 3 * std::sqrt(ss / static_cast<double>(dj.size() - 1)), tol);
  }
}

TEST(PoseAccuracy, StraightnessEqualsAnIndependentFit) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 21; ++k)
    points.push_back(Eigen::Vector3d(0.01 * k, 0.004 * k, -0.6 + 0.002 * k) +
                     0.3e-3 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
  const LineStraightness s = lineStraightness("L1", points, {});
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p / 21.0;
  Eigen::MatrixXd centred(21, 3);
  for (int k = 0; k < 21; ++k) centred.row(k) = (points[static_cast<std::size_t>(k)] - centroid).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  const Eigen::Vector3d axis = svd.matrixV().col(0);
  double sum = 0, largest = 0;
  for (int k = 0; k < 21; ++k) {
    const Eigen::Vector3d r = centred.row(k).transpose();
    const double d = (r - r.dot(axis) * axis).norm();
    sum += d * d;
    largest = std::max(largest, d);
  }
  EXPECT_NEAR(s.rms, std::sqrt(sum / 21.0), 1e-9);
  EXPECT_NEAR(s.max, largest, 1e-9);
  EXPECT_THROW(lineStraightness("short", {points[0], points[1]}, {}), std::invalid_argument);

  // The noise-only part: a perfectly straight line seen through 0.3 mm noise is not resolved.
  const std::vector<Eigen::Matrix3d> covariances(21, Eigen::Matrix3d::Identity() * 0.09e-6);
  const LineStraightness noisy = lineStraightness("L1", points, covariances);
  EXPECT_NEAR(noisy.noise_rms.mean, s.rms, 0.35 * s.rms);  // the points are that noise
  EXPECT_FALSE(noisy.warnings.empty());
}

// Known truth: the figures of the measured cycles against the same figures of the true attained
// poses, over 50 repetitions: within 3σ, and error/σ with a spread of 1.
TEST(PoseAccuracy, SigmaMatchesTheSpreadAgainstKnownTruth) {
  const IsoPoseCovariance noise = measurementNoise();
  AccuracyOptions options;
  options.noise_draws = 100;
  std::vector<double> z_xyz, z_abc, z_p, z_ad;
  double worst = 0.0;
  for (unsigned rep = 0; rep < 50; ++rep) {
    const Cycles c = simulateCycles(100 + rep, 30, 0.8e-3, 0.1e-3, noise);
    const auto measured = poseAccuracy(c.measured, options);
    const auto truth = poseAccuracy(c.truth, options);
    const auto dm = distanceAccuracy(c.measured, options);
    const auto dt = distanceAccuracy(c.truth, options);
    for (std::size_t p = 0; p < measured.size(); ++p) {
      for (int k = 0; k < 3; ++k) {
        z_xyz.push_back((measured[p].ap_xyz[k] - truth[p].ap_xyz[k]) / measured[p].sigma_ap_xyz[k]);
        z_abc.push_back((measured[p].ap_abc[k] - truth[p].ap_abc[k]) / measured[p].sigma_ap_abc[k]);
      }
      z_p.push_back((measured[p].ap_p - truth[p].ap_p) / measured[p].sigma_ap_p);
      worst = std::max(worst, std::abs(z_p.back()));
    }
    for (std::size_t k = 0; k < dm.size(); ++k) z_ad.push_back((dm[k].ad_p - dt[k].ad_p) / dm[k].sigma_ad_p);
  }
  const auto spread = [](const std::vector<double>& z) {
    double s = 0;
    for (double v : z) s += v * v;
    return std::sqrt(s / static_cast<double>(z.size()));
  };
  std::printf(
      "ISO 9283 sigma vs known truth, 50 repetitions x 5 positions: rms(err/sigma) AP_xyz %.3f, AP_abc %.3f, "
      "AP_p %.3f (max |z| %.2f), AD_p %.3f\n",
      spread(z_xyz), spread(z_abc), spread(z_p), worst, spread(z_ad));
  for (const auto* z : {&z_xyz, &z_abc, &z_p, &z_ad}) {
    EXPECT_GT(spread(*z), 0.8);
    EXPECT_LT(spread(*z), 1.25);
  }
  EXPECT_LT(worst, 3.5);  // 250 draws: a 3σ excursion is expected about once; 3.5σ is not
  int beyond3 = 0;
  for (double v : z_p) beyond3 += std::abs(v) > 3.0;
  EXPECT_LE(beyond3, 3);
}

// A perfectly repeatable robot seen through the noise: RP is the noise's, and flagged; a robot
// whose scatter is 10× the noise is not.
TEST(PoseAccuracy, RepeatabilityBelowTheNoiseIsFlagged) {
  const IsoPoseCovariance noise = measurementNoise();
  int flagged = 0, total = 0;
  for (unsigned rep = 0; rep < 10; ++rep) {
    const Cycles c = simulateCycles(500 + rep, 30, 0.8e-3, 0.0, noise);
    for (const PositionAccuracy& p : poseAccuracy(c.measured)) {
      ++total;
      EXPECT_NEAR(p.rp_l, p.noise_rp_l.mean, 0.35 * p.noise_rp_l.mean);
      for (const auto& w : p.warnings) flagged += w.rfind("RP_l", 0) == 0;
    }
  }
  EXPECT_GE(flagged, total * 8 / 10);
  const Cycles loose = simulateCycles(600, 30, 0.8e-3, 3e-3, noise);
  for (const PositionAccuracy& p : poseAccuracy(loose.measured)) {
    for (const auto& w : p.warnings) EXPECT_NE(w.rfind("RP_l", 0), 0u) << w;
    EXPECT_GT(p.rp_l, 2.0 * p.noise_rp_l.p95);
  }
}

TEST(PoseAccuracy, AttainedPoseCovarianceMatchesItsSpread) {
  const Eigen::Isometry3d cTb = pose({0.03, -0.02, 1.9}, 3.1, 0.05, -0.3);
  const Eigen::Isometry3d eTm = pose({0.012, -0.008, 0.005}, 0.1, 3.0, 0.2);
  const Eigen::Isometry3d bTe = pose({0.05, 0.02, -0.6}, 0.01, -0.02, 0.4);
  const PoseVector cTm = toPoseVector(cTb * bTe * eTm);
  PoseCovariance cov = PoseCovariance::Zero();
  cov.diagonal() << 4e-8, 4e-8, 9e-8, 3e-7, 3e-7, 2e-7;
  const AttainedPose a = attainedPose(cTb, eTm, cTm, cov);
  EXPECT_LT((a.bTe.matrix() - bTe.matrix()).norm(), 1e-12);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  IsoPoseCovariance sample = IsoPoseCovariance::Zero();
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    PoseVector x = cTm;
    for (int i = 0; i < 6; ++i) x[i] += std::sqrt(cov(i, i)) * normal(rng);
    const IsoPose d = isoDeviation(bTe, attainedPose(cTb, eTm, x, std::nullopt).bTe);
    sample += d * d.transpose() / n;
  }
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(std::sqrt(sample(i, i) / a.covariance(i, i)), 1.0, 0.06) << i;
  EXPECT_EQ(attainedPose(cTb, eTm, cTm, std::nullopt).covariance, IsoPoseCovariance::Zero());
}

TEST(PoseAccuracy, BadCyclesAreNamed) {
  Cycles c = simulateCycles(9, 2, 1e-3, 1e-4, measurementNoise());
  std::vector<AccuracySample> one(c.measured.begin(), c.measured.begin() + 5);
  try {
    poseAccuracy(one);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("position 'P1' has 1 cycle"), std::string::npos) << e.what();
  }
  c.measured[7].commanded.translation().x() += 1e-3;
  try {
    poseAccuracy(c.measured);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pose 'P3_2'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mire::mechanism
