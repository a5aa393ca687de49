// FKM / IKM predictions of an identified model with propagated σ (doc/mechanisms.md).
#include "mire/mechanism/prediction.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/side_files.hpp"
#include "mire/support/yaml.hpp"

namespace mire::mechanism {

namespace {

constexpr double kStep = 1e-6;  // central-difference step [m or rad]

ExternalParameterization fullForm() { return ExternalParameterization(ExternalForm::Full); }

// Index of each covariance name: geometric (k < geometric count) or mounting (offset).
struct CovarianceLayout {
  std::vector<std::size_t> geometric;  // positions in covariance_names that are geometric
  std::vector<std::size_t> mounting;
};
CovarianceLayout layoutOf(const PredictionModel& m) {
  CovarianceLayout layout;
  for (std::size_t k = 0; k < m.covariance_names.size(); ++k)
    (m.geometric.contains(m.covariance_names[k]) ? layout.geometric : layout.mounting).push_back(k);
  return layout;
}

// ∂q/∂ξg at bTe over the geometric covariance names (central differences of the IKM).
Eigen::MatrixXd jointsWrtGeometry(const PredictionModel& m, const Eigen::Isometry3d& bTe,
                                  const std::vector<std::string>& names) {
  Eigen::MatrixXd J(m.mechanism->jointCount(), static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    ParameterSet plus = m.geometric, minus = m.geometric;
    plus.setValue(names[k], plus.value(names[k]) + kStep);
    minus.setValue(names[k], minus.value(names[k]) - kStep);
    J.col(static_cast<Eigen::Index>(k)) = (m.mechanism->inverseKinematics(plus.values(), bTe).joints -
                                           m.mechanism->inverseKinematics(minus.values(), bTe).joints) /
                                          (2 * kStep);
  }
  return J;
}

// ∂q/∂X at the pose X (central differences).
Eigen::MatrixXd jointsWrtPose(const PredictionModel& m, const Eigen::VectorXd& X) {
  const Eigen::VectorXd g = m.geometric.values();
  Eigen::MatrixXd J(m.mechanism->jointCount(), X.size());
  for (Eigen::Index k = 0; k < X.size(); ++k) {
    Eigen::VectorXd p = X, q = X;
    p[k] += kStep;
    q[k] -= kStep;
    J.col(k) = (m.mechanism->inverseKinematics(g, m.mechanism->poseToTransform(p)).joints -
                m.mechanism->inverseKinematics(g, m.mechanism->poseToTransform(q)).joints) /
               (2 * kStep);
  }
  return J;
}

// The rotation vector (entries 3..5) equivalent to v's and nearest `reference`'s: r and
// r·(1 − 2π/|r|) are the same rotation, and near a half turn differences must not jump by 2π.
PoseVector nearestRotationVector(PoseVector v, const PoseVector& reference) {
  const Eigen::Vector3d r = v.tail<3>(), r0 = reference.tail<3>();
  if (r.norm() > 1.0) {
    const Eigen::Vector3d other = r * (1.0 - 2.0 * support::kPi / r.norm());
    if ((other - r0).norm() < (r - r0).norm()) v.tail<3>() = other;
  }
  return v;
}

Eigen::MatrixXd subCovariance(const Eigen::MatrixXd& C, const std::vector<std::size_t>& a,
                              const std::vector<std::size_t>& b) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(a.size()), static_cast<Eigen::Index>(b.size()));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          C(static_cast<Eigen::Index>(a[i]), static_cast<Eigen::Index>(b[j]));
  return out;
}

}  // namespace

namespace {
void requireCameraFixed(const PredictionModel& m) {
  if (m.mounting_form != ExternalForm::Full)
    throw std::runtime_error(m.model_name + ": the camera is on the effector: there is no cTb nor eTm");
}
}  // namespace

Eigen::Isometry3d PredictionModel::cTb() const {
  requireCameraFixed(*this);
  return fullForm().baseFromCamera(mounting.values()).inverse();
}
Eigen::Isometry3d PredictionModel::eTm() const {
  requireCameraFixed(*this);
  return fullForm().targetFromEffector(mounting.values()).inverse();
}

namespace {

// The geometric parameters of an identification, ties inside the geometry kept (variant E's L1..L4).
ParameterSet geometricPart(const IdentificationModel& id) {
  const int G = id.geometricCount();
  const ParameterSet& all = id.parameters;
  ParameterSet geometric;
  for (int k = 0; k < G; ++k) geometric.add(all[static_cast<std::size_t>(k)]);
  for (int k = 0; k < G; ++k) {
    std::vector<std::string> group;
    for (int j = 0; j < G; ++j)
      if (all.tieLeader(static_cast<std::size_t>(j)) == static_cast<std::size_t>(k))
        group.push_back(all[static_cast<std::size_t>(j)].name);
    if (group.size() > 1) geometric.tie(group);
  }
  return geometric;
}

// The form a prediction carries the mounting in: the full form, or the camera-on-effector one.
ExternalForm mountingFormOf(const IdentificationModel& id) {
  return id.external.form() == ExternalForm::CameraOnEffector ? ExternalForm::CameraOnEffector : ExternalForm::Full;
}

// External values of the identification's form → the 12 full-form mounting values, and the
// rotation vectors taken nearest the unperturbed ones (r and r·(1 − 2π/|r|) are the same
// rotation; near a half turn central differences must not jump by 2π).
struct FullMountingMap {
  explicit FullMountingMap(const IdentificationModel& model) : id(model) {}
  const IdentificationModel& id;
  ExternalParameterization full{mountingFormOf(id)};
  Eigen::VectorXd full0;
  // Translating plate aligned on the mean orientation R̄ (alignTranslatingTarget): eRm is
  // not a parameter but cRbᵀ·R̄, so it follows the camera rotation (mean_orientation_covariance).
  std::optional<Eigen::Matrix3d> mean_orientation;

  Eigen::VectorXd raw(const Eigen::VectorXd& e) const {
    return full.valuesFrom(id.external.baseFromCamera(e), id.external.targetFromEffector(e));
  }
  Eigen::VectorXd nearest(Eigen::VectorXd v) const {
    for (int start : {3, 9}) {
      const Eigen::Vector3d r = v.segment<3>(start), r0 = full0.segment<3>(start);
      if (r.norm() > 1.0) {
        const Eigen::Vector3d other = r * (1.0 - 2.0 * support::kPi / r.norm());
        if ((other - r0).norm() < (r - r0).norm()) v.segment<3>(start) = other;
      }
    }
    return v;
  }
  Eigen::VectorXd operator()(const Eigen::VectorXd& e) const {
    return nearest(mean_orientation ? mountingWithMeanOrientation(full.form(), raw(e), *mean_orientation) : raw(e));
  }
};

FullMountingMap fullMountingMap(const IdentificationResult& result, bool aligned_translating_target) {
  FullMountingMap map(result.model);
  map.full0 = map.raw(result.model.externalValues());
  if (aligned_translating_target) {  // cRm = cRb·eRm, or mRc = mRb·eRc with the camera on the effector
    const Eigen::Matrix3d first = map.full.baseFromCamera(map.full0).linear().transpose();
    const Eigen::Matrix3d second = map.full.targetFromEffector(map.full0).linear().transpose();
    map.mean_orientation = Eigen::Matrix3d(first * second);
  }
  return map;
}

constexpr double kConversionStep = 1e-5;  // smooth maps: truncation error ~1e-10

// T = ∂(geometric free, full mounting)/∂(free parameters): identity on the geometric ones,
// central differences of the conversion on the external ones.
Eigen::MatrixXd conversionJacobian(const IdentificationResult& result, const FullMountingMap& map,
                                   const std::vector<std::size_t>& geo, const std::vector<std::size_t>& ext) {
  const IdentificationModel& id = result.model;
  const int G = id.geometricCount();
  const auto nf = static_cast<Eigen::Index>(result.free_names.size());
  const auto rows = static_cast<Eigen::Index>(geo.size());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(rows + 12, nf);
  for (std::size_t i = 0; i < geo.size(); ++i) T(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(geo[i])) = 1.0;
  const bool identity = id.external.form() == map.full.form() && !map.mean_orientation;
  const Eigen::VectorXd e0 = id.externalValues();
  for (std::size_t k : ext) {
    const auto index = static_cast<Eigen::Index>(id.parameters.index(result.free_names[k]) - static_cast<std::size_t>(G));
    if (identity) {  // the mounting values are the parameters themselves
      T(rows + index, static_cast<Eigen::Index>(k)) = 1.0;
      continue;
    }
    Eigen::VectorXd p = e0, q = e0;
    p[index] += kConversionStep;
    q[index] -= kConversionStep;
    T.block(rows, static_cast<Eigen::Index>(k), 12, 1) = (map(p) - map(q)) / (2 * kConversionStep);
  }
  return T;
}

// ∂full/∂δ over the 4 tilts of the estimated axis alignment (aligned forms).
Eigen::MatrixXd alignmentJacobian(const IdentificationModel& id, const FullMountingMap& map, Eigen::Index rows) {
  const AxisAlignment& alignment = id.external.alignment();
  const Eigen::VectorXd e0 = id.externalValues();
  Eigen::MatrixXd Td = Eigen::MatrixXd::Zero(rows + 12, 4);
  for (int k = 0; k < 4; ++k) {
    const auto tilted = [&](double step) {
      const ExternalParameterization form(id.external.form(), tiltAlignment(alignment, step * Eigen::Vector4d::Unit(k)));
      return map.nearest(Eigen::VectorXd(map.full.valuesFrom(form.baseFromCamera(e0), form.targetFromEffector(e0))));
    };
    Td.block(rows, k, 12, 1) = (tilted(kConversionStep) - tilted(-kConversionStep)) / (2 * kConversionStep);
  }
  return Td;
}

// ∂full/∂r̄ over the rotation vector of the mean orientation R̄ (translating plate).
Eigen::MatrixXd meanOrientationJacobian(const FullMountingMap& map, Eigen::Index rows) {
  const Eigen::Vector3d r0 = rotationVector(*map.mean_orientation);
  Eigen::MatrixXd Tr = Eigen::MatrixXd::Zero(rows + 12, 3);
  for (int k = 0; k < 3; ++k) {
    const auto turned = [&](double step) {
      const Eigen::Vector3d r = r0 + step * Eigen::Vector3d::Unit(k);
      return map.nearest(mountingWithMeanOrientation(map.full.form(), map.full0, fromRotationVector(r)));
    };
    Tr.block(rows, k, 12, 1) = (turned(kConversionStep) - turned(-kConversionStep)) / (2 * kConversionStep);
  }
  return Tr;
}

}  // namespace

PredictionModel predictionModelFrom(const std::string& model_name, const IdentificationResult& result) {
  return predictionModelFrom(model_name, result, std::nullopt);
}

PredictionModel predictionModelFrom(const std::string& model_name, const IdentificationResult& result,
                                    const std::optional<Eigen::Matrix3d>& mean_orientation_covariance) {
  const IdentificationModel& id = result.model;
  PredictionModel m;
  m.model_name = model_name;
  m.mechanism = id.mechanism;
  m.geometric = geometricPart(id);
  const FullMountingMap map = fullMountingMap(result, mean_orientation_covariance.has_value());
  m.mounting_form = map.full.form();
  m.mounting = map.full.parameters();
  m.mounting.freeAll();
  m.mounting.setValues(map.full0);

  // Covariance: free geometric names as they are; free external names through ∂full/∂e.
  std::vector<std::size_t> geo, ext;
  for (std::size_t k = 0; k < result.free_names.size(); ++k)
    (id.parameters.index(result.free_names[k]) < static_cast<std::size_t>(id.geometricCount()) ? geo : ext).push_back(k);
  for (std::size_t k : geo) m.covariance_names.push_back(result.free_names[k]);
  for (const std::string& n : m.mounting.names()) m.covariance_names.push_back(n);
  if (result.covariance.size() == 0) return m;
  const Eigen::MatrixXd T = conversionJacobian(result, map, geo, ext);
  const auto rows = static_cast<Eigen::Index>(geo.size());
  if (map.mean_orientation) {
    const Eigen::MatrixXd Tr = meanOrientationJacobian(map, rows);
    m.covariance = T * result.covariance * T.transpose() + Tr * *mean_orientation_covariance * Tr.transpose();
    return m;
  }
  // Aligned forms: the mounting also depends on the estimated axis alignment δ, whose
  // uncertainty is one of the parameters' covariance terms (S·Σδ·Sᵀ). The mounting then varies
  // with (ξ, δ) jointly: the alignment term and the calibration's shared term (refits,
  // identification_covariance.cpp) move both, X Σ Xᵀ for ξ with Cov(ξ, δ) = X Σ Δᵀ, and go through
  // T·X + Td·Δ, with ∂full/∂δ by central differences of the tilted alignment; the other terms move ξ
  // alone. Leaving δ out overstates the σ of the predictions (the parameters' compensation of the
  // alignment error would count as an error).
  const CovarianceTerm* alignment = result.term(CovarianceTerm::kAlignment);
  if (id.external.form() == map.full.form() || !alignment || alignment->columns.rows() != T.cols() ||
      alignment->source_covariance.isZero()) {
    m.covariance = T * result.covariance * T.transpose();
    return m;
  }
  const Eigen::MatrixXd Td = alignmentJacobian(id, map, rows);
  m.covariance = Eigen::MatrixXd::Zero(T.rows(), T.rows());
  for (const CovarianceTerm& term : result.covariance_terms) {
    if (term.alignment_columns.rows() != 4 || term.alignment_columns.cols() != term.columns.cols()) {
      m.covariance += T * term.covariance * T.transpose();
      continue;
    }
    const Eigen::MatrixXd columns = T * term.columns + Td * term.alignment_columns;
    m.covariance += term.source_covariance.size()
                        ? Eigen::MatrixXd(columns * term.source_covariance * columns.transpose())
                        : Eigen::MatrixXd(columns * columns.transpose());
  }
  return m;
}

void writePredictionCovarianceCsv(const std::filesystem::path& path, const PredictionModel& m) {
  const std::vector<std::string>& names = m.covariance_names;
  const auto n = static_cast<Eigen::Index>(names.size());
  // Written symmetric: products such as J·Σ·Jᵀ leave rounding-level asymmetry (3e-9 relative on
  // a described linear delta), and the reader refuses more than 1e-9.
  const Eigen::MatrixXd C = m.covariance.size() ? Eigen::MatrixXd(0.5 * (m.covariance + m.covariance.transpose()))
                                                : Eigen::MatrixXd::Zero(n, n);
  std::ostringstream out;
  out << "name,value";
  for (const std::string& name : names) out << ',' << name;
  out << '\n';
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::string& name = names[static_cast<std::size_t>(i)];
    out << name << ','
        << support::formatNumber(m.geometric.contains(name) ? m.geometric.value(name) : m.mounting.value(name));
    for (Eigen::Index j = 0; j < n; ++j) out << ',' << support::formatNumber(C(i, j));
    out << '\n';
  }
  support::writeFileAtomically(path, out.str());
}

void readPredictionCovarianceCsv(const std::filesystem::path& path, PredictionModel& m) {
  const support::CsvTable table = support::readCsv(path);
  const std::size_t name_col = table.column("name"), value_col = table.column("value");
  if (m.mounting.size() == 0) m.mounting = fullForm().parameters();
  m.covariance_names.clear();
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const std::string& name = table.rows[r][name_col];
    for (const std::string& seen : m.covariance_names)
      if (seen == name) throw std::runtime_error(table.where(r) + ": name '" + name + "' repeats");
    const double value = table.number(r, value_col);
    if (m.mounting.contains(name)) {
      m.mounting.setValue(name, value);
    } else if (!m.geometric.contains(name)) {
      throw std::runtime_error(table.where(r) + ": '" + name + "' is not a parameter of " + m.mechanism->name() +
                               " nor a mounting value (" + m.mounting.names().front() + ".." +
                               m.mounting.names().back() + ")");
    } else if (std::abs(m.geometric.value(name) - value) > 1e-12 * std::max(1.0, std::abs(value))) {
      throw std::runtime_error(table.where(r) + ": '" + name +
                               "' differs from the parameter file's value: the files do not belong together");
    }
    m.covariance_names.push_back(name);
  }
  const auto n = static_cast<Eigen::Index>(m.covariance_names.size());
  m.covariance.resize(n, n);
  for (std::size_t r = 0; r < m.covariance_names.size(); ++r)
    for (std::size_t c = 0; c < m.covariance_names.size(); ++c)
      m.covariance(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          table.number(r, table.column(m.covariance_names[c]));
  if (!m.covariance.isApprox(m.covariance.transpose(), 1e-9) && n > 0)
    throw std::runtime_error(path.string() + ": the covariance is not symmetric");
  for (Eigen::Index k = 0; k < n; ++k)
    if (!(m.covariance(k, k) >= 0.0))
      throw std::runtime_error(path.string() + ": negative variance of '" +
                               m.covariance_names[static_cast<std::size_t>(k)] + "'");
}

namespace {

// An identified file of an aligned form holds x_BC.. and x_ME.. while its side file holds the full
// mounting (tx_CB..rz_EM) that predictions use. The aligned values map to the full ones through the
// axis alignment, which neither file holds, but two things do not depend on it: the camera centre
// in the base frame (x_BC, y_BC, z_BC = bTc's translation, external.cpp) and the effector's distance
// from the target origin (|(x_ME, y_ME, z_ME)| = |t_EM|). An edited or foreign value there must not
// be silently replaced by the side file's.
constexpr double kMountingTolerance = 1e-9;  // m, absolute and relative: the files hold 17 digits

// `what` of the parameter file (at `key`'s line) against the side file's `side_value`.
void checkAgrees(const ParameterFile& file, const std::filesystem::path& side, const std::string& key,
                 const std::string& what, double yaml_value, double side_value) {
  if (std::abs(yaml_value - side_value) <= kMountingTolerance * std::max(1.0, std::abs(side_value))) return;
  throw std::runtime_error(file.where(*file.find(key)) + ": " + what + " = " +
                           support::formatMessageNumber(yaml_value) + " m, but the mounting of " + side.string() +
                           " (tx_CB..rz_EM) gives " + support::formatMessageNumber(side_value) +
                           " m: the files do not belong together (or one was edited)");
}

void checkAlignedMountingAgrees(const ParameterFile& file, const std::filesystem::path& side, const PredictionModel& m) {
  const auto value = [&file](const std::string& key) { return file.number(*file.find(key)); };
  const Eigen::Vector3d centre = fullForm().baseFromCamera(m.mounting.values()).translation();
  const char* const centre_keys[3] = {"x_BC", "y_BC", "z_BC"};
  for (int k = 0; k < 3; ++k)
    if (file.find(centre_keys[k]))
      checkAgrees(file, side, centre_keys[k], centre_keys[k], value(centre_keys[k]), centre[k]);
  if (!file.find("x_ME") || !file.find("y_ME")) return;
  const double z = file.find("z_ME") ? value("z_ME") : 0.0;
  checkAgrees(file, side, "x_ME", "|(x_ME, y_ME, z_ME)| (the effector origin's distance from the target origin)",
              Eigen::Vector3d(value("x_ME"), value("y_ME"), z).norm(),
              fullForm().targetFromEffector(m.mounting.values()).translation().norm());
}

}  // namespace

LoadedPredictionModel loadPredictionModel(const std::filesystem::path& yaml,
                                          const std::optional<std::filesystem::path>& covariance_csv) {
  const ParameterFile file = readParameterFile(yaml);
  const ParameterFileEntry* model_key = file.find("model");
  if (!model_key)
    throw std::runtime_error(yaml.string() + ": no 'model' key (expected one of " + registeredModelList() + ")");
  RegisteredModel registered;
  try {
    registered = makeRegisteredModel(parameterFileModel(file));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file.where(*model_key) + ": " + e.what());
  }
  LoadedPredictionModel out;
  PredictionModel& m = out.model;
  m.model_name = registered.name;
  m.mechanism = registered.mechanism;
  ParameterSet all = registered.nominal;
  const ParameterFileEntry* form_key = file.find("external_form");
  if (form_key && form_key->text == externalFormName(ExternalForm::CameraOnEffector))
    m.mounting_form = ExternalForm::CameraOnEffector;
  m.mounting = ExternalParameterization(m.mounting_form).parameters();
  for (const Parameter& p : m.mounting.parameters()) all.add(p);
  std::vector<std::string> also{"amplification"};
  for (ExternalForm form :
       {ExternalForm::AxisAligned, ExternalForm::CameraFrame, ExternalForm::Full, ExternalForm::CameraOnEffector})
    for (const std::string& n : ExternalParameterization(form).parameters().names()) also.push_back(n);
  // The full mounting may come from the covariance side file instead (has_mounting below).
  applyParameterFile(file, all, also, m.mounting.names());
  m.geometric = registered.nominal;
  for (const Parameter& p : registered.nominal.parameters()) m.geometric.setValue(p.name, all.value(p.name));
  bool mounting_in_yaml = true;
  for (const Parameter& p : m.mounting.parameters()) {
    mounting_in_yaml = mounting_in_yaml && file.find(p.name) != nullptr;
    m.mounting.setValue(p.name, all.value(p.name));
  }
  out.has_mounting = mounting_in_yaml;
  const std::filesystem::path side = covariance_csv ? *covariance_csv : support::covarianceSidePath(yaml);
  if (covariance_csv || std::filesystem::exists(side)) {
    const ParameterSet yaml_mounting = m.mounting;
    readPredictionCovarianceCsv(side, m);
    if (mounting_in_yaml)
      for (const Parameter& p : yaml_mounting.parameters())
        if (std::abs(p.value - m.mounting.value(p.name)) > 1e-12 * std::max(1.0, std::abs(p.value)))
          throw std::runtime_error(side.string() + ": '" + p.name + "' differs from " + yaml.string() +
                                   ": the files do not belong together");
    bool mounting_in_side = true;
    for (const std::string& n : m.mounting.names()) {
      bool found = false;
      for (const std::string& c : m.covariance_names) found = found || c == n;
      mounting_in_side = mounting_in_side && found;
    }
    out.has_mounting = out.has_mounting || mounting_in_side;
    if (mounting_in_side && !mounting_in_yaml) checkAlignedMountingAgrees(file, side, m);
    out.has_covariance = true;
  }
  return out;
}

PosePrediction predictPose(const PredictionModel& m, const Eigen::VectorXd& joints) {
  PosePrediction out;
  const Eigen::VectorXd g = m.geometric.values();
  const FkmResult fkm = m.mechanism->forwardKinematics(g, joints, m.mechanism->referencePose(g));
  out.converged = fkm.converged;
  out.message = fkm.message;
  if (!fkm.converged) return out;
  out.pose = fkm.pose;
  out.bTe = fkm.bTe;
  const ExternalParameterization mounting_form(m.mounting_form);
  out.cTm = toPoseVector(mounting_form.targetInCamera(m.mounting.values(), fkm.bTe));
  const auto P = static_cast<Eigen::Index>(fkm.pose.size());
  out.pose_covariance = Eigen::MatrixXd::Zero(P, P);
  if (m.covariance.size() == 0) return out;

  const CovarianceLayout layout = layoutOf(m);
  std::vector<std::string> gnames;
  for (std::size_t k : layout.geometric) gnames.push_back(m.covariance_names[k]);
  // ∂X/∂ξg = −(∂q/∂X)⁺ ∂q/∂ξg (implicit function; pseudo-inverse when more joints than DoF).
  const Eigen::MatrixXd Jx = jointsWrtPose(m, fkm.pose);
  const Eigen::MatrixXd Jg = jointsWrtGeometry(m, fkm.bTe, gnames);
  const Eigen::MatrixXd dXdg = -Jx.completeOrthogonalDecomposition().solve(Jg);
  const Eigen::MatrixXd Cgg = subCovariance(m.covariance, layout.geometric, layout.geometric);
  out.pose_covariance = dXdg * Cgg * dXdg.transpose();

  // cTm(X, mounting): central differences over X and the 12 mounting values.
  const Eigen::VectorXd mount = m.mounting.values();
  const auto cTmOf = [&](const Eigen::VectorXd& X, const Eigen::VectorXd& mt) {
    return nearestRotationVector(toPoseVector(mounting_form.targetInCamera(mt, m.mechanism->poseToTransform(X))),
                                 out.cTm);
  };
  Eigen::MatrixXd dX(6, P), dM(6, 12);
  for (Eigen::Index k = 0; k < P; ++k) {
    Eigen::VectorXd a = fkm.pose, b = fkm.pose;
    a[k] += kStep;
    b[k] -= kStep;
    dX.col(k) = (cTmOf(a, mount) - cTmOf(b, mount)) / (2 * kStep);
  }
  for (Eigen::Index k = 0; k < 12; ++k) {
    Eigen::VectorXd a = mount, b = mount;
    a[k] += kStep;
    b[k] -= kStep;
    dM.col(k) = (cTmOf(fkm.pose, a) - cTmOf(fkm.pose, b)) / (2 * kStep);
  }
  // Total Jacobian over the covariance names.
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, static_cast<Eigen::Index>(m.covariance_names.size()));
  const Eigen::MatrixXd dg = dX * dXdg;
  for (std::size_t i = 0; i < layout.geometric.size(); ++i)
    J.col(static_cast<Eigen::Index>(layout.geometric[i])) = dg.col(static_cast<Eigen::Index>(i));
  const std::vector<std::string> mnames = m.mounting.names();
  for (std::size_t k : layout.mounting)
    for (std::size_t j = 0; j < mnames.size(); ++j)
      if (mnames[j] == m.covariance_names[k])
        J.col(static_cast<Eigen::Index>(k)) = dM.col(static_cast<Eigen::Index>(j));
  out.cTm_covariance = J * m.covariance * J.transpose();
  return out;
}

JointPrediction predictJointCommands(const PredictionModel& m, const Eigen::Isometry3d& bTe) {
  JointPrediction out;
  out.ikm = m.mechanism->inverseKinematics(m.geometric.values(), bTe);
  const auto n = static_cast<Eigen::Index>(m.mechanism->jointCount());
  out.covariance = Eigen::MatrixXd::Zero(n, n);
  if (m.covariance.size() == 0 || !out.ikm.reachable()) return out;
  const CovarianceLayout layout = layoutOf(m);
  std::vector<std::string> gnames;
  for (std::size_t k : layout.geometric) gnames.push_back(m.covariance_names[k]);
  const Eigen::MatrixXd Jg = jointsWrtGeometry(m, bTe, gnames);
  out.covariance = Jg * subCovariance(m.covariance, layout.geometric, layout.geometric) * Jg.transpose();
  return out;
}

}  // namespace mire::mechanism
