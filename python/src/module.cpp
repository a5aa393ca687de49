// `import mire`: submodules named after the C++ namespaces (mire.calibration, mire.metrology,
// mire.mechanism, mire.pipeline), the same class and function names as the C++ API (doc/python.md).
#include "bindings.hpp"

PYBIND11_MODULE(mire, m) {
  namespace mp = mire::python;
  m.doc() = "mire: camera calibration, target pose measurement and kinematic identification (doc/python.md)";
  mp::bindErrors(m);
  auto calibration = m.def_submodule("calibration", "cameras, camera files, calibration (mire::calibration)");
  auto metrology = m.def_submodule("metrology", "targets, detection, pose measurement (mire::metrology)");
  mp::bindCameras(calibration);
  mp::bindTargets(metrology);  // before calibration: calibrateFromImages takes a Target
  mp::bindCalibration(calibration);
  mp::bindMeasurement(metrology);
  auto mechanism =
      m.def_submodule("mechanism", "mechanisms, identification, evaluation, plan/select (mire::mechanism)");
  mp::bindMechanisms(mechanism);
  mp::bindExperiment(mechanism);
  mp::bindHandEye(mechanism);
  auto pipeline =
      m.def_submodule("pipeline", "the end-to-end stages: the identification recipe, pose sets (mire::pipeline)");
  mp::bindPipeline(pipeline);
  mp::bindCompensation(mechanism, pipeline);
  mp::bindAccuracy(pipeline);
#ifdef MIRE_VERSION
  m.attr("__version__") = MIRE_VERSION;
#endif
}
