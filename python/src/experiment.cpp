// `mire plan` and `mire select` as a library (doc/plan-and-select.md, doc/python.md): the
// workspace and candidate poses, the mounting guess, the Fisher information of the
// identification per candidate, the DETMAX design and its report; the candidate models, the
// cross-validated selection and its table. Poses are (N, poseDof) arrays in and out.
#include "bindings.hpp"

#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/model_selection.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/functional.h>

namespace mire::python {
namespace {

namespace mech = mechanism;

std::vector<Eigen::VectorXd> toRows(const Eigen::MatrixXd& rows) {
  std::vector<Eigen::VectorXd> out;
  out.reserve(static_cast<std::size_t>(rows.rows()));
  for (Eigen::Index i = 0; i < rows.rows(); ++i) out.emplace_back(rows.row(i).transpose());
  return out;
}

// (N, dim) from N vectors of one size ((0, 0) when empty).
Eigen::MatrixXd fromRows(const std::vector<Eigen::VectorXd>& rows) {
  if (rows.empty()) return {};
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), rows.front().size());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
  return out;
}

// Poses (N, poseDof) of `mechanism` as the C++ calls take them; ValueError naming the call.
std::vector<Eigen::VectorXd> poseRows(const mech::Mechanism& mechanism, const Eigen::MatrixXd& poses,
                                      const std::string& what) {
  if (poses.cols() != mechanism.poseDof())
    throw py::value_error(what + ": poses must have " + std::to_string(mechanism.poseDof()) + " columns (" +
                          py::str(py::cast(mechanism.poseComponentNames())).cast<std::string>() + "), got " +
                          std::to_string(poses.cols()));
  return toRows(poses);
}

void bindWorkspace(py::module_& m) {
  using I = mech::Interval;
  py::class_<I>(m, "Interval")
      .def(py::init([](double min, double max) {
             return I{min, max};
           }),
           py::arg("min") = 0.0, py::arg("max") = 0.0)
      .def_readwrite("min", &I::min)
      .def_readwrite("max", &I::max)
      .def("width", &I::width)
      .def("centre", &I::centre)
      .def("__repr__", [](const I& i) {
        return "Interval(" + py::repr(py::float_(i.min)).cast<std::string>() + ", " +
               py::repr(py::float_(i.max)).cast<std::string>() + ")";
      });
  using W = mech::Workspace;
  py::class_<W> workspace(m, "Workspace");
  py::enum_<W::Shape>(workspace, "Shape").value("Box", W::Shape::Box).value("Cylinder", W::Shape::Cylinder);
  workspace.def(py::init<>())
      .def_readwrite("shape", &W::shape)
      .def_readwrite("x", &W::x)
      .def_readwrite("y", &W::y)
      .def_readwrite("z", &W::z)
      .def_readwrite("rotations", &W::rotations, "list of Interval [rad] (assign a new list; a copy is returned)")
      .def_readwrite("joint_margin", &W::joint_margin)
      .def_readwrite("min_jacobian_ratio", &W::min_jacobian_ratio);
  m.def(
      "protocolWorkspace",
      [](const std::shared_ptr<mech::Mechanism>& mechanism, const Eigen::VectorXd& geometric) {
        return mech::protocolWorkspace(*mechanism, geometric);
      },
      py::arg("mechanism"), py::arg("geometric"));
  m.def(
      "validateWorkspace",
      [](const W& workspace, const std::shared_ptr<mech::Mechanism>& mechanism) {
        mech::validateWorkspace(workspace, *mechanism);
      },
      py::arg("workspace"), py::arg("mechanism"));
  m.def(
      "generateCandidatePoses",
      [](const std::shared_ptr<mech::Mechanism>& mechanism, const Eigen::VectorXd& geometric, const W& workspace,
         int count, unsigned seed) {
        py::gil_scoped_release release;
        return fromRows(mech::generateCandidatePoses(*mechanism, geometric, workspace, count, seed));
      },
      py::arg("mechanism"), py::arg("geometric"), py::arg("workspace"), py::arg("count"), py::arg("seed") = 1u,
      "Candidate poses (count, poseDof) drawn uniformly in the workspace, reproducible for a seed.");
  m.def(
      "candidateAcceptable",
      [](const std::shared_ptr<mech::Mechanism>& mechanism, const Eigen::VectorXd& geometric, const W& workspace,
         const Eigen::VectorXd& pose) { return mech::candidateAcceptable(*mechanism, geometric, workspace, pose); },
      py::arg("mechanism"), py::arg("geometric"), py::arg("workspace"), py::arg("pose"));
}

void bindModels(py::module_& m) {
  using G = mech::MountingGuess;
  py::class_<G>(m, "MountingGuess")
      .def(py::init<>())
      .def_property(
          "bTc", [](const G& g) { return toMatrix(g.bTc); },
          [](G& g, const Eigen::Matrix4d& t) { g.bTc = toIsometry(t, "MountingGuess.bTc"); }, "camera in base, 4×4")
      .def_property(
          "mTe", [](const G& g) { return toMatrix(g.mTe); },
          [](G& g, const Eigen::Matrix4d& t) { g.mTe = toIsometry(t, "MountingGuess.mTe"); }, "effector in target, 4×4")
      .def_readwrite("camera_on_effector", &G::camera_on_effector,
                     "the camera on the effector: eTc and bTm are the mounting, bTc and mTe unused")
      .def_property(
          "eTc", [](const G& g) { return toMatrix(g.eTc); },
          [](G& g, const Eigen::Matrix4d& t) { g.eTc = toIsometry(t, "MountingGuess.eTc"); },
          "camera in effector, 4×4 (camera on the effector)")
      .def_property(
          "bTm", [](const G& g) { return toMatrix(g.bTm); },
          [](G& g, const Eigen::Matrix4d& t) { g.bTm = toIsometry(t, "MountingGuess.bTm"); },
          "target in base, 4×4 (camera on the effector)");
  m.def("defaultMountingGuess", &mech::defaultMountingGuess, py::arg("workspace"), py::arg("camera_on_effector") = false);
  py::enum_<mech::DesignCriterion>(m, "DesignCriterion")
      .value("D", mech::DesignCriterion::D)
      .value("A", mech::DesignCriterion::A)
      .value("E", mech::DesignCriterion::E);
  m.def("designCriterionName", &mech::designCriterionName);
  py::class_<mech::DesignModel>(m, "DesignModel")
      .def_readonly("registered", &mech::DesignModel::registered)
      .def_readonly("h4", &mech::DesignModel::h4);
  m.def("makeDesignModel", &mech::makeDesignModel, py::arg("name"), py::arg("h4") = mech::H4Nominal{},
        "The registry entry `name` at its nominal geometry (H4 models: from the model-12 values `h4`).");
  m.def("withCameraOnEffector", &mech::withCameraOnEffector, py::arg("model"),
        "the design model with the camera on the effector (ValueError for the H4's models)");
  m.def("initialModelFor", &mech::initialModelFor, py::arg("model"), py::arg("observations"),
        py::call_guard<py::gil_scoped_release>());
}

void bindDesignOptions(py::module_& m) {
  using O = mech::DesignOptions;
  py::class_<O>(m, "DesignOptions")
      .def(py::init<>())
      .def_readwrite("criterion", &O::criterion)
      .def_readwrite("count", &O::count)
      .def_readwrite("sigma_translation", &O::sigma_translation)
      .def_readwrite("sigma_rotation", &O::sigma_rotation)
      .def_readwrite("random_designs", &O::random_designs)
      .def_readwrite("seed", &O::seed)
      .def_readwrite("max_exchanges", &O::max_exchanges);
  using C = mech::CandidateInformation;
  py::class_<C>(m, "CandidateInformation")
      .def_readonly("model", &C::model)
      .def_readonly("free_names", &C::free_names)
      .def_readonly("geometric_free", &C::geometric_free)
      .def_property_readonly(
          "poses", [](const C& c) { return fromRows(c.poses); }, "(N, poseDof)")
      .def_readonly("observations", &C::observations)
      .def_readonly("rows", &C::rows, "whitened Jacobian rows per candidate (jointCount, free)")
      .def_readonly("shared_covariance", &C::shared_covariance, "Σ_k of the shared term (empty without)")
      .def_readonly("shared_rows", &C::shared_rows, "whitened shared rows per candidate (jointCount, n)")
      .def("hasSharedTerm", &C::hasSharedTerm);
}

// candidateInformation with the poses as an (N, poseDof) array and, optionally, a Python
// callable cTm (6,) -> 6×6 covariance or None (None: the options' σ), and the calibration's
// shared term: Σ_k (n × n) with a callable cTm (6,) -> ∂cTm/∂k (6 × n).
mech::CandidateInformation candidateInformation(
    const mech::DesignModel& model, const mech::MountingGuess& mounting, const Eigen::MatrixXd& poses,
    const mech::DesignOptions& options, const std::optional<mech::PoseCovarianceProvider>& covariance,
    const std::optional<Eigen::MatrixXd>& shared_covariance,
    const std::optional<std::function<Eigen::MatrixXd(const mech::PoseVector&)>>& shared_sensitivity) {
  const auto rows = poseRows(*model.registered.mechanism, poses, "candidateInformation");
  const mech::PoseCovarianceProvider provider = covariance.value_or(mech::PoseCovarianceProvider{});
  if (shared_covariance.has_value() != shared_sensitivity.has_value())
    throw std::invalid_argument("candidateInformation: shared_covariance and shared_sensitivity go together");
  mech::SharedTermModel shared;
  if (shared_covariance) shared = {*shared_covariance, *shared_sensitivity};
  py::gil_scoped_release release;  // a Python provider takes the GIL back for each call
  return mech::candidateInformation(model, mounting, rows, options, provider, shared);
}

void bindDesign(py::module_& m) {
  const auto release = py::call_guard<py::gil_scoped_release>();
  m.def("candidateInformation", &candidateInformation, py::arg("model"), py::arg("mounting"), py::arg("poses"),
        py::arg("options") = mech::DesignOptions{}, py::arg("covariance") = py::none(),
        py::arg("shared_covariance") = py::none(), py::arg("shared_sensitivity") = py::none());
  m.def("fisherInformation", &mech::fisherInformation, py::arg("info"), py::arg("design"), release);
  m.def("designCovariance", &mech::designCovariance, py::arg("info"), py::arg("design"), release);
  m.def("designSigma", &mech::designSigma, py::arg("info"), py::arg("design"), release);
  m.def("designSharedCovariance", &mech::designSharedCovariance, py::arg("info"), py::arg("design"), release);
  m.def("chooseDesign", &mech::chooseDesign, py::arg("info"), py::arg("options"), release);
  m.def("predictedPositionSigma", &mech::predictedPositionSigma, py::arg("info"), py::arg("covariance"),
        py::arg("poses"), release);
  using R = mech::DesignReport;
  py::class_<R>(m, "DesignReport")
      .def_readonly("criterion", &R::criterion)
      .def_readonly("design", &R::design)
      .def_readonly("names", &R::names)
      .def_readonly("units", &R::units)
      .def_readonly("geometric_free", &R::geometric_free)
      .def_readonly("sigma_plan", &R::sigma_plan)
      .def_readonly("sigma_plan_shared", &R::sigma_plan_shared)
      .def_readonly("sigma_random", &R::sigma_random)
      .def_readonly("sigma_all", &R::sigma_all)
      .def_readonly("median_ratio_plan_random", &R::median_ratio_plan_random)
      .def_readonly("position_sigma_plan_rms", &R::position_sigma_plan_rms)
      .def_readonly("position_sigma_random_rms", &R::position_sigma_random_rms)
      .def_readonly("position_sigma_plan_max", &R::position_sigma_plan_max)
      .def_readonly("random_designs_used", &R::random_designs_used)
      .def_readonly("seconds", &R::seconds);
  m.def("planExperiment", &mech::planExperiment, py::arg("info"), py::arg("options"), release);
  m.def("designReportText", &mech::designReportText, py::arg("report"));
}

std::vector<mech::SelectionCandidate> parseSelectionCandidates(
    const std::string& text, const std::optional<std::function<mech::DesignModel(const std::string&)>>& make) {
  if (make) return mech::parseSelectionCandidates(text, *make);
  return mech::parseSelectionCandidates(text, [](const std::string& name) { return mech::makeDesignModel(name); });
}

void bindSelectionInputs(py::module_& m) {
  using C = mech::SelectionCandidate;
  py::class_<C>(m, "SelectionCandidate")
      .def_readonly("label", &C::label)
      .def_readonly("model", &C::model)
      .def_property_readonly(
          "variant", [](const C& c) { return c.variant ? std::string(1, c.variant) : std::string(); },
          "H4 variant letter, '' for a plain registry model");
  m.def("parseSelectionCandidates", &parseSelectionCandidates, py::arg("text"), py::arg("make") = py::none(),
        "'h4-12:A,B,C,D,h4-31c:E,F,G,H' or 'delta,delta-legs'; `make(name)` -> DesignModel (default "
        "makeDesignModel(name)).");
  m.def("defaultSelectionModels", &mech::defaultSelectionModels, py::arg("joint_count"), py::arg("unit"));
  using O = mech::SelectionOptions;
  py::class_<O>(m, "SelectionOptions").def(py::init<>()).def_readwrite("folds", &O::folds).def_readwrite("seed", &O::seed);
}

void bindSelectionResult(py::module_& m) {
  using S = mech::ModelScore;
  py::class_<S>(m, "ModelScore")
      .def_readonly("label", &S::label)
      .def_readonly("ok", &S::ok)
      .def_readonly("message", &S::message)
      .def_readonly("parameters", &S::parameters)
      .def_readonly("cv_mse", &S::cv_mse)
      .def_readonly("cv_se", &S::cv_se)
      .def("cv_rms", &S::cv_rms)
      .def("cv_rms_se", &S::cv_rms_se)
      .def_readonly("fit_rms", &S::fit_rms)
      .def_readonly("chi2", &S::chi2)
      .def_readonly("weighted", &S::weighted)
      .def_readonly("residuals", &S::residuals)
      .def_readonly("aic", &S::aic)
      .def_readonly("bic", &S::bic)
      .def_readonly("condition", &S::condition)
      .def_readonly("rank", &S::rank)
      .def_readonly("v3", &S::v3)
      .def_readonly("model_name", &S::model_name)
      .def_readonly("free_names", &S::free_names);
  using T = mech::NestedTest;
  py::class_<T>(m, "NestedTest")
      .def_readonly("simpler", &T::simpler)
      .def_readonly("richer", &T::richer)
      .def_readonly("F", &T::F)
      .def_readonly("p_value", &T::p_value)
      .def_readonly("df1", &T::df1)
      .def_readonly("df2", &T::df2);
  using R = mech::SelectionResult;
  py::class_<R>(m, "SelectionResult")
      .def_readonly("scores", &R::scores)
      .def_readonly("tests", &R::tests)
      .def_readonly("best", &R::best)
      .def_readonly("recommended", &R::recommended)
      .def_readonly("seconds", &R::seconds)
      .def("recommendedLabel", &R::recommendedLabel);
  m.def("selectModel", &mech::selectModel, py::arg("candidates"), py::arg("poses"),
        py::arg("lines") = std::vector<mech::LineRecord>{}, py::arg("options") = mech::SelectionOptions{},
        py::call_guard<py::gil_scoped_release>());
  m.def("selectionTable", &mech::selectionTable, py::arg("result"), py::arg("joint_unit"));
}

}  // namespace

void bindExperiment(py::module_& m) {
  bindWorkspace(m);
  bindModels(m);
  bindDesignOptions(m);
  bindDesign(m);
  bindSelectionInputs(m);
  bindSelectionResult(m);
}

}  // namespace mire::python
