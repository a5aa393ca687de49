// Mechanisms by name (IKM/FKM, vectorised ikm/fkm over arrays of poses or joints), parameter
// sets and files, identification from arrays or files (with pose covariances), the
// identifiability report, the gauge analysis and the evaluation criteria V1–V3.
#include "bindings.hpp"

#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/variants.hpp"
#include "mire/support/side_files.hpp"

#include <limits>
#include <memory>
#include <optional>

namespace mire::python {
namespace {

namespace mech = mechanism;
using MechanismPtr = std::shared_ptr<mech::Mechanism>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

MechanismPtr mutablePtr(const std::shared_ptr<const mech::Mechanism>& mechanism) {
  return std::const_pointer_cast<mech::Mechanism>(mechanism);
}

void bindParameters(py::module_& m) {
  py::enum_<mech::Unit>(m, "Unit")
      .value("Metre", mech::Unit::Metre)
      .value("Radian", mech::Unit::Radian)
      .value("Dimensionless", mech::Unit::Dimensionless);
  m.def("unitName", &mech::unitName);
  m.def("displayUnitName", &mech::displayUnitName);
  m.def("toDisplay", &mech::toDisplay);
  py::class_<mech::Parameter>(m, "Parameter")
      .def(py::init([](std::string name, double value, mech::Unit unit, bool fixed, std::string description) {
             return mech::Parameter{std::move(name), value, unit, fixed, std::move(description)};
           }),
           py::arg("name"), py::arg("value") = 0.0, py::arg("unit") = mech::Unit::Metre, py::arg("fixed") = false,
           py::arg("description") = "")
      .def_readwrite("name", &mech::Parameter::name)
      .def_readwrite("value", &mech::Parameter::value)
      .def_readwrite("unit", &mech::Parameter::unit)
      .def_readwrite("fixed", &mech::Parameter::fixed)
      .def_readwrite("description", &mech::Parameter::description)
      .def("__repr__", [](const mech::Parameter& p) {
        return "<Parameter " + p.name + " = " + py::repr(py::float_(p.value)).cast<std::string>() + " " +
               mech::unitName(p.unit) + (p.fixed ? " (fixed)>" : ">");
      });
  using PS = mech::ParameterSet;
  py::class_<PS>(m, "ParameterSet")
      .def(py::init<>())
      .def("add", &PS::add)
      .def("append", &PS::append)
      .def("size", &PS::size)
      .def("__len__", &PS::size)
      .def("contains", &PS::contains)
      .def("__contains__", &PS::contains)
      .def("index", &PS::index)
      .def("__getitem__", [](const PS& s, std::size_t i) { return s[i]; })
      .def("__getitem__", [](const PS& s, const std::string& name) { return s.at(name); })
      .def("at", &PS::at)
      .def("parameters", &PS::parameters)
      .def("names", &PS::names)
      .def("value", &PS::value)
      .def("setValue", &PS::setValue)
      .def("setFixed", &PS::setFixed, py::arg("name"), py::arg("fixed") = true)
      .def("fix", &PS::fix)
      .def("freeAll", &PS::freeAll)
      .def("tie", &PS::tie)
      .def("tieLeader", &PS::tieLeader)
      .def("isTied", &PS::isTied)
      .def("values", &PS::values)
      .def("setValues", &PS::setValues)
      .def("freeIndices", &PS::freeIndices)
      .def("freeCount", &PS::freeCount)
      .def("freeNames", &PS::freeNames)
      .def("expansion", &PS::expansion)
      .def(
          "asDict",
          [](const PS& s) {
            py::dict out;
            for (const auto& p : s.parameters()) out[py::str(p.name)] = p.value;
            return out;
          },
          "{name: value (SI)}");
}

void bindExternal(py::module_& m) {
  py::enum_<mech::ExternalForm>(m, "ExternalForm")
      .value("AxisAligned", mech::ExternalForm::AxisAligned)
      .value("Full", mech::ExternalForm::Full)
      .value("CameraFrame", mech::ExternalForm::CameraFrame)
      .value("CameraOnEffector", mech::ExternalForm::CameraOnEffector);
  m.def("externalFormName", &mech::externalFormName);
  py::class_<mech::AxisAlignment>(m, "AxisAlignment")
      .def(py::init<>())
      .def_readwrite("camera", &mech::AxisAlignment::camera)
      .def_readwrite("target", &mech::AxisAlignment::target)
      .def_readwrite("covariance", &mech::AxisAlignment::covariance);
  using EP = mech::ExternalParameterization;
  py::class_<EP>(m, "ExternalParameterization")
      .def(py::init<mech::ExternalForm, mech::AxisAlignment>(), py::arg("form"),
           py::arg("alignment") = mech::AxisAlignment{})
      .def("form", &EP::form)
      .def("alignment", &EP::alignment)
      .def("size", py::overload_cast<>(&EP::size, py::const_))
      .def("parameters", &EP::parameters)
      .def("baseFromCamera", [](const EP& e, const Eigen::VectorXd& v) { return toMatrix(e.baseFromCamera(v)); })
      .def("targetFromEffector", [](const EP& e, const Eigen::VectorXd& v) { return toMatrix(e.targetFromEffector(v)); })
      .def("effectorInBase", [](const EP& e, const Eigen::VectorXd& v, const mech::PoseVector& cTm) {
        return toMatrix(e.effectorInBase(v, cTm));
      });
  m.def("estimateAxisAlignment", &mech::estimateAxisAlignment, py::arg("poses"));
}

// Vectorised IKM: poses (N, poseDof) -> joints (N, jointCount), NaN rows where unreachable.
Eigen::MatrixXd ikmRows(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric, const Eigen::MatrixXd& poses) {
  if (poses.cols() != mechanism.poseDof())
    throw py::value_error("ikm: poses must have " + std::to_string(mechanism.poseDof()) + " columns (" +
                          py::str(py::cast(mechanism.poseComponentNames())).cast<std::string>() + ")");
  Eigen::MatrixXd joints(poses.rows(), mechanism.jointCount());
  for (Eigen::Index i = 0; i < poses.rows(); ++i) {
    const auto result = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(poses.row(i).transpose()));
    if (result.reachable())
      joints.row(i) = result.joints.transpose();
    else
      joints.row(i).setConstant(kNaN);
  }
  return joints;
}

// Vectorised FKM: joints (N, jointCount) -> poses (N, poseDof), each started from the previous
// converged pose (the reference pose first), NaN rows where the FKM does not converge.
Eigen::MatrixXd fkmRows(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                        const Eigen::MatrixXd& joints, std::optional<Eigen::VectorXd> initial) {
  if (joints.cols() != mechanism.jointCount())
    throw py::value_error("fkm: joints must have " + std::to_string(mechanism.jointCount()) + " columns");
  Eigen::VectorXd start = initial ? *initial : mechanism.referencePose(geometric);
  Eigen::MatrixXd poses(joints.rows(), mechanism.poseDof());
  for (Eigen::Index i = 0; i < joints.rows(); ++i) {
    const auto result = mechanism.forwardKinematics(geometric, joints.row(i).transpose(), start);
    if (result.converged) {
      poses.row(i) = result.pose.transpose();
      start = result.pose;
    } else {
      poses.row(i).setConstant(kNaN);
    }
  }
  return poses;
}

// The Mechanism interface with its IKM/FKM results (doc/mechanisms.md).
void bindMechanism(py::module_& m) {
  py::enum_<mech::MotionType>(m, "MotionType")
      .value("Schoenflies", mech::MotionType::Schoenflies)
      .value("Translation", mech::MotionType::Translation)
      .value("Spatial", mech::MotionType::Spatial);
  py::class_<mech::IkmResult>(m, "IkmResult")
      .def_readonly("joints", &mech::IkmResult::joints)
      .def_readonly("unreachable_joints", &mech::IkmResult::unreachable_joints)
      .def_readonly("out_of_stroke_joints", &mech::IkmResult::out_of_stroke_joints)
      .def("reachable", &mech::IkmResult::reachable)
      .def("withinStroke", &mech::IkmResult::withinStroke);
  py::class_<mech::FkmOptions>(m, "FkmOptions")
      .def(py::init<>())
      .def_readwrite("max_iterations", &mech::FkmOptions::max_iterations)
      .def_readwrite("joint_tolerance", &mech::FkmOptions::joint_tolerance);
  py::class_<mech::FkmResult>(m, "FkmResult")
      .def_readonly("pose", &mech::FkmResult::pose)
      .def_property_readonly("bTe", [](const mech::FkmResult& r) { return toMatrix(r.bTe); })
      .def_readonly("converged", &mech::FkmResult::converged)
      .def_readonly("iterations", &mech::FkmResult::iterations)
      .def_readonly("max_joint_error", &mech::FkmResult::max_joint_error)
      .def_readonly("message", &mech::FkmResult::message);
  using M = mech::Mechanism;
  py::class_<M, MechanismPtr>(m, "Mechanism")
      .def("name", &M::name)
      .def("jointCount", &M::jointCount)
      .def("jointUnits", &M::jointUnits)
      .def("jointColumnNames", &M::jointColumnNames)
      .def("motionType", &M::motionType)
      .def("poseDof", &M::poseDof)
      .def("poseComponentNames", &M::poseComponentNames)
      .def("poseComponentUnits", &M::poseComponentUnits)
      .def("nominal", &M::nominal)
      .def("geometricCount", &M::geometricCount)
      .def("poseToTransform", [](const M& s, const Eigen::VectorXd& pose) { return toMatrix(s.poseToTransform(pose)); })
      .def("transformToPose",
           [](const M& s, const Eigen::Matrix4d& bTe) { return s.transformToPose(toIsometry(bTe, "bTe")); })
      .def("referencePose", &M::referencePose)
      .def(
          "inverseKinematics",
          [](const M& s, const Eigen::VectorXd& geometric, const Eigen::Matrix4d& bTe) {
            return s.inverseKinematics(geometric, toIsometry(bTe, "bTe"));
          },
          py::arg("geometric"), py::arg("bTe"))
      .def("forwardKinematics", &M::forwardKinematics, py::arg("geometric"), py::arg("joints"), py::arg("initial_pose"),
           py::arg("options") = mech::FkmOptions{})
      .def("predictJoints", &M::predictJoints, py::arg("external"), py::arg("geometric"), py::arg("external_values"),
           py::arg("cTm"))
      .def("jointJacobianWrtPose", &M::jointJacobianWrtPose, py::arg("external"), py::arg("geometric"),
           py::arg("external_values"), py::arg("cTm"))
      .def("ikm", &ikmRows, py::arg("geometric"), py::arg("poses"),
           "IKM of many poses (N, poseDof) -> joints (N, jointCount); NaN rows where unreachable.")
      .def("fkm", &fkmRows, py::arg("geometric"), py::arg("joints"), py::arg("initial_pose") = py::none(),
           "FKM of many joint vectors (N, jointCount) -> poses (N, poseDof), warm-started along the rows; NaN rows "
           "where it does not converge.");
}

// The H4 (its nominal geometry and model kinds) and the registry of mechanisms by name.
void bindH4AndRegistry(py::module_& m) {
  py::enum_<mech::H4ModelKind>(m, "H4ModelKind")
      .value("Model12", mech::H4ModelKind::Model12)
      .value("Model31", mech::H4ModelKind::Model31)
      .value("Model31Camera", mech::H4ModelKind::Model31Camera);
  py::class_<mech::H4Nominal>(m, "H4Nominal")
      .def(py::init<>())
      .def_readwrite("R", &mech::H4Nominal::R)
      .def_readwrite("L", &mech::H4Nominal::L)
      .def_readwrite("l", &mech::H4Nominal::l)
      .def_readwrite("h", &mech::H4Nominal::h)
      .def_readwrite("d", &mech::H4Nominal::d)
      .def_readwrite("alpha", &mech::H4Nominal::alpha)
      .def_readwrite("q0", &mech::H4Nominal::q0)
      .def_readwrite("amplification", &mech::H4Nominal::amplification);
  m.def(
      "makeH4Mechanism",
      [](mech::H4ModelKind kind, const mech::H4Nominal& nominal) {
        return MechanismPtr(mech::makeH4Mechanism(kind, nominal));
      },
      py::arg("kind"), py::arg("nominal") = mech::H4Nominal{});
  m.def("h4Model12Parameters", &mech::h4Model12Parameters, py::arg("nominal") = mech::H4Nominal{});
  m.def("model31FromModel12", [](const mech::ParameterSet& p) { return mech::model31FromModel12(p); });

  py::class_<mech::ModelInfo>(m, "ModelInfo")
      .def_readonly("name", &mech::ModelInfo::name)
      .def_readonly("description", &mech::ModelInfo::description)
      .def_readonly("label", &mech::ModelInfo::label)
      .def_readonly("h4_nominal", &mech::ModelInfo::h4_nominal)
      .def_readonly("family", &mech::ModelInfo::family)
      .def_readonly("variants", &mech::ModelInfo::variants)
      .def_readonly("contains", &mech::ModelInfo::contains)
      .def_readonly("contains_when_free", &mech::ModelInfo::contains_when_free)
      .def_property_readonly("default_variant", [](const mech::ModelInfo& m) {
        return m.default_variant ? std::string(1, m.default_variant) : std::string();
      });
  m.def("modelInfo", &mech::modelInfo, py::arg("name"));
  m.def("isDescriptionFile", &mech::isDescriptionFile, py::arg("model"));
  m.def("registeredModels", &mech::registeredModels);
  py::class_<mech::MechanismFamily>(m, "MechanismFamily")
      .def_readonly("name", &mech::MechanismFamily::name)
      .def_readonly("title", &mech::MechanismFamily::title)
      .def_readonly("models", &mech::MechanismFamily::models)
      .def_readonly("selection", &mech::MechanismFamily::selection)
      .def_readonly("truth_model", &mech::MechanismFamily::truth_model);
  m.def("mechanismFamilies", &mech::mechanismFamilies);
  m.def("mechanismFamily", &mech::mechanismFamily, py::arg("name"), py::return_value_policy::reference);
  py::class_<mech::RegisteredModel>(m, "RegisteredModel")
      .def_readonly("name", &mech::RegisteredModel::name)
      .def_property_readonly("mechanism", [](const mech::RegisteredModel& r) { return mutablePtr(r.mechanism); })
      .def_readonly("nominal", &mech::RegisteredModel::nominal)
      .def_readonly("external_form", &mech::RegisteredModel::external_form);
  static const std::string make_doc = "A mechanism by name: " + mech::registeredModelList() + ".";
  m.def("makeRegisteredModel", &mech::makeRegisteredModel, py::arg("name"), py::arg("h4") = mech::H4Nominal{},
        make_doc.c_str());
}

mech::PoseObservation makeObservation(std::string id, const mech::PoseVector& cTm, const Eigen::VectorXd& joints,
                                      std::optional<mech::PoseCovariance> covariance) {
  return mech::PoseObservation{std::move(id), cTm, joints, std::move(covariance)};
}

// Observations from arrays: ids (N), cTm (N, 6) [m, rad], joints (N, J), covariances (N, 6, 6) or None.
std::vector<mech::PoseObservation> observationsFromArrays(const std::vector<std::string>& ids,
                                                          const Eigen::MatrixXd& poses, const Eigen::MatrixXd& joints,
                                                          const py::object& covariances) {
  const auto n = static_cast<Eigen::Index>(ids.size());
  if (poses.rows() != n || poses.cols() != 6)
    throw py::value_error("observationsFromArrays: poses must be (" + std::to_string(n) + ", 6): tx ty tz rx ry rz");
  if (joints.rows() != n)
    throw py::value_error("observationsFromArrays: joints must have " + std::to_string(n) + " rows");
  const bool has_covariances = !covariances.is_none();
  DoubleArray cov;
  if (has_covariances) {
    cov = DoubleArray::ensure(covariances);
    if (!cov || cov.ndim() != 3 || cov.shape(0) != n || cov.shape(1) != 6 || cov.shape(2) != 6)
      throw py::value_error("observationsFromArrays: covariances must be (" + std::to_string(n) + ", 6, 6) or None");
  }
  std::vector<mech::PoseObservation> out;
  for (Eigen::Index i = 0; i < n; ++i) {
    std::optional<mech::PoseCovariance> c;
    if (has_covariances) {
      mech::PoseCovariance matrix;
      for (int r = 0; r < 6; ++r)
        for (int k = 0; k < 6; ++k) matrix(r, k) = cov.at(i, r, k);
      c = matrix;
    }
    out.push_back(
        makeObservation(ids[static_cast<std::size_t>(i)], poses.row(i).transpose(), joints.row(i).transpose(), c));
  }
  return out;
}

void bindObservations(py::module_& m) {
  using O = mech::PoseObservation;
  py::class_<O>(m, "PoseObservation")
      .def(py::init(&makeObservation), py::arg("id"), py::arg("cTm"), py::arg("joints"),
           py::arg("covariance") = py::none())
      .def_readwrite("id", &O::id)
      .def_readwrite("cTm", &O::cTm)
      .def_readwrite("joints", &O::joints)
      .def_readwrite("covariance", &O::covariance);
  m.def("observationsFromArrays", &observationsFromArrays, py::arg("ids"), py::arg("poses"), py::arg("joints"),
        py::arg("covariances") = py::none());
  m.def("validatePoses", &mech::validatePoses, py::arg("poses"), py::arg("joint_count"));
  m.def("toPoseVector", [](const Eigen::Matrix4d& t) { return mech::toPoseVector(toIsometry(t, "transform")); });
  m.def(
      "toIsometry", [](const mech::PoseVector& p) { return toMatrix(mech::toIsometry(p)); },
      "4×4 from (tx ty tz rx ry rz)");

  py::class_<mech::PoseRow>(m, "PoseRow")
      .def_readonly("observation", &mech::PoseRow::observation)
      .def_readonly("line", &mech::PoseRow::line);
  m.def("readPosesCsv", &mech::readPosesCsv, py::arg("poses_csv"), py::arg("covariance_csv") = py::none());
  m.def("defaultCovariancePath", &mire::support::covarianceSidePath);
  py::class_<mech::JointRow>(m, "JointRow")
      .def_readonly("pose_id", &mech::JointRow::pose_id)
      .def_readonly("joints", &mech::JointRow::joints)
      .def_readonly("line", &mech::JointRow::line);
  m.def("readJointsCsv",
        py::overload_cast<const std::filesystem::path&, const std::vector<std::string>&>(&mech::readJointsCsv),
        py::arg("joints_csv"), py::arg("joint_columns"));
  m.def("readJointsCsv", py::overload_cast<const std::filesystem::path&, int>(&mech::readJointsCsv),
        py::arg("joints_csv"), py::arg("joint_count") = 4);
  py::class_<mech::ObservationSet>(m, "ObservationSet")
      .def_readonly("poses", &mech::ObservationSet::poses)
      .def_readonly("unused_joint_ids", &mech::ObservationSet::unused_joint_ids);
  m.def("readObservations",
        py::overload_cast<const std::filesystem::path&, const std::filesystem::path&,
                          const std::optional<std::filesystem::path>&, const std::vector<std::string>&>(
            &mech::readObservations),
        py::arg("poses_csv"), py::arg("joints_csv"), py::arg("covariance_csv"), py::arg("joint_columns"));
  m.def("readObservations",
        py::overload_cast<const std::filesystem::path&, const std::filesystem::path&,
                          const std::optional<std::filesystem::path>&, int>(&mech::readObservations),
        py::arg("poses_csv"), py::arg("joints_csv"), py::arg("covariance_csv") = py::none(), py::arg("joint_count") = 4);
  py::class_<mech::LineRecord>(m, "LineRecord")
      .def(py::init<>())
      .def_readwrite("line_id", &mech::LineRecord::line_id)
      .def_readwrite("joints", &mech::LineRecord::joints);
  m.def("readLinesCsv", py::overload_cast<const std::filesystem::path&, int>(&mech::readLinesCsv), py::arg("lines_csv"),
        py::arg("joint_count") = 4);
  m.def("readLinesCsv",
        py::overload_cast<const std::filesystem::path&, const std::vector<std::string>&>(&mech::readLinesCsv),
        py::arg("lines_csv"), py::arg("joint_columns"));
}

// Parameter files (mechanism/io.hpp): read, apply to a parameter set, write.
void bindParameterFiles(py::module_& m) {
  py::class_<mech::ParameterFileEntry>(m, "ParameterFileEntry")
      .def_readonly("key", &mech::ParameterFileEntry::key)
      .def_readonly("text", &mech::ParameterFileEntry::text)
      .def_readonly("line", &mech::ParameterFileEntry::line);
  py::class_<mech::ParameterFile>(m, "ParameterFile")
      .def_readonly("path", &mech::ParameterFile::path)
      .def_readonly("entries", &mech::ParameterFile::entries)
      .def("find",
           [](const mech::ParameterFile& f, const std::string& key) -> std::optional<mech::ParameterFileEntry> {
             const auto* entry = f.find(key);
             return entry ? std::optional<mech::ParameterFileEntry>(*entry) : std::nullopt;
           })
      .def("number", &mech::ParameterFile::number);
  m.def("readParameterFile", &mech::readParameterFile, py::arg("path"));
  m.def(
      "applyParameterFile",
      [](const mech::ParameterFile& file, mech::ParameterSet parameters, const std::vector<std::string>& also_allowed,
         const std::vector<std::string>& may_default) {
        mech::applyParameterFile(file, parameters, also_allowed, may_default);
        return parameters;
      },
      py::arg("file"), py::arg("parameters"), py::arg("also_allowed") = std::vector<std::string>{},
      py::arg("may_default") = std::vector<std::string>{}, "Returns a copy of `parameters` with the file's values.");
  m.def("writeParameterFile", &mech::writeParameterFile, py::arg("path"), py::arg("parameters"),
        py::arg("sigma") = Eigen::VectorXd(), py::arg("metadata") = std::vector<std::pair<std::string, std::string>>{},
        py::arg("comment") = "");
  m.def("parameterFileString", &mech::parameterFileString, py::arg("parameters"), py::arg("sigma") = Eigen::VectorXd(),
        py::arg("metadata") = std::vector<std::pair<std::string, std::string>>{}, py::arg("comment") = "");
}

}  // namespace

void bindMechanisms(py::module_& m) {
  bindParameters(m);
  bindExternal(m);
  bindMechanism(m);
  bindH4AndRegistry(m);
  bindObservations(m);
  bindParameterFiles(m);
  bindIdentification(m);
}

}  // namespace mire::python
