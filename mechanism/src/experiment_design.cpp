// Experiment design, part 1: workspace, candidate poses, and the Fisher information of every
// candidate as the identification sees it (doc/plan-and-select.md). The exchange algorithm and
// the report are in experiment_design_exchange.cpp.
#include "mire/mechanism/experiment_design.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/mechanism/variants.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {
namespace {

using support::kPi;
// Rotations are compared with translations through this length (a lever arm of the size of
// the effector) in the singularity guard.
constexpr double kRotationScale = 0.1;

int rotationCount(const Mechanism& mechanism) { return mechanism.poseDof() - 3; }

// ∂q/∂X by central differences of the IKM; empty when a neighbour is unreachable.
Eigen::MatrixXd ikmPoseJacobian(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                const Eigen::VectorXd& pose, double step = 1e-6) {
  Eigen::MatrixXd J(mechanism.jointCount(), pose.size());
  for (Eigen::Index k = 0; k < pose.size(); ++k) {
    Eigen::VectorXd a = pose, b = pose;
    a[k] += step;
    b[k] -= step;
    const IkmResult qa = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(a));
    const IkmResult qb = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(b));
    if (!qa.reachable() || !qb.reachable()) return {};
    J.col(k) = (qa.joints - qb.joints) / (2.0 * step);
  }
  return J;
}

Eigen::Isometry3d transformOf(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = fromRotationVector(rotation_vector);
  T.translation() = t;
  return T;
}

}  // namespace

IdentificationModel initialModelFor(const DesignModel& model, const std::vector<PoseObservation>& observations) {
  const RegisteredModel& r = model.registered;
  IdentificationModel out;
  // The camera-frame model starts from its default variant's preset (paper eq. 25-26).
  if (r.external_form == ExternalForm::CameraFrame) {
    out = makeH4VariantModel(modelInfo(r.name).default_variant, model.h4, observations);
  } else {
    out = makeInitialModel(r.mechanism, r.nominal, observations, r.external_form);
  }
  fixGauge(out, observations);
  return out;
}

DesignModel makeDesignModel(const std::string& name, const H4Nominal& h4) {
  DesignModel m;
  m.h4 = h4;
  m.registered = makeRegisteredModel(name, h4);
  return m;
}

DesignModel withCameraOnEffector(DesignModel model) {
  const ExternalForm form = model.registered.external_form;
  if (form != ExternalForm::Full)
    throw std::invalid_argument(model.registered.name + " (" + externalFormName(form) +
                                " mounting) assumes the camera fixed (paper §4)");
  model.registered.external_form = ExternalForm::CameraOnEffector;
  return model;
}

Workspace protocolWorkspace(const Mechanism& mechanism, const Eigen::VectorXd& geometric) {
  const Eigen::VectorXd ref = mechanism.referencePose(geometric);
  const double deg = kPi / 180.0;
  Workspace w;
  switch (mechanism.motionType()) {
    case MotionType::Schoenflies:
      w.x = {ref[0] - 0.1, ref[0] + 0.1};
      w.y = {ref[1] - 0.1, ref[1] + 0.1};
      w.z = {ref[2] - 0.075, ref[2] + 0.075};
      w.rotations = {{-20 * deg, 20 * deg}};
      w.joint_margin = 1 * deg;
      break;
    case MotionType::Translation:
      w.x = {-0.15, 0.15};
      w.y = {-0.15, 0.15};
      w.z = {-0.725, -0.575};
      w.joint_margin = 1 * deg;
      break;
    case MotionType::Spatial:
      w.x = {ref[0] - 0.04, ref[0] + 0.04};
      w.y = {ref[1] - 0.04, ref[1] + 0.04};
      w.z = {ref[2] - 0.03, ref[2] + 0.03};
      w.rotations = {{-6 * deg, 6 * deg}, {-6 * deg, 6 * deg}, {-6 * deg, 6 * deg}};
      w.joint_margin = 1e-3;
      break;
  }
  return w;
}

void validateWorkspace(const Workspace& w, const Mechanism& mechanism) {
  const auto check = [](const Interval& i, const std::string& name) {
    if (!(std::isfinite(i.min) && std::isfinite(i.max) && i.max >= i.min))
      throw std::invalid_argument("workspace: " + name + " needs finite [min, max] with min <= max");
  };
  check(w.x, "x_m");
  check(w.y, "y_m");
  check(w.z, "z_m");
  if (static_cast<int>(w.rotations.size()) != rotationCount(mechanism))
    throw std::invalid_argument("workspace: " + mechanism.name() + " has " + std::to_string(rotationCount(mechanism)) +
                                " rotation range(s), the workspace gives " + std::to_string(w.rotations.size()));
  for (const Interval& i : w.rotations) check(i, "rotation");
  if (!(w.joint_margin >= 0.0 && std::isfinite(w.joint_margin)))
    throw std::invalid_argument("workspace: the joint margin must be >= 0");
}

bool candidateAcceptable(const Mechanism& mechanism, const Eigen::VectorXd& geometric, const Workspace& w,
                         const Eigen::VectorXd& pose) {
  // A pose the robot cannot assemble, or that drives a joint past its declared stroke (the
  // hexapod's legs, a description's `stroke`), is never proposed.
  const auto inReach = [&](const Eigen::VectorXd& at) {
    const IkmResult ikm = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(at));
    return ikm.reachable() && ikm.withinStroke();
  };
  if (!inReach(pose)) return false;
  const Eigen::MatrixXd J = ikmPoseJacobian(mechanism, geometric, pose);
  if (J.size() == 0 || !J.allFinite()) return false;
  // Serial-singularity / reach margin: one margin of joint motion away in every direction.
  if (w.joint_margin > 0.0) {
    for (Eigen::Index k = 0; k < pose.size(); ++k) {
      const double rate = J.col(k).cwiseAbs().maxCoeff();
      if (rate <= 0.0) continue;
      const double step = w.joint_margin / rate;
      for (const double s : {-step, step}) {
        Eigen::VectorXd moved = pose;
        moved[k] += s;
        if (!inReach(moved)) return false;
      }
    }
  }
  // Parallel-singularity guard on the conditioning of ∂q/∂X.
  Eigen::MatrixXd scaled = J;
  for (Eigen::Index k = 3; k < scaled.cols(); ++k) scaled.col(k) /= kRotationScale;
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(scaled).singularValues();
  return s.size() > 0 && s[s.size() - 1] >= w.min_jacobian_ratio * s[0];
}

std::vector<Eigen::VectorXd> generateCandidatePoses(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                    const Workspace& w, int count, unsigned seed) {
  validateWorkspace(w, mechanism);
  if (count < 1) throw std::invalid_argument("candidate count must be >= 1");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto draw = [&](const Interval& i) { return i.min + u(rng) * i.width(); };
  std::vector<Eigen::VectorXd> out;
  const long attempts = 50L * count;
  for (long a = 0; a < attempts && static_cast<int>(out.size()) < count; ++a) {
    Eigen::VectorXd pose(mechanism.poseDof());
    pose[0] = draw(w.x);
    pose[1] = draw(w.y);
    pose[2] = draw(w.z);
    for (std::size_t k = 0; k < w.rotations.size(); ++k) pose[3 + static_cast<Eigen::Index>(k)] = draw(w.rotations[k]);
    if (w.shape == Workspace::Shape::Cylinder) {
      const double radius = 0.5 * std::min(w.x.width(), w.y.width());
      if (std::hypot(pose[0] - w.x.centre(), pose[1] - w.y.centre()) > radius) continue;
    }
    if (candidateAcceptable(mechanism, geometric, w, pose)) out.push_back(pose);
  }
  if (static_cast<int>(out.size()) < count)
    throw std::runtime_error("only " + std::to_string(out.size()) + " of " + std::to_string(count) +
                             " candidate poses are reachable with the margins in " + std::to_string(attempts) +
                             " draws: shrink the workspace or the margin");
  return out;
}

Eigen::Isometry3d MountingGuess::targetInCamera(const Eigen::Isometry3d& bTe) const {
  return camera_on_effector ? eTc.inverse() * bTe.inverse() * bTm : bTc.inverse() * bTe * mTe.inverse();
}

MountingGuess defaultMountingGuess(const Workspace& w, bool camera_on_effector) {
  MountingGuess m;
  const bool below = w.z.centre() < 0.0;  // the robot hangs from its base: the camera looks up
  const Eigen::Vector3d centre(w.x.centre(), w.y.centre(), below ? w.z.min - 0.8 : w.z.max + 0.8);
  // Camera z (optical axis) towards the workspace; the target faces the camera (its z away).
  m.bTc = transformOf(below ? Eigen::Vector3d::Zero() : Eigen::Vector3d(kPi, 0, 0), centre);
  m.mTe = transformOf(Eigen::Vector3d(kPi, 0, 0), Eigen::Vector3d::Zero());
  if (!below) m.mTe = Eigen::Isometry3d::Identity();
  if (!camera_on_effector) return m;
  // The fixed camera's view at the workspace centre (effector level), cTm0, kept: the camera
  // turned by a half turn about x rides at the effector origin and the target is placed where it
  // sees it so, bTm = bTe0 · eTc · cTm0 (as datasets::eyeInHandMounting places the demo's).
  const Eigen::Isometry3d bTe0 =
      transformOf(Eigen::Vector3d::Zero(), Eigen::Vector3d(w.x.centre(), w.y.centre(), w.z.centre()));
  const Eigen::Isometry3d cTm0 = m.targetInCamera(bTe0);
  m.camera_on_effector = true;
  m.eTc.linear() = fromRotationVector(Eigen::Vector3d(kPi, 0, 0)) * m.bTc.linear();
  m.bTm = bTe0 * m.eTc * cTm0;
  m.bTc = m.mTe = Eigen::Isometry3d::Identity();
  return m;
}

CandidateInformation candidateInformation(const DesignModel& model, const MountingGuess& mounting,
                                          const std::vector<Eigen::VectorXd>& poses, const DesignOptions& options,
                                          const PoseCovarianceProvider& covariance, const SharedTermModel& shared) {
  const RegisteredModel& r = model.registered;
  if ((r.external_form == ExternalForm::CameraOnEffector) != mounting.camera_on_effector)
    throw std::invalid_argument("candidateInformation: the model's mounting is " + mountingName(r.external_form) +
                                ", the guess's " + (mounting.camera_on_effector ? "camera-on-effector" : "camera-fixed"));
  const Mechanism& m = *r.mechanism;
  const Eigen::VectorXd g = r.nominal.values();
  CandidateInformation info;
  info.poses = poses;
  PoseCovariance fallback = PoseCovariance::Zero();
  fallback.diagonal() << Eigen::Vector3d::Constant(options.sigma_translation * options.sigma_translation),
      Eigen::Vector3d::Constant(options.sigma_rotation * options.sigma_rotation);
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Isometry3d bTe = m.poseToTransform(poses[j]);
    PoseObservation o;
    o.id = std::to_string(j + 1);
    o.joints = m.inverseKinematics(g, bTe).joints;
    o.cTm = toPoseVector(mounting.targetInCamera(bTe));
    std::optional<PoseCovariance> c = covariance ? covariance(o.cTm) : std::nullopt;
    o.covariance = c ? *c : fallback;
    info.observations.push_back(o);
  }
  // The mounting/gauge from a spread-out sample (every k-th candidate), as identify() does.
  std::vector<PoseObservation> sample;
  const std::size_t stride = std::max<std::size_t>(1, poses.size() / 150);
  for (std::size_t j = 0; j < poses.size(); j += stride) sample.push_back(info.observations[j]);
  // Noise-free data at the nominal geometry: the mounting values are exactly the guess's.
  info.model = initialModelFor(model, sample);
  info.free_names = info.model.parameters.freeNames();
  for (std::size_t i : info.model.parameters.freeIndices())
    if (static_cast<int>(i) < info.model.geometricCount()) ++info.geometric_free;

  // Whitened rows: W = L⁻¹ with Σq = Jx Σ_cTm Jxᵀ = L Lᵀ (identify()'s weighting).
  const Eigen::MatrixXd J = identificationJacobian(info.model, info.observations);
  const int nq = m.jointCount();
  const Eigen::VectorXd ge = info.model.geometricValues(), ee = info.model.externalValues();
  info.rows.reserve(poses.size());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const PoseObservation& o = info.observations[j];
    const Eigen::MatrixXd Jx = m.jointJacobianWrtPose(info.model.external, ge, ee, o.cTm);
    const Eigen::MatrixXd sq = Jx * (*o.covariance) * Jx.transpose();
    const Eigen::LLT<Eigen::MatrixXd> llt(sq);
    info.rows.emplace_back(llt.matrixL().solve(J.middleRows(static_cast<Eigen::Index>(j) * nq, nq)));
    if (shared.empty()) continue;
    const Eigen::MatrixXd D = shared.sensitivity(o.cTm);
    if (D.rows() != 6 || D.cols() != shared.covariance.rows())
      throw std::invalid_argument("shared term: the sensitivity of candidate " + o.id + " is " +
                                  std::to_string(D.rows()) + " x " + std::to_string(D.cols()) + ", expected 6 x " +
                                  std::to_string(shared.covariance.rows()));
    info.shared_rows.emplace_back(llt.matrixL().solve(Jx * D));
  }
  if (!shared.empty()) info.shared_covariance = shared.covariance;
  return info;
}

Eigen::MatrixXd fisherInformation(const CandidateInformation& info, const std::vector<int>& design) {
  const Eigen::Index p = static_cast<Eigen::Index>(info.free_names.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (int j : design)
    M.noalias() += info.rows.at(static_cast<std::size_t>(j)).transpose() * info.rows[static_cast<std::size_t>(j)];
  return M;
}

namespace {

// (Σ_j A_jᵀ A_j)⁻¹, a pseudo-inverse with C(0, 0) = +∞ when singular.
Eigen::MatrixXd informationInverse(const CandidateInformation& info, const std::vector<int>& design) {
  // An empty design has no information: its "covariance" would be a zero matrix with one inf.
  if (design.empty()) throw std::invalid_argument("the design is empty: choose at least one candidate pose");
  for (int j : design)
    if (j < 0 || static_cast<std::size_t>(j) >= info.rows.size())
      throw std::invalid_argument("design index " + std::to_string(j) + " is not a candidate (0.." +
                                  std::to_string(static_cast<long long>(info.rows.size()) - 1) + ")");
  const Eigen::MatrixXd M = fisherInformation(info, design);
  // Scale to unit diagonal so that mixed units do not fake a rank loss.
  Eigen::VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd S = d.asDiagonal() * M * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  const Eigen::VectorXd& l = eig.eigenvalues();
  Eigen::VectorXd inv(l.size());
  const double cut = 1e-12 * l.maxCoeff();
  bool singular = false;
  for (Eigen::Index k = 0; k < l.size(); ++k) {
    singular |= l[k] <= cut;
    inv[k] = l[k] > cut ? 1.0 / l[k] : 0.0;
  }
  Eigen::MatrixXd C =
      d.asDiagonal() * (eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose()) * d.asDiagonal();
  if (singular) C(0, 0) = std::numeric_limits<double>::infinity();  // marks the design as singular
  return C;
}

// The shared term's pieces for a design: G = H⁻¹ Σ_j A_jᵀ R_j and B = Σ_j A_jᵀ R_j Σ_k R_jᵀ A_j.
struct SharedPieces {
  Eigen::MatrixXd G, B;
};
SharedPieces sharedPieces(const CandidateInformation& info, const std::vector<int>& design,
                          const Eigen::MatrixXd& information_inverse) {
  const Eigen::Index p = information_inverse.rows(), n = info.shared_covariance.rows();
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(p, n);
  SharedPieces pieces{Eigen::MatrixXd(), Eigen::MatrixXd::Zero(p, p)};
  for (const int j : design) {
    const auto k = static_cast<std::size_t>(j);
    const Eigen::MatrixXd AtR = info.rows.at(k).transpose() * info.shared_rows.at(k);
    Q += AtR;
    pieces.B.noalias() += AtR * info.shared_covariance * AtR.transpose();
  }
  pieces.G = information_inverse * Q;
  return pieces;
}

}  // namespace

Eigen::MatrixXd designCovariance(const CandidateInformation& info, const std::vector<int>& design) {
  const Eigen::MatrixXd C = informationInverse(info, design);
  if (!info.hasSharedTerm() || !std::isfinite(C(0, 0))) return C;
  const SharedPieces s = sharedPieces(info, design, C);
  return C - C * s.B * C + s.G * info.shared_covariance * s.G.transpose();
}

Eigen::MatrixXd designSharedCovariance(const CandidateInformation& info, const std::vector<int>& design) {
  const Eigen::MatrixXd C = informationInverse(info, design);
  if (!info.hasSharedTerm() || !std::isfinite(C(0, 0))) return Eigen::MatrixXd::Zero(C.rows(), C.cols());
  const Eigen::MatrixXd G = sharedPieces(info, design, C).G;
  return G * info.shared_covariance * G.transpose();
}

Eigen::VectorXd designSigma(const CandidateInformation& info, const std::vector<int>& design) {
  const Eigen::MatrixXd C = designCovariance(info, design);
  if (!std::isfinite(C(0, 0))) return Eigen::VectorXd::Constant(C.rows(), std::numeric_limits<double>::infinity());
  return C.diagonal().cwiseMax(0.0).cwiseSqrt();
}

std::vector<double> predictedPositionSigma(const CandidateInformation& info, const Eigen::MatrixXd& covariance,
                                           const std::vector<int>& poses) {
  const Mechanism& m = *info.model.mechanism;
  const Eigen::VectorXd g = info.model.geometricValues();
  const int G = info.geometric_free;
  const Eigen::MatrixXd Cg = covariance.topLeftCorner(G, G);
  // Free geometric directions in the geometric values (ties move their whole group).
  const Eigen::MatrixXd E = info.model.parameters.expansion().topLeftCorner(g.size(), G);
  const Eigen::VectorXd ee = info.model.externalValues();
  std::vector<Eigen::MatrixXd> sensitivities;  // ∂X_position/∂ξg per pose
  std::vector<Eigen::Vector3d> positions;
  for (int j : poses) {
    // The pose in the model's own base frame (h4-31c's is the aligned camera frame).
    const PoseObservation& o = info.observations.at(static_cast<std::size_t>(j));
    const Eigen::Isometry3d bTe = info.model.external.effectorInBase(ee, o.cTm);
    const Eigen::VectorXd X = m.transformToPose(bTe);
    const Eigen::MatrixXd Jx = ikmPoseJacobian(m, g, X);
    if (Jx.size() == 0) continue;
    Eigen::MatrixXd Jg = Eigen::MatrixXd::Constant(m.jointCount(), G, std::numeric_limits<double>::quiet_NaN());
    for (int k = 0; k < G; ++k) {
      const double h = 1e-7;
      const IkmResult a = m.inverseKinematics(g + h * E.col(k), bTe), b = m.inverseKinematics(g - h * E.col(k), bTe);
      if (!a.reachable() || !b.reachable()) break;
      Jg.col(k) = (a.joints - b.joints) / (2 * h);
    }
    if (!Jg.allFinite()) continue;
    // Implicit function theorem: ∂X/∂ξg = −(∂q/∂X)⁺·∂q/∂ξg.
    sensitivities.emplace_back(-(Jx.completeOrthogonalDecomposition().pseudoInverse() * Jg).topRows(3));
    positions.emplace_back(bTe.translation());
  }
  const auto n = static_cast<Eigen::Index>(sensitivities.size());
  if (n == 0) return {};
  // A common rigid motion of every pose is a choice of base frame (it merges with the camera
  // mounting and, for per-leg models, with the gauge), not a positioning error: it is
  // projected out, so what remains is the error of distances between poses (the square test).
  Eigen::MatrixXd S(3 * n, G), B(3 * n, 6);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : positions) centre += p / static_cast<double>(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    S.middleRows(3 * j, 3) = sensitivities[static_cast<std::size_t>(j)];
    const Eigen::Vector3d p = positions[static_cast<std::size_t>(j)] - centre;
    B.block(3 * j, 0, 3, 3).setIdentity();
    B.block(3 * j, 3, 3, 3) << 0, p.z(), -p.y(), -p.z(), 0, p.x(), p.y(), -p.x(), 0;  // δω × p = −[p]×δω
  }
  const Eigen::MatrixXd P = S - B * B.completeOrthogonalDecomposition().solve(S);
  std::vector<double> out;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::MatrixXd D = P.middleRows(3 * j, 3);
    out.push_back(std::sqrt(std::max(0.0, (D * Cg * D.transpose()).trace())));
  }
  return out;
}

std::string designCriterionName(DesignCriterion c) {
  switch (c) {
    case DesignCriterion::D:
      return "D";
    case DesignCriterion::A:
      return "A";
    case DesignCriterion::E:
      return "E";
  }
  return "?";
}

}  // namespace mire::mechanism
