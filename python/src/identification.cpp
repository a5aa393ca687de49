// Identification (paper eq. 2/4): the model, options and result, the H4 variants A–H, the
// identifiability report and gauge analysis, and the evaluation criteria (V1–V3, square test,
// Monte-Carlo study).
#include "bindings.hpp"

#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/mechanism/variants.hpp"
#include "mire/support/side_files.hpp"

#include <memory>

#include <pybind11/functional.h>

namespace mire::python {
namespace {

namespace mech = mechanism;
using MechanismPtr = std::shared_ptr<mech::Mechanism>;

void bindIdentifiability(py::module_& m) {
  using O = mech::IdentifiabilityOptions;
  py::class_<O>(m, "IdentifiabilityOptions")
      .def(py::init<>())
      .def_readwrite("rank_tolerance", &O::rank_tolerance)
      .def_readwrite("coefficient_tolerance", &O::coefficient_tolerance);
  using C = mech::UnidentifiableCombination;
  py::class_<C>(m, "UnidentifiableCombination")
      .def_readonly("dependent", &C::dependent)
      .def_readonly("direction", &C::direction)
      .def_readonly("identifiable_sums", &C::identifiable_sums)
      .def_readonly("singular_value", &C::singular_value)
      .def("text", &C::text);
  using R = mech::IdentifiabilityReport;
  py::class_<R>(m, "IdentifiabilityReport")
      .def_readonly("parameter_names", &R::parameter_names)
      .def_readonly("scaling", &R::scaling)
      .def_readonly("column_norms", &R::column_norms)
      .def_readonly("singular_values", &R::singular_values)
      .def_readonly("condition_number", &R::condition_number)
      .def_readonly("condition_number_unscaled", &R::condition_number_unscaled)
      .def_readonly("condition_number_identifiable", &R::condition_number_identifiable)
      .def_readonly("rank", &R::rank)
      .def_readonly("identifiable", &R::identifiable)
      .def_readonly("unidentifiable", &R::unidentifiable)
      .def_readonly("combinations", &R::combinations)
      .def("fullRank", &R::fullRank)
      .def("text", &R::text);
  m.def("analyzeJacobian", &mech::analyzeJacobian, py::arg("jacobian"), py::arg("names"), py::arg("options") = O{});
  using G = mech::GaugeAnalysis;
  py::class_<G>(m, "GaugeAnalysis")
      .def_readonly("report", &G::report)
      .def_readonly("identified", &G::identified)
      .def_readonly("combination_only", &G::combination_only)
      .def_readonly("gauge", &G::gauge)
      .def_readonly("no_influence", &G::no_influence)
      .def("text", &G::text);
}

void bindModel(py::module_& m) {
  using IM = mech::IdentificationModel;
  py::class_<IM>(m, "IdentificationModel")
      .def_property(
          "mechanism", [](const IM& s) { return std::const_pointer_cast<mech::Mechanism>(s.mechanism); },
          [](IM& s, const MechanismPtr& p) { s.mechanism = p; })
      .def_readwrite("external", &IM::external)
      .def_readwrite("parameters", &IM::parameters)
      .def("geometricCount", &IM::geometricCount)
      .def("geometricValues", &IM::geometricValues)
      .def("externalValues", &IM::externalValues)
      .def("predictJoints", &IM::predictJoints, py::arg("cTm"))
      .def("copy", [](const IM& s) { return IM(s); });
  m.def(
      "makeIdentificationModel",
      [](const MechanismPtr& mechanism, const mech::ParameterSet& geometric,
         const mech::ExternalParameterization& external, const mech::ParameterSet& values) {
        return mech::makeIdentificationModel(mechanism, geometric, external, values);
      },
      py::arg("mechanism"), py::arg("geometric"), py::arg("external"), py::arg("external_values"));
  m.def(
      "makeInitialModel",
      [](const MechanismPtr& mechanism, const mech::ParameterSet& geometric,
         const std::vector<mech::PoseObservation>& poses, mech::ExternalForm form, double z_ME) {
        py::gil_scoped_release release;
        return mech::makeInitialModel(mechanism, geometric, poses, form, z_ME);
      },
      py::arg("mechanism"), py::arg("geometric"), py::arg("poses"), py::arg("form"), py::arg("z_ME") = 0.0);
  m.def("unreachablePoses", &mech::unreachablePoses, py::arg("model"), py::arg("poses"));

  py::enum_<mech::RobustLoss>(m, "RobustLoss")
      .value("None_", mech::RobustLoss::None)
      .value("Huber", mech::RobustLoss::Huber)
      .value("Cauchy", mech::RobustLoss::Cauchy);
  py::class_<mech::GaussianPrior>(m, "GaussianPrior")
      .def(py::init([](std::string name, double mean, double sigma) {
             return mech::GaussianPrior{std::move(name), mean, sigma};
           }),
           py::arg("name"), py::arg("mean"), py::arg("sigma"))
      .def_readwrite("name", &mech::GaussianPrior::name)
      .def_readwrite("mean", &mech::GaussianPrior::mean)
      .def_readwrite("sigma", &mech::GaussianPrior::sigma);
  using IO = mech::IdentificationOptions;
  py::class_<IO>(m, "IdentificationOptions")
      .def(py::init<>())
      .def_readwrite("fix", &IO::fix)
      .def_readwrite("release", &IO::release)
      .def_readwrite("priors", &IO::priors)
      .def_readwrite("use_pose_covariances", &IO::use_pose_covariances)
      .def_readwrite("joint_sigma", &IO::joint_sigma)
      .def_readwrite("loss", &IO::loss)
      .def_readwrite("loss_scale", &IO::loss_scale)
      .def_readwrite("outlier_probability", &IO::outlier_probability)
      .def_readwrite("max_iterations", &IO::max_iterations)
      .def_readwrite("compute_identifiability", &IO::compute_identifiability)
      .def_readwrite("identifiability", &IO::identifiability);
}

void bindResult(py::module_& m) {
  using PR = mech::PoseResidual;
  py::class_<PR>(m, "PoseResidual")
      .def_readonly("id", &PR::id)
      .def_readonly("residual", &PR::residual)
      .def_readonly("chi2", &PR::chi2)
      .def_readonly("outlier", &PR::outlier);
  using CT = mech::CovarianceTerm;
  py::class_<CT>(m, "CovarianceTerm")
      .def_readonly("name", &CT::name)
      .def_readonly("method", &CT::method)
      .def_readonly("scale2", &CT::scale2)
      .def_readonly("covariance", &CT::covariance);
  using R = mech::IdentificationResult;
  py::class_<R>(m, "IdentificationResult")
      .def_readwrite("model", &R::model)
      .def_readonly("free_names", &R::free_names)
      .def_readonly("covariance", &R::covariance)
      .def_property_readonly("alignment_covariance",
                             [](const R& r) { return r.termCovariance(mech::CovarianceTerm::kAlignment); })
      .def_readonly("covariance_terms", &R::covariance_terms, "the named terms summed into `covariance`")
      .def_readonly("sigma", &R::sigma)
      .def("sigmaOf", &R::sigmaOf)
      .def_readonly("weighted", &R::weighted)
      .def_readonly("chi2", &R::chi2)
      .def_readonly("dof", &R::dof)
      .def_readonly("residual_scale", &R::residual_scale)
      .def_property_readonly("covariance_method", &R::covarianceMethod)
      .def_property_readonly("covariance_scale2", &R::covarianceScale2)
      .def_readonly("misfit_scale2", &R::misfit_scale2)
      .def_readonly("rms_joint_residual", &R::rms_joint_residual)
      .def_readonly("poses", &R::poses)
      .def_readonly("outliers", &R::outliers)
      .def_readonly("identifiability", &R::identifiability)
      .def_readonly("converged", &R::converged)
      .def_readonly("iterations", &R::iterations)
      .def_readonly("solve_seconds", &R::solve_seconds)
      .def_readonly("solver_report", &R::solver_report);
  const auto release = py::call_guard<py::gil_scoped_release>();
  m.def("identify", &mech::identify, py::arg("model"), py::arg("poses"),
        py::arg("options") = mech::IdentificationOptions{}, release);
  m.def("identificationJacobian", &mech::identificationJacobian, py::arg("model"), py::arg("poses"), release);
  m.def("analyzeIdentifiability", &mech::analyzeIdentifiability, py::arg("model"), py::arg("poses"),
        py::arg("options") = mech::IdentifiabilityOptions{}, release);
  m.def("modelConsistentPoses", &mech::modelConsistentPoses, py::arg("model"), py::arg("poses"), release);
  m.def("analyzeGauge", &mech::analyzeGauge, py::arg("model"), py::arg("poses"),
        py::arg("options") = mech::IdentifiabilityOptions{}, release);
  m.def(
      "fixGauge",
      [](mech::IdentificationModel& model, const std::vector<mech::PoseObservation>& poses,
         const mech::IdentifiabilityOptions& options) { return mech::fixGauge(model, poses, options); },
      py::arg("model"), py::arg("poses"), py::arg("options") = mech::IdentifiabilityOptions{},
      "analyzeGauge, then fixes the gauge parameters in `model` (in place).");
  m.def(
      "alignTranslatingTarget",
      [](const MechanismPtr& mechanism, const mech::ExternalParameterization& form, mech::ParameterSet& parameters,
         const std::vector<mech::PoseObservation>& poses) {
        mech::alignTranslatingTarget(*mechanism, form, parameters, poses);
      },
      py::arg("mechanism"), py::arg("form"), py::arg("parameters"), py::arg("poses"),
      "Updates `parameters` in place (values only: prefer the overload on a result).");
  m.def(
      "alignTranslatingTarget",
      [](mech::IdentificationResult& result, const std::vector<mech::PoseObservation>& poses) {
        return mech::alignTranslatingTarget(result, poses);
      },
      py::arg("result"), py::arg("poses"),
      "On an identification result, as `mire identify` does for a translating plate (Delta): sets the "
      "target's rotation from the measured orientations, turns the covariance rows of the target offset "
      "with it (in place) and returns the 3x3 covariance of the mean orientation; None (and no change) "
      "for other motions.");
}

// The H4 variants A–H (paper Table 2) and the calibration term shared by every pose.
void bindVariants(py::module_& m) {
  const auto release = py::call_guard<py::gil_scoped_release>();
  py::class_<mech::H4Variant>(m, "H4Variant")
      .def_readonly("letter", &mech::H4Variant::letter)
      .def_readonly("model", &mech::H4Variant::model)
      .def_readonly("external", &mech::H4Variant::external)
      .def_readonly("fixed", &mech::H4Variant::fixed)
      .def_readonly("tied", &mech::H4Variant::tied)
      .def_readonly("geometric_count", &mech::H4Variant::geometric_count)
      .def_readonly("external_count", &mech::H4Variant::external_count)
      .def_readonly("description", &mech::H4Variant::description);
  m.def("h4Variants", &mech::h4Variants);
  m.def("h4Variant", &mech::h4Variant, py::arg("letter"));
  m.def("makeH4VariantModel", &mech::makeH4VariantModel, py::arg("letter"), py::arg("nominal"), py::arg("poses"),
        py::arg("options") = mech::IdentificationOptions{}, release);
  m.def("identifyH4Variant", &mech::identifyH4Variant, py::arg("letter"), py::arg("nominal"), py::arg("poses"),
        py::arg("options") = mech::IdentificationOptions{}, release);
  // The calibration term shared by every pose (doc/uncertainty.md): `refit` is called with the
  // shifted poses and returns the identification result of the whole estimator on them.
  using T = mech::SharedPoseTerm;
  py::class_<T>(m, "SharedPoseTerm")
      .def_readonly("names", &T::names)
      .def_readonly("covariance", &T::covariance)
      .def("poseCovariance", &T::poseCovariance, py::arg("pose_id"));
  m.def("sharedTermPath", &mire::support::sharedTermSidePath, py::arg("poses_csv"));
  m.def("readSharedTermCsv", &mech::readSharedTermCsv, py::arg("path"));
  m.def("addSharedTermCovariance", &mech::addSharedTermCovariance, py::arg("result"), py::arg("poses"),
        py::arg("shared"), py::arg("refit") = mech::Refit{});
}

// V1/V2 (joint residuals), V3 (straightness, eq. 29) and the square test.
void bindEvaluation(py::module_& m) {
  using J = mech::JointResidualCriteria;
  py::class_<J>(m, "JointResidualCriteria")
      .def_readonly("v1_rad", &J::v1_rad)
      .def_readonly("v2_rad", &J::v2_rad)
      .def_readonly("pose_count", &J::pose_count)
      .def_readonly("unreachable", &J::unreachable);
  m.def("jointResidualCriteria", &mech::jointResidualCriteria, py::arg("model"), py::arg("validation"));
  m.def(
      "straightness",
      [](const py::handle& points) { return mech::straightness(toPoints3(points, "straightness: points")); },
      py::arg("points"));
  using S = mech::StraightnessResult;
  py::class_<S>(m, "StraightnessResult")
      .def_readonly("per_line_m", &S::per_line_m)
      .def_readonly("v3_m", &S::v3_m)
      .def_property_readonly("points",
                             [](const S& s) {
                               py::list out;
                               for (const auto& line : s.points) out.append(toArray(line));
                               return out;
                             })
      .def_readonly("ok", &S::ok)
      .def_readonly("message", &S::message);
  m.def(
      "straightnessCriterion",
      [](const MechanismPtr& mechanism, const Eigen::VectorXd& geometric, const std::vector<Eigen::MatrixXd>& lines) {
        std::vector<std::vector<Eigen::VectorXd>> joints;
        for (const auto& line : lines) {
          joints.emplace_back();
          for (Eigen::Index r = 0; r < line.rows(); ++r) joints.back().push_back(line.row(r).transpose());
        }
        py::gil_scoped_release release;
        return mech::straightnessCriterion(*mechanism, geometric, joints);
      },
      py::arg("mechanism"), py::arg("geometric"), py::arg("lines"),
      "V3 (eq. 29) from recorded lines: a list of (N_i, jointCount) joint arrays.");
  m.def(
      "commandJoints",
      [](const MechanismPtr& mechanism, const Eigen::VectorXd& geometric, const std::vector<Eigen::VectorXd>& poses) {
        return mech::commandJoints(*mechanism, geometric, poses);
      },
      py::arg("mechanism"), py::arg("geometric"), py::arg("poses"));
  m.def("squareCorners", &mech::squareCorners, py::arg("centre"), py::arg("side"));
  m.def("squareSideErrors", &mech::squareSideErrors, py::arg("reached_corners"), py::arg("side"));
}

// The Monte-Carlo study of the paper's §6.2 (random pose subsets, spread of the identified values).
void bindMonteCarlo(py::module_& m) {
  using MO = mech::MonteCarloOptions;
  py::class_<MO>(m, "MonteCarloOptions")
      .def(py::init<>())
      .def_readwrite("subset_sizes", &MO::subset_sizes)
      .def_readwrite("repeats", &MO::repeats)
      .def_readwrite("seed", &MO::seed)
      .def_readwrite("threads", &MO::threads)
      .def_readwrite("identification", &MO::identification);
  using MR = mech::MonteCarloRun;
  py::class_<MR>(m, "MonteCarloRun")
      .def_readonly("subset", &MR::subset)
      .def_readonly("ok", &MR::ok)
      .def_readonly("error", &MR::error)
      .def_readonly("values", &MR::values)
      .def_readonly("v1_rad", &MR::v1_rad)
      .def_readonly("v2_rad", &MR::v2_rad)
      .def_readonly("v3_m", &MR::v3_m);
  using MS = mech::MonteCarloSummary;
  py::class_<MS>(m, "MonteCarloSummary")
      .def_readonly("subset_size", &MS::subset_size)
      .def_readonly("runs_ok", &MS::runs_ok)
      .def_readonly("runs_failed", &MS::runs_failed)
      .def_readonly("mean", &MS::mean)
      .def_readonly("sigma", &MS::sigma)
      .def_readonly("v1_mean", &MS::v1_mean)
      .def_readonly("v1_sigma", &MS::v1_sigma)
      .def_readonly("v2_mean", &MS::v2_mean)
      .def_readonly("v2_sigma", &MS::v2_sigma)
      .def_readonly("v3_mean", &MS::v3_mean)
      .def_readonly("v3_sigma", &MS::v3_sigma)
      .def_readonly("runs", &MS::runs);
  py::class_<mech::MonteCarloStudy>(m, "MonteCarloStudy")
      .def_readonly("parameter_names", &mech::MonteCarloStudy::parameter_names)
      .def_readonly("summaries", &mech::MonteCarloStudy::summaries)
      .def_readonly("seconds", &mech::MonteCarloStudy::seconds);
  m.def(
      "runMonteCarloStudy",
      [](const mech::IdentificationModel& initial, const std::vector<mech::PoseObservation>& poses,
         const std::vector<std::vector<Eigen::VectorXd>>& line_joints, MO options) {
        options.on_run_done = nullptr;  // worker threads must not call into Python
        py::gil_scoped_release release;
        return mech::runMonteCarloStudy(initial, poses, line_joints, options);
      },
      py::arg("initial"), py::arg("poses"), py::arg("line_joints"), py::arg("options") = MO{});
}

}  // namespace

void bindIdentification(py::module_& m) {
  bindIdentifiability(m);
  bindModel(m);
  bindResult(m);
  bindVariants(m);
  bindEvaluation(m);
  bindMonteCarlo(m);
}

}  // namespace mire::python
