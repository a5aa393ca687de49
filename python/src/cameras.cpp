// Cameras: the model (mire::calibration::Camera), vectorised project/unproject, and every
// camera file format mire reads or writes (camera_formats.hpp).
#include "bindings.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/calibration/camera_model.hpp"
#include "mire/support/atomic_file.hpp"

#include <cmath>
#include <limits>
#include <optional>

namespace mire::python {
namespace {

using calibration::Camera;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Pixels of camera-frame points (N×3 -> N×2), NaN behind the camera. One loop in C++ over
// the same projectPoint the library uses everywhere (no per-point Python call).
py::array_t<double> projectPoints(const Camera& camera, const py::handle& points) {
  camera.validate();
  const DoubleArray in = requirePoints(points, 3, "Camera.project: points");
  const py::ssize_t n = in.shape(0);
  py::array_t<double> out({n, py::ssize_t{2}});
  const double* source = in.data();
  double* target = out.mutable_data();
  const double* params = camera.params.data();
  const int count = camera.distortionCount();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      if (!calibration::projectPoint(params, camera.lens, count, source + 3 * i, target + 2 * i)) {
        target[2 * i] = kNaN;
        target[2 * i + 1] = kNaN;
      }
    }
  }
  return out;
}

// Normalised rays (x, y) (z = 1) of pixels (N×2 -> N×2), NaN where the inverse does not converge.
py::array_t<double> unprojectPixels(const Camera& camera, const py::handle& pixels) {
  camera.validate();
  const DoubleArray in = requirePoints(pixels, 2, "Camera.unproject: pixels");
  const py::ssize_t n = in.shape(0);
  py::array_t<double> out({n, py::ssize_t{2}});
  const double* source = in.data();
  double* target = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      Eigen::Vector2d normalized;
      if (camera.unproject(Eigen::Vector2d(source[2 * i], source[2 * i + 1]), &normalized)) {
        target[2 * i] = normalized.x();
        target[2 * i + 1] = normalized.y();
      } else {
        target[2 * i] = kNaN;
        target[2 * i + 1] = kNaN;
      }
    }
  }
  return out;
}

calibration::CameraFormat formatOf(const std::optional<std::string>& name, const std::filesystem::path& path) {
  if (name) {
    const auto format = calibration::cameraFormatFromName(*name);
    if (!format)
      throw py::value_error("unknown camera format '" + *name + "' (known: opencv, ros, visp, kalibr, mrcal)");
    return *format;
  }
  const auto format = calibration::cameraFormatFromExtension(path);
  if (!format)
    throw py::value_error(path.string() +
                          ": cannot tell the camera format from the name; pass format= "
                          "(opencv, ros, visp, kalibr, mrcal)");
  return *format;
}

void bindCameraClass(py::module_& m) {
  py::enum_<calibration::LensModel>(m, "LensModel")
      .value("OpenCV", calibration::LensModel::OpenCV)
      .value("Fisheye", calibration::LensModel::Fisheye);

  py::class_<Camera>(m, "Camera",
                     "A calibrated camera: fx fy cx cy + lens coefficients (OpenCV's order and pixel convention).")
      .def(py::init<>())
      .def(py::init([](int width, int height, std::vector<double> params, calibration::LensModel lens) {
             Camera camera;
             camera.width = width;
             camera.height = height;
             camera.params = std::move(params);
             camera.lens = lens;
             camera.validate();
             return camera;
           }),
           py::arg("width"), py::arg("height"), py::arg("params"), py::arg("lens") = calibration::LensModel::OpenCV)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def_readwrite("lens", &Camera::lens)
      .def_readwrite("params", &Camera::params)
      .def_readwrite("rms_px", &Camera::rms_px)
      .def_property(
          "covariance", [](const Camera& c) { return c.covariance; },
          [](Camera& c, const Eigen::MatrixXd& covariance) {
            const auto n = static_cast<Eigen::Index>(c.params.size());
            if (covariance.size() != 0 && (covariance.rows() != n || covariance.cols() != n))
              throw py::value_error("Camera.covariance: " + std::to_string(covariance.rows()) + "x" +
                                    std::to_string(covariance.cols()) + " for " + std::to_string(n) + " parameters (" +
                                    c.modelName() + "): expected " + std::to_string(n) + "x" + std::to_string(n) +
                                    " or empty");
            c.covariance = covariance;
          },
          "parameter covariance (n×n, n = len(params)) or empty")
      .def("distortionCount", &Camera::distortionCount)
      .def("fx", &Camera::fx)
      .def("fy", &Camera::fy)
      .def("cx", &Camera::cx)
      .def("cy", &Camera::cy)
      .def("parameterNames", &Camera::parameterNames)
      .def("sigmas", &Camera::sigmas)
      .def("modelName", &Camera::modelName)
      .def("validate", &Camera::validate)
      .def("project", &projectPoints, py::arg("points"),
           "Pixels (N, 2) of camera-frame points (N, 3); NaN for points at or behind the camera plane.")
      .def("unproject", &unprojectPixels, py::arg("pixels"),
           "Normalised rays (x, y) with z = 1, (N, 2), of pixels (N, 2): the exact inverse of the lens model; NaN "
           "where it does not converge.")
      .def("__repr__", [](const Camera& c) {
        return "<mire.calibration.Camera " + c.modelName() + " " + std::to_string(c.width) + "x" +
               std::to_string(c.height) + ">";
      });
  m.def("cameraFromOpenCV", &calibration::cameraFromOpenCV, py::arg("width"), py::arg("height"), py::arg("fx"),
        py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("distortion"));
}

void bindCameraFiles(py::module_& m) {
  py::enum_<calibration::CameraFormat>(m, "CameraFormat")
      .value("OpenCV", calibration::CameraFormat::OpenCV)
      .value("Ros", calibration::CameraFormat::Ros)
      .value("Visp", calibration::CameraFormat::Visp)
      .value("Kalibr", calibration::CameraFormat::Kalibr)
      .value("Mrcal", calibration::CameraFormat::Mrcal);
  m.def("cameraFormatName", &calibration::cameraFormatName);
  m.def("cameraFormatFromName", &calibration::cameraFormatFromName);
  m.def("cameraFormatFromExtension", &calibration::cameraFormatFromExtension);
  m.def("detectCameraFormat", &calibration::detectCameraFormat, py::arg("path"));
  m.def("readCamera", &calibration::readCamera, py::arg("path"),
        "Reads a camera in any readable format (from the content).");
  m.def("readCameraYaml", &calibration::readCameraYaml, py::arg("path"));
  m.def("readCameraVispXml", &calibration::readCameraVispXml, py::arg("path"));
  m.def("readCameraKalibrYaml", &calibration::readCameraKalibrYaml, py::arg("path"));
  m.def("cameraYamlString", &calibration::cameraYamlString, py::arg("camera"));
  m.def("cameraVispXmlString", &calibration::cameraVispXmlString, py::arg("camera"), py::arg("camera_name") = "camera");
  m.def("cameraRosYamlString", &calibration::cameraRosYamlString, py::arg("camera"), py::arg("camera_name") = "camera");
  m.def("cameraKalibrYamlString", &calibration::cameraKalibrYamlString, py::arg("camera"));
  m.def("cameraMrcalString", &calibration::cameraMrcalString, py::arg("camera"));
  m.def("cameraString", &calibration::cameraString, py::arg("camera"), py::arg("format"),
        py::arg("camera_name") = "camera");
  m.def(
      "writeCamera",
      [](const Camera& camera, const std::filesystem::path& path, const std::optional<std::string>& format,
         const std::string& camera_name) {
        support::writeFileAtomically(path, calibration::cameraString(camera, formatOf(format, path), camera_name));
      },
      py::arg("camera"), py::arg("path"), py::arg("format") = py::none(), py::arg("camera_name") = "camera",
      "Writes the camera atomically; the format is `format` (opencv, ros, visp, kalibr, mrcal) or implied by the "
      "file name (.yaml/.yml opencv, .xml visp, .cameramodel mrcal).");
}

}  // namespace

void bindCameras(py::module_& m) {
  bindCameraClass(m);
  bindCameraFiles(m);
}

}  // namespace mire::python
