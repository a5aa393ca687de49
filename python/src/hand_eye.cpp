// Hand-eye calibration of a robot that reports its own pose (mechanism/hand_eye.hpp,
// doc/mechanisms.md "Hand-eye calibration"): observations, the joint solve with its covariance,
// OpenCV's closed forms, robot_poses.csv, the choice of poses (planHandEye). Transforms are 4×4 matrices, poses 6-vectors (t, r).
#include "bindings.hpp"

#include "mire/mechanism/hand_eye.hpp"

#include <optional>

namespace mire::python {

void bindHandEye(py::module_& m) {
  namespace mech = mechanism;
  py::enum_<mech::HandEyeMounting>(m, "HandEyeMounting")
      .value("CameraOnEffector", mech::HandEyeMounting::CameraOnEffector)
      .value("CameraFixed", mech::HandEyeMounting::CameraFixed);
  m.def("handEyeMountingName", &mech::handEyeMountingName, py::arg("mounting"));
  m.def("parseHandEyeMounting", &mech::parseHandEyeMounting, py::arg("text"));
  m.def("handEyeParameterNames", &mech::handEyeParameterNames, py::arg("mounting"));

  using S = mech::RobotPoseSigma;
  py::class_<S>(m, "RobotPoseSigma")
      .def(py::init([](double translation_m, double rotation_rad) {
             return S{translation_m, rotation_rad};
           }),
           py::arg("translation_m"), py::arg("rotation_rad"))
      .def_readwrite("translation_m", &S::translation_m)
      .def_readwrite("rotation_rad", &S::rotation_rad);
  using Row = mech::RobotPoseRow;
  py::class_<Row>(m, "RobotPoseRow")
      .def_readonly("id", &Row::id)
      .def_readonly("bTe", &Row::bTe)
      .def_readonly("sigma", &Row::sigma)
      .def_readonly("line", &Row::line);
  m.def("readRobotPosesCsv", &mech::readRobotPosesCsv, py::arg("robot_poses_csv"));

  using O = mech::HandEyeObservation;
  py::class_<O>(m, "HandEyeObservation")
      .def(py::init([](const std::string& id, const mech::PoseVector& bTe, const S& robot_sigma,
                       const mech::PoseVector& cTm, std::optional<mech::PoseCovariance> covariance) {
             return O{id, bTe, robot_sigma, cTm, covariance};
           }),
           py::arg("id"), py::arg("bTe"), py::arg("robot_sigma"), py::arg("cTm"), py::arg("cTm_covariance") = py::none())
      .def_readwrite("id", &O::id)
      .def_readwrite("bTe", &O::bTe)
      .def_readwrite("robot_sigma", &O::robot_sigma)
      .def_readwrite("cTm", &O::cTm)
      .def_readwrite("cTm_covariance", &O::cTm_covariance);

  using Opt = mech::HandEyeOptions;
  py::class_<Opt>(m, "HandEyeOptions")
      .def(py::init<>())
      .def_readwrite("outlier_chi2", &Opt::outlier_chi2)
      .def_readwrite("remove_outliers", &Opt::remove_outliers);
  using P = mech::HandEyePoseScore;
  py::class_<P>(m, "HandEyePoseScore")
      .def_readonly("id", &P::id)
      .def_readonly("chi2", &P::chi2)
      .def_readonly("camera_t_m", &P::camera_t_m)
      .def_readonly("camera_r_rad", &P::camera_r_rad)
      .def_readonly("robot_t_m", &P::robot_t_m)
      .def_readonly("robot_r_rad", &P::robot_r_rad);
  using R = mech::HandEyeResult;
  py::class_<R>(m, "HandEyeResult")
      .def_readonly("mounting", &R::mounting)
      .def_property_readonly("X", [](const R& r) { return toMatrix(r.X); })
      .def_property_readonly("Z", [](const R& r) { return toMatrix(r.Z); })
      .def_property_readonly("X_closed_form", [](const R& r) { return toMatrix(r.X_closed_form); })
      .def_property_readonly("Z_closed_form", [](const R& r) { return toMatrix(r.Z_closed_form); })
      .def_readonly("closed_form_method", &R::closed_form_method)
      .def_readonly("parameters", &R::parameters)
      .def_readonly("covariance", &R::covariance)
      .def_readonly("sigma", &R::sigma)
      .def_readonly("chi2", &R::chi2)
      .def_readonly("dof", &R::dof)
      .def_readonly("scale2", &R::scale2)
      .def_readonly("sigma_from_residuals", &R::sigma_from_residuals)
      .def_readonly("poses", &R::poses)
      .def_readonly("outliers", &R::outliers)
      .def_readonly("identifiability", &R::identifiability)
      .def_readonly("rotation_spread", &R::rotation_spread)
      .def_readonly("converged", &R::converged);
  m.def("solveHandEye", &mech::solveHandEye, py::arg("poses"), py::arg("mounting"), py::arg("options") = Opt{});
  using D = mech::HandEyeDesignModel;
  py::class_<D>(m, "HandEyeDesignModel")
      .def(py::init<>())
      .def_readwrite("mounting", &D::mounting)
      .def_property(
          "X", [](const D& d) { return toMatrix(d.X); },
          [](D& d, const Eigen::Matrix4d& X) { d.X = toIsometry(X, "HandEyeDesignModel.X"); })
      .def_property(
          "Z", [](const D& d) { return toMatrix(d.Z); },
          [](D& d, const Eigen::Matrix4d& Z) { d.Z = toIsometry(Z, "HandEyeDesignModel.Z"); })
      .def_readwrite("robot_sigma", &D::robot_sigma)
      .def_readwrite("camera_covariance", &D::camera_covariance);
  using Plan = mech::HandEyePlan;
  py::class_<Plan>(m, "HandEyePlan")
      .def_readonly("chosen", &Plan::chosen)
      .def_readonly("covariance", &Plan::covariance)
      .def_readonly("sigma", &Plan::sigma);
  m.def(
      "handEyePoseInformation",
      [](const D& model, const Eigen::Matrix4d& bTe) {
        return Eigen::MatrixXd(mech::handEyePoseInformation(model, toIsometry(bTe, "bTe")));
      },
      py::arg("model"), py::arg("bTe"));
  m.def(
      "planHandEye",
      [](const D& model, const std::vector<Eigen::Matrix4d>& candidates, std::size_t count) {
        std::vector<Eigen::Isometry3d> poses;
        for (const Eigen::Matrix4d& c : candidates) poses.push_back(toIsometry(c, "candidates"));
        return mech::planHandEye(model, poses, count);
      },
      py::arg("model"), py::arg("candidates"), py::arg("count"));
  m.def(
      "handEyeClosedForm",
      [](const std::vector<O>& poses, mech::HandEyeMounting mounting, const std::string& method) {
        const mech::HandEyeTransforms t = mech::handEyeClosedForm(poses, mounting, method);
        return py::make_tuple(toMatrix(t.X), toMatrix(t.Z));
      },
      py::arg("poses"), py::arg("mounting"), py::arg("method"));
}

}  // namespace mire::python
