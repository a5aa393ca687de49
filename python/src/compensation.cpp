// Closing the loop (doc/accuracy.md, "Compensation"): the identified robot's prediction model,
// what a controller loads for desired poses (`mire compensate`: joint commands, or the pose to
// command a controller that runs another geometry), and a controller model fitted to an
// identification.
#include "bindings.hpp"

#include "mire/mechanism/compensation.hpp"
#include "mire/mechanism/controller_fit.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace mire::python {
namespace {

namespace mech = mechanism;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The reason an IKM gives no command (the wording of `mire ikm` and `mire compensate --poses`).
std::string unreachableReason(const mech::IkmResult& ikm) {
  const auto joints = [](const std::vector<int>& indices) {
    std::string out;
    for (int j : indices) out += (out.empty() ? "" : ", ") + std::to_string(j + 1);
    return out;
  };
  if (!ikm.reachable()) return "unreachable (joint(s) " + joints(ikm.unreachable_joints) + ")";
  if (!ikm.withinStroke()) return "outside the stroke of joint(s) " + joints(ikm.out_of_stroke_joints);
  return "";
}

Eigen::MatrixXd requirePoses(const mech::Mechanism& m, const Eigen::MatrixXd& poses, const std::string& what) {
  if (poses.cols() != m.poseDof())
    throw py::value_error(what + ": poses must have " + std::to_string(m.poseDof()) + " columns (" +
                          py::str(py::cast(m.poseComponentNames())).cast<std::string>() + ")");
  return poses;
}

// One result per row: values (N, k) and σ (N, k) (NaN where none), covariances (N, k, k), reachable (N),
// messages (N; "" where reachable).
struct Rows {
  Eigen::MatrixXd values, sigma;
  py::array_t<double> covariance;
  std::vector<bool> reachable;
  std::vector<std::string> messages;

  Rows(Eigen::Index n, Eigen::Index k)
      : values(Eigen::MatrixXd::Constant(n, k, kNaN)),
        sigma(Eigen::MatrixXd::Constant(n, k, kNaN)),
        covariance({n, k, k}),
        reachable(static_cast<std::size_t>(n), false),
        messages(static_cast<std::size_t>(n)) {
    std::fill(covariance.mutable_data(), covariance.mutable_data() + n * k * k, kNaN);
  }
  void set(Eigen::Index i, const Eigen::VectorXd& value, const Eigen::MatrixXd& cov) {
    values.row(i) = value.transpose();
    sigma.row(i) = cov.diagonal().cwiseMax(0.0).cwiseSqrt().transpose();
    auto c = covariance.mutable_unchecked<3>();
    for (Eigen::Index r = 0; r < cov.rows(); ++r)
      for (Eigen::Index k = 0; k < cov.cols(); ++k) c(i, r, k) = cov(r, k);
    reachable[static_cast<std::size_t>(i)] = true;
  }
  py::dict dict(const char* name) const {
    py::dict out;
    out[name] = values;
    out["sigma"] = sigma;
    out["covariance"] = covariance;
    out["reachable"] = reachable;
    out["messages"] = messages;
    return out;
  }
};

// `mire compensate --poses` (joint commands, controller None) or the corrected poses of the
// correction map (a controller running `controller` geometry, the identified model's parameters).
py::dict compensate(const mech::PredictionModel& model, const Eigen::MatrixXd& poses,
                    const std::optional<Eigen::VectorXd>& controller) {
  const mech::Mechanism& m = *model.mechanism;
  requirePoses(m, poses, "compensate");
  if (controller && controller->size() != model.geometric.values().size())
    throw py::value_error("compensate: controller must have " + std::to_string(model.geometric.values().size()) +
                          " geometric values (the identified model's parameters, in its order)");
  const Eigen::Index n = poses.rows();
  if (!controller) {
    Rows rows(n, m.jointCount());
    {
      py::gil_scoped_release release;
      for (Eigen::Index i = 0; i < n; ++i) {
        const mech::JointPrediction p = mech::predictJointCommands(model, m.poseToTransform(poses.row(i).transpose()));
        const std::string why = unreachableReason(p.ikm);
        if (why.empty())
          rows.set(i, p.ikm.joints, p.covariance);
        else
          rows.messages[static_cast<std::size_t>(i)] = why;
      }
    }
    return rows.dict("joints");
  }
  Rows rows(n, m.poseDof());
  {
    py::gil_scoped_release release;
    for (Eigen::Index i = 0; i < n; ++i) {
      const mech::PoseCorrection c = mech::correctedCommand(model, *controller, poses.row(i).transpose());
      if (c.ok)
        rows.set(i, c.command, c.command_covariance);
      else
        rows.messages[static_cast<std::size_t>(i)] = c.message;
    }
  }
  return rows.dict("commands");
}

void bindPredictionModel(py::module_& m) {
  using PM = mech::PredictionModel;
  py::class_<PM>(m, "PredictionModel")
      .def(py::init([](const std::string& model_name, const mech::ParameterSet& geometric,
                       const std::optional<mech::ParameterSet>& mounting) {
             const mech::RegisteredModel r = mech::makeRegisteredModel(model_name);
             PM p;
             p.model_name = r.name;
             p.mechanism = r.mechanism;
             p.geometric = geometric;
             p.mounting = mounting ? *mounting : mech::ExternalParameterization(mech::ExternalForm::Full).parameters();
             return p;
           }),
           py::arg("model_name"), py::arg("geometric"), py::arg("mounting") = py::none(),
           "A model without covariance (σ 0): a registered model's name, its geometry, and the mounting in the "
           "full form (ExternalParameterization(ExternalForm.Full).parameters(); default identity)")
      .def_readonly("model_name", &PM::model_name)
      .def_property_readonly("mechanism",
                             [](const PM& p) { return std::const_pointer_cast<mech::Mechanism>(p.mechanism); })
      .def_readwrite("geometric", &PM::geometric)
      .def_readwrite("mounting", &PM::mounting)
      .def_readwrite("covariance_names", &PM::covariance_names)
      .def_readwrite("covariance", &PM::covariance)
      .def("cTb", [](const PM& p) { return toMatrix(p.cTb()); })
      .def("eTm", [](const PM& p) { return toMatrix(p.eTm()); });
  m.def("predictionModelFrom", &mech::predictionModelFrom, py::arg("model_name"), py::arg("result"),
        "geometry, full-form mounting and covariance of an identification result");
  py::class_<mech::LoadedPredictionModel>(m, "LoadedPredictionModel")
      .def_readonly("model", &mech::LoadedPredictionModel::model)
      .def_readonly("has_mounting", &mech::LoadedPredictionModel::has_mounting)
      .def_readonly("has_covariance", &mech::LoadedPredictionModel::has_covariance);
  m.def("loadPredictionModel", &mech::loadPredictionModel, py::arg("parameters_yaml"),
        py::arg("covariance_csv") = py::none(), "an identified parameter file and its covariance side file");
}

void bindControllerFit(py::module_& m) {
  using CF = mech::ControllerFit;
  py::class_<CF>(m, "ControllerFit")
      .def_readonly("parameters", &CF::parameters)
      .def_property_readonly("frame", [](const CF& f) { return toMatrix(f.frame); })
      .def_readonly("converged", &CF::converged)
      .def_readonly("rms_joint_residual", &CF::rms_joint_residual)
      .def_readonly("rms_position_error", &CF::rms_position_error)
      .def_readonly("max_position_error", &CF::max_position_error)
      .def_readonly("expected_rms_position_error", &CF::expected_rms_position_error)
      .def_readonly("sigma_rms_position_error", &CF::sigma_rms_position_error)
      .def_readonly("draws", &CF::draws)
      .def_readonly("worst_pose", &CF::worst_pose)
      .def_readonly("poses", &CF::poses);
  m.def(
      "fitControllerModel",
      [](const mech::PredictionModel& identified, const std::string& controller, const Eigen::MatrixXd& workspace) {
        const mech::RegisteredModel c = mech::makeRegisteredModel(controller);
        requirePoses(*c.mechanism, workspace, "fitControllerModel");
        std::vector<Eigen::VectorXd> poses;
        for (Eigen::Index i = 0; i < workspace.rows(); ++i) poses.push_back(workspace.row(i).transpose());
        py::gil_scoped_release release;
        return mech::fitControllerModel(identified, c, poses);
      },
      py::arg("identified"), py::arg("controller"), py::arg("workspace"),
      "`mire compensate --controller-model`: the controller model's parameters and frame F fitted so that the "
      "identified robot follows its commands over the workspace poses (N, poseDof), identified base frame");
  m.def(
      "workspaceGrid",
      [](const std::shared_ptr<mech::Mechanism>& mechanism, const Eigen::Vector3d& low, const Eigen::Vector3d& high,
         double step) {
        const auto grid = mech::workspaceGrid(*mechanism, low, high, step);
        Eigen::MatrixXd out(static_cast<Eigen::Index>(grid.size()), mechanism->poseDof());
        for (std::size_t i = 0; i < grid.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = grid[i].transpose();
        return out;
      },
      py::arg("mechanism"), py::arg("low"), py::arg("high"), py::arg("step"),
      "the points of a box `step` apart, corners included (N, poseDof)");
}

}  // namespace

void bindCompensation(py::module_& mechanism, py::module_& pipeline) {
  bindPredictionModel(mechanism);
  bindControllerFit(mechanism);
  pipeline.def("compensate", &compensate, py::arg("model"), py::arg("poses"), py::arg("controller") = py::none(),
               "`mire compensate` on arrays: for desired poses (N, poseDof) in the identified base frame, the joint "
               "commands {'joints' (N, J), 'sigma', 'covariance', 'reachable', 'messages'}; with `controller` (the "
               "geometric values a controller runs, the model's order) the poses to command it "
               "{'commands' (N, poseDof), ...}. NaN rows where no command exists, the reason in 'messages'.");
}

}  // namespace mire::python
