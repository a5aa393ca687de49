// mire.pipeline: the end-to-end stages (mire/pipeline/*.hpp), the recipe `mire identify` runs.
#include "bindings.hpp"

#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace mire::python {

namespace pipe = mire::pipeline;
namespace mech = mire::mechanism;

void bindPipeline(py::module_& m) {
  py::class_<pipe::ModelChoice>(m, "ModelChoice")
      .def(py::init<>())
      .def_readwrite("model", &pipe::ModelChoice::model)
      .def_property(
          "variant", [](const pipe::ModelChoice& c) { return c.variant ? std::string(1, c.variant) : std::string(); },
          [](pipe::ModelChoice& c, const std::string& v) { c.variant = v.empty() ? 0 : v[0]; })
      .def_readwrite("h4", &pipe::ModelChoice::h4)
      .def_readwrite("nominal", &pipe::ModelChoice::nominal)
      .def("label", &pipe::ModelChoice::label)
      .def("registered", &pipe::ModelChoice::registered);
  m.def(
      "applyNominalFile",
      [](pipe::ModelChoice choice, const std::filesystem::path& file) {
        pipe::applyNominalFile(choice, file);
        return choice;
      },
      py::arg("choice"), py::arg("file"),
      "a copy of `choice` starting from the geometry of a parameter file, as `--nominal` reads it");
  m.def("chooseModel", &pipe::chooseModel, py::arg("model") = "", py::arg("variant") = "",
        py::arg("h4") = mech::H4Nominal{},
        "the model by name, completed as `mire identify --model --variant` does (ValueError names the option)");

  py::enum_<pipe::RefitGauge>(m, "RefitGauge")
      .value("HeldAtMainFit", pipe::RefitGauge::HeldAtMainFit)
      .value("Reinitialised", pipe::RefitGauge::Reinitialised);
  py::class_<pipe::IdentifyOptions>(m, "IdentifyOptions")
      .def(py::init<>())
      .def_readwrite("fit", &pipe::IdentifyOptions::fit)
      .def_readwrite("refit_gauge", &pipe::IdentifyOptions::refit_gauge);
  py::class_<pipe::InitialModel>(m, "InitialModel")
      .def_readonly("model", &pipe::InitialModel::model)
      .def_readonly("label", &pipe::InitialModel::label)
      .def_readonly("gauge", &pipe::InitialModel::gauge);
  py::class_<pipe::Identification>(m, "Identification")
      .def_readonly("initial", &pipe::Identification::initial)
      .def_readonly("result", &pipe::Identification::result)
      .def_readonly("mean_orientation_covariance", &pipe::Identification::mean_orientation_covariance);
  m.def("initialModel", &pipe::initialModel, py::arg("choice"), py::arg("poses"),
        py::arg("options") = mech::IdentificationOptions{});
  m.def("identify", &pipe::identify, py::arg("choice"), py::arg("poses"), py::arg("shared") = py::none(),
        py::arg("options") = pipe::IdentifyOptions{},
        "initial model, gauge, weighted fit, the shared calibration term by refits, the translating target's "
        "orientation: `mire identify`'s recipe");

  py::class_<pipe::PoseSetFiles>(m, "PoseSetFiles")
      .def(py::init<>())
      .def_static("beside", &pipe::PoseSetFiles::beside, py::arg("poses"), py::arg("joints"))
      .def_readwrite("poses", &pipe::PoseSetFiles::poses)
      .def_readwrite("joints", &pipe::PoseSetFiles::joints)
      .def_readwrite("covariances", &pipe::PoseSetFiles::covariances)
      .def_readwrite("shared", &pipe::PoseSetFiles::shared)
      .def_readwrite("lines", &pipe::PoseSetFiles::lines);
  py::class_<pipe::PoseSet>(m, "PoseSet")
      .def_readonly("observations", &pipe::PoseSet::observations)
      .def_readonly("shared", &pipe::PoseSet::shared)
      .def_readonly("lines", &pipe::PoseSet::lines)
      .def("lineJoints", &pipe::PoseSet::lineJoints);
  m.def("readPoseSet", &pipe::readPoseSet, py::arg("files"), py::arg("joint_columns"));
}

}  // namespace mire::python
