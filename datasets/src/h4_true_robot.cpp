// The simulated true H4 (see h4_true_robot.hpp for the physical model).
#include "mire/datasets/h4_true_robot.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mire/mechanism/io.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/yaml.hpp"

namespace mire::datasets {

namespace {

template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

// Columns of Rz(ψ)·Rx(β): the arm direction is V = −cosφ·e1 − sinφ·e2 (eq. 17), the arm
// rotation axis is e3.
struct ArmFrame {
  Eigen::Vector3d e1, e2, e3;
};

ArmFrame armFrame(const H4TrueLeg& leg) {
  const Eigen::Matrix3d m =
      (Eigen::AngleAxisd(leg.psi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(leg.beta, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return {m.col(0), m.col(1), m.col(2)};
}

// Nacelle offset of attachment i before tilt: ε·h·(cosθ, sinθ, 0) + σ·d·(0,1,0) (doc/mechanisms.md, "H4
// model 12").
template <typename T>
Vec3<T> nacelleOffset(const H4TrueGeometry& g, int leg, const T& theta) {
  using std::cos;
  using std::sin;
  const double eps = mechanism::kH4Epsilon[leg], sig = mechanism::kH4Sigma[leg];
  return Vec3<T>(eps * g.h * cos(theta), eps * g.h * sin(theta) + T(sig * g.d), T(0.0));
}

// Arm angle φ solving ‖A − P − L·V(φ)‖ = l, elbow-out branch (doc/mechanisms.md, "H4 model 12", general axis):
// with w = A − P, a = −w·e1, b = −w·e2, c = (L² + ‖w‖² − l²)/(2L): a cosφ + b sinφ = c.
// Returns false when |c| > ρ (unreachable). `clamp` keeps the result finite for the tilt model.
template <typename T>
bool armAngle(const H4TrueLeg& leg, const ArmFrame& frame, const Vec3<T>& attachment, bool clamp, T* phi) {
  using std::acos;
  using std::atan2;
  using std::sqrt;
  const Vec3<T> w = attachment - leg.pivot.cast<T>();
  const T a = -w.dot(frame.e1.cast<T>());
  const T b = -w.dot(frame.e2.cast<T>());
  const double L = leg.arm_length, l = leg.forearm_length;
  const T c = (T(L * L - l * l) + w.squaredNorm()) / T(2.0 * L);
  const T rho = sqrt(a * a + b * b);
  T ratio = c / rho;
  if (ratio > T(1.0) || ratio < T(-1.0)) {
    if (!clamp) return false;
    ratio = ratio > T(1.0) ? T(1.0 - 1e-12) : T(-1.0 + 1e-12);
  }
  *phi = atan2(b, a) - acos(ratio);
  return true;
}

template <typename T>
Vec3<T> elbow(const H4TrueLeg& leg, const ArmFrame& frame, const T& phi) {
  using std::cos;
  using std::sin;
  return leg.pivot.cast<T>() + T(leg.arm_length) * (-cos(phi) * frame.e1.cast<T>() - sin(phi) * frame.e2.cast<T>());
}

// ω(X): mean over the legs of (δ_i/s)·n_i, n_i = e3_i × f_i normalised, horizontal part only;
// evaluated at the untilted configuration (see the header).
template <typename T>
Vec3<T> rawTiltVector(const H4TrueGeometry& g, const std::array<ArmFrame, 4>& frames, const T* pose) {
  const Vec3<T> centre(pose[0], pose[1], pose[2]);
  Vec3<T> omega = Vec3<T>::Zero();
  for (int i = 0; i < 4; ++i) {
    const H4TrueLeg& leg = g.legs[i];
    if (leg.bar_mismatch == 0.0) continue;
    const Vec3<T> attachment = centre + nacelleOffset(g, i, pose[3]);
    T phi;
    armAngle(leg, frames[i], attachment, /*clamp=*/true, &phi);
    const Vec3<T> forearm = (attachment - elbow(leg, frames[i], phi)).normalized();
    const Vec3<T> normal = frames[i].e3.cast<T>().cross(forearm).normalized();
    omega += T(0.25 * leg.bar_mismatch / g.bar_spacing) * normal;
  }
  omega.z() = T(0.0);
  return omega;
}

template <typename T>
Vec3<T> tiltVector(const H4TrueGeometry& g, const std::array<ArmFrame, 4>& frames, const T* pose) {
  const Eigen::Vector3d level = rawTiltVector(g, frames, g.level_pose.data());
  return rawTiltVector(g, frames, pose) - level.cast<T>();
}

template <typename T>
std::array<Vec3<T>, 4> attachments(const H4TrueGeometry& g, const std::array<ArmFrame, 4>& frames, const T* pose) {
  const Vec3<T> omega = tiltVector(g, frames, pose);
  const Vec3<T> centre(pose[0], pose[1], pose[2]);
  std::array<Vec3<T>, 4> points;
  for (int i = 0; i < 4; ++i) {
    const Vec3<T> offset = nacelleOffset(g, i, pose[3]);
    Vec3<T> rotated;
    ceres::AngleAxisRotatePoint(omega.data(), offset.data(), rotated.data());
    points[i] = centre + rotated;
  }
  return points;
}

std::array<ArmFrame, 4> armFrames(const H4TrueGeometry& g) {
  std::array<ArmFrame, 4> frames;
  for (int i = 0; i < 4; ++i) frames[i] = armFrame(g.legs[i]);
  return frames;
}

// FKM residual: forearm centre-line lengths ‖A_i(X) − B_i‖ − l_i (m).
struct ForearmClosure {
  const H4TrueGeometry* geometry;
  const std::array<ArmFrame, 4>* frames;
  std::array<Eigen::Vector3d, 4> elbows;

  template <typename T>
  bool operator()(const T* pose, T* residuals) const {
    const auto points = attachments(*geometry, *frames, pose);
    for (int i = 0; i < 4; ++i)
      residuals[i] = (points[i] - elbows[i].cast<T>()).norm() - T(geometry->legs[i].forearm_length);
    return true;
  }
};

double wrapAngle(double angle) { return std::remainder(angle, 2.0 * kH4Pi); }

Eigen::Isometry3d makeIsometry(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = rotation;
  t.translation() = translation;
  return t;
}

}  // namespace

H4TrueGeometry geometryFromModel12(const H4Model12Values& v) {
  H4TrueGeometry g;
  g.h = v.h;
  g.d = v.d;
  g.rotation_ratio = v.amplification;
  for (int i = 0; i < 4; ++i) {
    H4TrueLeg& leg = g.legs[i];
    // P_i = A_i(0) + R·(cos α_i, sin α_i, 0); model 12 is ψ_i = α_i + π, β_i = π/2 (eq. 17).
    leg.pivot = Eigen::Vector3d(mechanism::kH4Epsilon[i] * v.h, mechanism::kH4Sigma[i] * v.d, 0.0) +
                v.R * Eigen::Vector3d(std::cos(v.alpha[i]), std::sin(v.alpha[i]), 0.0);
    leg.psi = v.alpha[i] + kH4Pi;
    leg.beta = 0.5 * kH4Pi;
    leg.arm_length = v.L;
    leg.forearm_length = v.l;
    leg.joint_offset = v.q0[i];
    leg.bar_mismatch = 0.0;
  }
  return g;
}

H4Model12Values drawModel12Values(const H4Model12Values& nominal, const H4ErrorSizes& sizes, std::uint64_t seed) {
  std::mt19937_64 model12_rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  H4Model12Values v = nominal;
  v.R += sizes.length_m * normal(model12_rng);
  v.L += sizes.length_m * normal(model12_rng);
  v.l += sizes.length_m * normal(model12_rng);
  v.h += sizes.length_m * normal(model12_rng);
  for (int i = 0; i < 4; ++i) v.alpha[i] += sizes.angle_rad * normal(model12_rng);
  for (int i = 0; i < 4; ++i) v.q0[i] += sizes.joint_offset_rad * normal(model12_rng);
  return v;
}

H4TrueGeometry makeTrueGeometry(const H4Model12Values& nominal, const H4ErrorSizes& sizes, std::uint64_t seed) {
  std::normal_distribution<double> normal(0.0, 1.0);
  H4TrueGeometry g = geometryFromModel12(drawModel12Values(nominal, sizes, seed));

  // A separate stream, so the model-12 part does not depend on the unmodelled sizes.
  std::mt19937_64 defect_rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::uniform_real_distribution<double> magnitude(0.75, 1.25);
  for (int i = 0; i < 4; ++i) {
    H4TrueLeg& leg = g.legs[i];
    leg.arm_length += sizes.leg_length_m * normal(defect_rng);
    leg.forearm_length += sizes.leg_length_m * normal(defect_rng);
    leg.pivot.z() += sizes.pivot_height_m * normal(defect_rng);
    leg.psi += sizes.axis_tilt_rad * normal(defect_rng);
    leg.beta += sizes.axis_tilt_rad * normal(defect_rng);
    // Bar mismatch of fixed size and random sign: a Gaussian draw could make the tilt vanish
    // by chance, and the tests need the ≈0.1° defect to be there.
    const double sign = (defect_rng() & 1U) ? 1.0 : -1.0;
    leg.bar_mismatch = sign * sizes.bar_mismatch_m * magnitude(defect_rng);
  }
  return g;
}

std::string trueGeometryYaml(const H4TrueGeometry& geometry) {
  const auto n = [](double value) { return support::formatYamlNumber(value); };
  std::ostringstream out;
  out << "h: " << n(geometry.h) << "\nd: " << n(geometry.d) << "\nbar_spacing: " << n(geometry.bar_spacing)
      << "\nrotation_ratio: " << n(geometry.rotation_ratio) << "\nlegs:\n";
  for (const auto& leg : geometry.legs) {
    out << "  - { pivot: [" << n(leg.pivot.x()) << ", " << n(leg.pivot.y()) << ", " << n(leg.pivot.z())
        << "], psi: " << n(leg.psi) << ", beta: " << n(leg.beta) << ", L: " << n(leg.arm_length)
        << ", l: " << n(leg.forearm_length) << ", q0: " << n(leg.joint_offset)
        << ", bar_mismatch: " << n(leg.bar_mismatch) << " }\n";
  }
  return out.str();
}

Eigen::Isometry3d defaultBaseTCamera() {
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(25.0 * kH4Degree, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(1.5 * kH4Degree, Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(-1.0 * kH4Degree, Eigen::Vector3d::UnitY()))
                                       .toRotationMatrix();
  return makeIsometry(rotation, Eigen::Vector3d(0.03, -0.02, -1.46));
}

Eigen::Isometry3d defaultMarkerTEffector() {
  // Effector origin expressed in M: the board's first feature sits at (−88, −64, −40) mm from
  // the effector in E, i.e. the 12 x 9 x 16 mm board of specs/target_h4.yaml is centred under the effector, 40 mm below it.
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(10.0 * kH4Degree, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return makeIsometry(rotation, Eigen::Vector3d(0.088, 0.064, 0.04));
}

H4TrueKinematics::H4TrueKinematics(H4TrueGeometry geometry, const Eigen::Isometry3d& base_T_camera,
                                   const Eigen::Isometry3d& marker_T_effector)
    : geometry_(std::move(geometry)), base_T_camera_(base_T_camera), marker_T_effector_(marker_T_effector) {}

Eigen::Vector3d H4TrueKinematics::tilt(const H4Pose& pose) const {
  return tiltVector(geometry_, armFrames(geometry_), pose.data());
}

std::array<Eigen::Vector3d, 4> H4TrueKinematics::attachmentPoints(const H4Pose& pose) const {
  return attachments(geometry_, armFrames(geometry_), pose.data());
}

Eigen::Isometry3d H4TrueKinematics::baseTEffector(const H4Pose& pose) const {
  const Eigen::Vector3d omega = tilt(pose);
  Eigen::Matrix3d tilt_rotation = Eigen::Matrix3d::Identity();
  if (omega.norm() > 0.0) tilt_rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  const Eigen::Matrix3d rotation =
      tilt_rotation * Eigen::AngleAxisd(geometry_.rotation_ratio * pose[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return makeIsometry(rotation, pose.head<3>());
}

Eigen::Isometry3d H4TrueKinematics::cameraTMarker(const H4Pose& pose) const {
  return base_T_camera_.inverse() * baseTEffector(pose) * marker_T_effector_.inverse();
}

std::optional<H4Joints> H4TrueKinematics::joints(const H4Pose& pose) const {
  const auto frames = armFrames(geometry_);
  const auto points = attachments(geometry_, frames, pose.data());
  H4Joints q;
  for (int i = 0; i < 4; ++i) {
    double phi = 0.0;
    if (!armAngle(geometry_.legs[i], frames[i], points[i], /*clamp=*/false, &phi)) return std::nullopt;
    q[i] = wrapAngle(phi - geometry_.legs[i].joint_offset);
  }
  return q;
}

std::optional<H4Joints> H4TrueKinematics::joints(const H4Pose& pose, double noise_rad, std::mt19937_64& rng) const {
  auto q = joints(pose);
  if (!q || noise_rad <= 0.0) return q;
  std::normal_distribution<double> normal(0.0, noise_rad);
  for (int i = 0; i < 4; ++i) (*q)[i] += normal(rng);
  return q;
}

std::array<Eigen::Vector3d, 4> H4TrueKinematics::elbows(const H4Joints& q) const {
  const auto frames = armFrames(geometry_);
  std::array<Eigen::Vector3d, 4> points;
  for (int i = 0; i < 4; ++i) points[i] = elbow(geometry_.legs[i], frames[i], q[i] + geometry_.legs[i].joint_offset);
  return points;
}

std::optional<H4Pose> H4TrueKinematics::pose(const H4Joints& q, const H4Pose& guess) const {
  const auto frames = armFrames(geometry_);
  auto* closure = new ForearmClosure{&geometry_, &frames, elbows(q)};
  H4Pose x = guess;
  ceres::Problem problem;  // takes ownership of the cost function
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ForearmClosure, 4, 4>(closure), nullptr, x.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-20;
  options.gradient_tolerance = 1e-20;
  options.parameter_tolerance = 1e-15;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  double residuals[4];
  (*closure)(x.data(), residuals);
  for (double r : residuals)
    if (!std::isfinite(r) || std::abs(r) > 1e-10) return std::nullopt;
  return x;
}

std::optional<Eigen::Isometry3d> H4TrueKinematics::baseTEffector(const H4Joints& q, const H4Pose& guess) const {
  const auto x = pose(q, guess);
  if (!x) return std::nullopt;
  return baseTEffector(*x);
}

std::vector<H4Pose> protocolPoses(const H4ProtocolGrid& grid) {
  std::vector<H4Pose> poses;
  poses.reserve(81);
  for (int iz = -1; iz <= 1; ++iz)
    for (int iy = -1; iy <= 1; ++iy)
      for (int ix = -1; ix <= 1; ++ix)
        for (double theta : grid.thetas) {
          const Eigen::Vector3d p =
              grid.centre + 0.5 * Eigen::Vector3d(ix * grid.extent.x(), iy * grid.extent.y(), iz * grid.extent.z());
          poses.emplace_back(p.x(), p.y(), p.z(), theta);
        }
  return poses;
}

std::array<std::vector<H4Pose>, 2> straightLineMotions(const H4ProtocolGrid& grid, int points) {
  if (points < 3) throw std::invalid_argument("straightLineMotions: need at least 3 points per line");
  const Eigen::Vector3d half_x(0.5 * grid.extent.x(), 0.0, 0.0);
  const Eigen::Vector3d half_diagonal = 0.5 * grid.extent;
  const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 2> ends{
      std::make_pair(grid.centre - half_x, grid.centre + half_x),
      std::make_pair(grid.centre - half_diagonal, grid.centre + half_diagonal)};
  std::array<std::vector<H4Pose>, 2> lines;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < points; ++j) {
      const double s = static_cast<double>(j) / (points - 1);
      const Eigen::Vector3d p = (1.0 - s) * ends[k].first + s * ends[k].second;
      lines[k].emplace_back(p.x(), p.y(), p.z(), 0.0);
    }
  return lines;
}

std::vector<H4Joints> recordJoints(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses, double noise_rad,
                                   std::mt19937_64& rng) {
  std::vector<H4Joints> joints;
  joints.reserve(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const auto q = robot.joints(poses[k], noise_rad, rng);
    if (!q) throw std::runtime_error("recordJoints: pose " + std::to_string(k) + " is out of reach");
    joints.push_back(*q);
  }
  return joints;
}

SquareTestResult squareTest(const H4TrueKinematics& robot, const CommandIkm& command_ikm, const Eigen::Vector3d& centre,
                            double side) {
  SquareTestResult result;
  const double half = 0.5 * side;
  const std::array<Eigen::Vector2d, 4> corners{Eigen::Vector2d(-half, -half), Eigen::Vector2d(half, -half),
                                               Eigen::Vector2d(half, half), Eigen::Vector2d(-half, half)};
  for (int k = 0; k < 4; ++k) {
    result.commanded[k] = H4Pose(centre.x() + corners[k].x(), centre.y() + corners[k].y(), centre.z(), 0.0);
    const auto q = command_ikm(result.commanded[k]);
    if (!q) throw std::runtime_error("squareTest: the control model cannot reach corner " + std::to_string(k + 1));
    const auto reached = robot.pose(*q, result.commanded[k]);
    if (!reached)
      throw std::runtime_error("squareTest: the true robot's FKM failed at corner " + std::to_string(k + 1));
    result.reached[k] = *reached;
  }
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = result.reached[k].head<2>(), b = result.reached[(k + 1) % 4].head<2>();
    result.side_error_m[k] = (b - a).norm() - side;
    result.max_abs_error_m = std::max(result.max_abs_error_m, std::abs(result.side_error_m[k]));
  }
  return result;
}

Eigen::Isometry3d perturbPose(const Eigen::Isometry3d& pose, const H4MeasurementNoise& noise, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d dt, dr;
  for (int k = 0; k < 3; ++k) dt[k] = noise.translation_m * normal(rng);
  for (int k = 0; k < 3; ++k) dr[k] = noise.rotation_rad * normal(rng);
  Eigen::Isometry3d noisy = pose;
  noisy.translation() += dt;
  if (dr.norm() > 0.0)
    noisy.linear() = pose.linear() * Eigen::AngleAxisd(dr.norm(), dr.normalized()).toRotationMatrix();
  return noisy;
}

std::vector<H4SimulatedMeasurement> simulateMeasurements(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses,
                                                         const H4MeasurementNoise& noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<H4SimulatedMeasurement> out;
  out.reserve(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    H4SimulatedMeasurement m;
    m.pose_id = static_cast<int>(k) + 1;
    m.true_pose = poses[k];
    m.camera_T_marker = perturbPose(robot.cameraTMarker(poses[k]), noise, rng);
    const auto q = robot.joints(poses[k], noise.encoder_rad, rng);
    if (!q) throw std::runtime_error("simulateMeasurements: pose " + std::to_string(k + 1) + " is out of reach");
    m.joints = *q;
    out.push_back(m);
  }
  return out;
}

std::vector<mechanism::PoseObservation> toObservations(const std::vector<H4SimulatedMeasurement>& measurements,
                                                       const H4MeasurementNoise& noise) {
  std::vector<mechanism::PoseObservation> poses;
  mechanism::PoseCovariance covariance = mechanism::PoseCovariance::Zero();
  const double st = noise.translation_m * noise.translation_m, sr = noise.rotation_rad * noise.rotation_rad;
  covariance.diagonal() << st, st, st, sr, sr, sr;
  for (const auto& m : measurements) {
    mechanism::PoseObservation p;
    p.id = std::to_string(m.pose_id);
    p.cTm = mechanism::toPoseVector(m.camera_T_marker);
    p.joints = m.joints;
    if (st > 0.0 && sr > 0.0) p.covariance = covariance;
    poses.push_back(std::move(p));
  }
  return poses;
}

void writeSimulatedCampaign(const std::filesystem::path& dir, const std::vector<H4SimulatedMeasurement>& measurements,
                            const H4MeasurementNoise& noise, const std::vector<std::vector<H4Joints>>& lines) {
  std::filesystem::create_directories(dir);
  const auto poses = toObservations(measurements, noise);
  std::ostringstream out;
  out << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,"
         "sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  const std::string st = support::formatNumber(noise.translation_m * 1e3, 6);
  const std::string sr = support::formatNumber(noise.rotation_rad / kH4Degree, 6);
  std::vector<std::string> ids;
  std::vector<Eigen::VectorXd> joints;
  for (const auto& p : poses) {
    out << p.id << ",10,10";
    for (int k = 0; k < 6; ++k) out << ',' << support::formatNumber(p.cTm[k]);
    out << ',' << st << ',' << st << ',' << st << ',' << sr << ',' << sr << ',' << sr << ",0\n";
    ids.push_back(p.id);
    joints.push_back(p.joints);
  }
  support::writeFileAtomically(dir / "poses.csv", out.str());
  mechanism::writeJointsCsv(dir / "joints.csv", ids, joints);
  if (!lines.empty()) {
    std::vector<mechanism::LineRecord> records;
    for (std::size_t k = 0; k < lines.size(); ++k) {
      mechanism::LineRecord record{std::to_string(k + 1), {}};
      for (const auto& q : lines[k]) record.joints.emplace_back(q);
      records.push_back(std::move(record));
    }
    mechanism::writeLinesCsv(dir / "lines.csv", records);
  }
}

double smallestImageMargin(const H4TrueKinematics& robot, const std::vector<H4Pose>& poses,
                           const std::vector<Eigen::Vector3d>& marker_points, int width, int height, double focal_px) {
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  double margin = std::numeric_limits<double>::infinity();
  for (const H4Pose& pose : poses) {
    const Eigen::Isometry3d c_T_m = robot.cameraTMarker(pose);
    for (const Eigen::Vector3d& point : marker_points) {
      const Eigen::Vector3d p = c_T_m * point;
      if (p.z() <= 0.0) return -std::numeric_limits<double>::infinity();
      const double u = focal_px * p.x() / p.z() + cx, v = focal_px * p.y() / p.z() + cy;
      margin = std::min({margin, u, (width - 1) - u, v, (height - 1) - v});
    }
  }
  return margin;
}

}  // namespace mire::datasets
