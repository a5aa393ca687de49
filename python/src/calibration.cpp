// Calibration: calibrateCamera from detections (views), from per-view point arrays
// (cv::calibrateCamera's shape), or from images (paths or numpy arrays, detected here the way
// `mire calibrate` does), with σ, covariance, per-view residuals and the projection
// uncertainty at given pixels.
#include "bindings.hpp"

#include "mire/calibration/calibrate.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include <opencv2/imgcodecs.hpp>

#include <stdexcept>

namespace mire::python {
namespace {

namespace cal = calibration;

void bindOptions(py::module_& m) {
  py::enum_<cal::DistortionModel>(m, "DistortionModel")
      .value("OpenCV4", cal::DistortionModel::OpenCV4)
      .value("OpenCV5", cal::DistortionModel::OpenCV5)
      .value("OpenCV8", cal::DistortionModel::OpenCV8)
      .value("OpenCV12", cal::DistortionModel::OpenCV12)
      .value("Pinhole", cal::DistortionModel::Pinhole)
      .value("Fisheye", cal::DistortionModel::Fisheye);
  m.def("parseDistortionModel", &cal::parseDistortionModel, py::arg("name"));
  m.def("distortionModelName", &cal::distortionModelName, py::arg("model"));
  m.def("distortionCoefficientCount", &cal::distortionCoefficientCount, py::arg("model"));
  py::enum_<cal::RobustLoss>(m, "RobustLoss")
      .value("None_", cal::RobustLoss::None)
      .value("Huber", cal::RobustLoss::Huber)
      .value("Cauchy", cal::RobustLoss::Cauchy);
  py::class_<cal::CalibrationOptions>(m, "CalibrationOptions")
      .def(py::init<>())
      .def_readwrite("model", &cal::CalibrationOptions::model)
      .def_readwrite("fixed_parameters", &cal::CalibrationOptions::fixed_parameters)
      .def_readwrite("initial_params", &cal::CalibrationOptions::initial_params)
      .def_readwrite("robust_loss", &cal::CalibrationOptions::robust_loss)
      .def_readwrite("robust_scale_sigmas", &cal::CalibrationOptions::robust_scale_sigmas)
      .def_readwrite("outlier_threshold_sigmas", &cal::CalibrationOptions::outlier_threshold_sigmas)
      .def_readwrite("min_sigma_px", &cal::CalibrationOptions::min_sigma_px)
      .def_readwrite("min_points_per_view", &cal::CalibrationOptions::min_points_per_view)
      .def_readwrite("min_inlier_fraction", &cal::CalibrationOptions::min_inlier_fraction)
      .def_readwrite("refine_target", &cal::CalibrationOptions::refine_target)
      .def_readwrite("view_cluster_covariance", &cal::CalibrationOptions::view_cluster_covariance)
      .def_readwrite("uncertainty_distance_m", &cal::CalibrationOptions::uncertainty_distance_m)
      .def_readwrite("num_threads", &cal::CalibrationOptions::num_threads);
}

void bindViews(py::module_& m) {
  py::class_<cal::CalibrationView>(m, "CalibrationView", "One image's observations: target point indices and pixels.")
      .def(py::init<>())
      .def(py::init([](const std::string& name, std::vector<int> ids, const py::handle& pixels) {
             cal::CalibrationView view{name, std::move(ids), toPoints2(pixels, "CalibrationView: pixels")};
             if (view.ids.size() != view.pixels.size())
               throw py::value_error("CalibrationView '" + name + "': " + std::to_string(view.ids.size()) +
                                     " ids but " + std::to_string(view.pixels.size()) + " pixels");
             return view;
           }),
           py::arg("name"), py::arg("ids"), py::arg("pixels"))
      .def_readwrite("name", &cal::CalibrationView::name)
      .def_readwrite("ids", &cal::CalibrationView::ids)
      .def_property(
          "pixels", [](const cal::CalibrationView& v) { return toArray(v.pixels); },
          [](cal::CalibrationView& v, const py::handle& a) { v.pixels = toPoints2(a, "CalibrationView.pixels"); });

  using VR = cal::CalibrationViewResult;
  py::class_<VR>(m, "CalibrationViewResult")
      .def_readonly("name", &VR::name)
      .def_readonly("used", &VR::used)
      .def_readonly("rejection_reason", &VR::rejection_reason)
      .def_readonly("rotation", &VR::rotation)
      .def_readonly("translation", &VR::translation)
      .def_readonly("rms_px", &VR::rms_px)
      .def_readonly("tilt_deg", &VR::tilt_deg)
      .def_readonly("ids", &VR::ids)
      .def_property_readonly("pixels", [](const VR& v) { return toArray(v.pixels); })
      .def_property_readonly(
          "residuals", [](const VR& v) { return toArray(v.residuals); }, "projected − observed (N, 2), px")
      .def_property_readonly("inlier", [](const VR& v) {
        py::array_t<bool> out(static_cast<py::ssize_t>(v.inlier.size()));
        for (std::size_t i = 0; i < v.inlier.size(); ++i) out.mutable_at(static_cast<py::ssize_t>(i)) = v.inlier[i];
        return out;
      });
}

// Distance used when distance_m = 0 (the calibration's own), as the C++ functions expect.
double workingDistance(const cal::CalibrationResult& result, double distance_m) {
  return distance_m > 0.0 ? distance_m : result.uncertainty_distance_m;
}

void bindResult(py::module_& m) {
  using R = cal::CalibrationResult;
  py::class_<R>(m, "CalibrationResult")
      .def_readonly("camera", &R::camera)
      .def_readonly("model", &R::model)
      .def_readonly("fixed_parameters", &R::fixed_parameters)
      .def_readonly("views", &R::views)
      .def_readonly("used_views", &R::used_views)
      .def_readonly("used_points", &R::used_points)
      .def_readonly("rejected_points", &R::rejected_points)
      .def_readonly("rejected_views", &R::rejected_views)
      .def_readonly("free_parameter_count", &R::free_parameter_count)
      .def_readonly("sigma_px", &R::sigma_px)
      .def_readonly("robust_scale_px", &R::robust_scale_px)
      .def_property_readonly("target_points", [](const R& r) { return toArray(r.target_points); })
      .def_readonly("target_refined", &R::target_refined)
      .def_readonly("gauge_points", &R::gauge_points)
      .def_readonly("target_out_of_plane_rms_m", &R::target_out_of_plane_rms_m)
      .def_readonly("target_out_of_plane_max_m", &R::target_out_of_plane_max_m)
      .def_readonly("target_displacement_rms_m", &R::target_displacement_rms_m)
      .def_readonly("sigma_inflation", &R::sigma_inflation)
      .def_readonly("covariance_pixel_noise", &R::covariance_pixel_noise)
      .def_readonly("state_covariance", &R::state_covariance)
      .def_readonly("state_view_index", &R::state_view_index)
      .def_readonly("uncertainty_distance_m", &R::uncertainty_distance_m)
      .def_readonly("warnings", &R::warnings);

  py::class_<cal::ProjectionUncertaintySummary>(m, "ProjectionUncertaintySummary")
      .def_readonly("centre_px", &cal::ProjectionUncertaintySummary::centre_px)
      .def_readonly("edge_px", &cal::ProjectionUncertaintySummary::edge_px)
      .def_readonly("corner_px", &cal::ProjectionUncertaintySummary::corner_px);
  m.def("summarizeProjectionUncertainty", &cal::summarizeProjectionUncertainty, py::arg("result"));
  m.def(
      "projectionUncertaintyPx",
      [](const R& result, const py::handle& pixels, double distance_m) {
        const auto points = toPoints2(pixels, "projectionUncertaintyPx: pixels");
        py::array_t<double> out(static_cast<py::ssize_t>(points.size()));
        for (std::size_t i = 0; i < points.size(); ++i)
          out.mutable_at(static_cast<py::ssize_t>(i)) =
              cal::projectionUncertaintyPx(result, points[i], workingDistance(result, distance_m));
        return out;
      },
      py::arg("result"), py::arg("pixels"), py::arg("distance_m") = 0.0,
      "1-σ (worst direction, px) of the projection at each pixel (N, 2) -> (N,); distance 0 = the calibration's.");
  m.def(
      "projectionCovariancePx",
      [](const R& result, const py::handle& pixels, double distance_m) {
        const auto points = toPoints2(pixels, "projectionCovariancePx: pixels");
        py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}, py::ssize_t{2}});
        auto view = out.mutable_unchecked<3>();
        for (std::size_t i = 0; i < points.size(); ++i) {
          const Eigen::Matrix2d c = cal::projectionCovariancePx(result, points[i], workingDistance(result, distance_m));
          for (int r = 0; r < 2; ++r)
            for (int k = 0; k < 2; ++k) view(static_cast<py::ssize_t>(i), r, k) = c(r, k);
        }
        return out;
      },
      py::arg("result"), py::arg("pixels"), py::arg("distance_m") = 0.0, "2×2 covariances (N, 2, 2), px².");
}

// Detects `target` in every image (paths or arrays) like `mire calibrate`, then calibrates.
cal::CalibrationResult calibrateFromImages(const metrology::Target& target, const py::list& images,
                                           const cal::CalibrationOptions& options,
                                           const metrology::DetectionOptions& detection) {
  std::vector<cal::CalibrationView> views;
  int width = 0, height = 0;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const py::handle item = images[i];
    cv::Mat gray;
    std::string name;
    ByteArray array;
    if (py::isinstance<py::str>(item) || py::hasattr(item, "__fspath__")) {
      const std::string path = py::str(py::module_::import("os").attr("fspath")(item));
      gray = cv::imread(path, cv::IMREAD_GRAYSCALE);
      if (gray.empty()) throw std::runtime_error("cannot read image '" + path + "' (not a decodable image)");
      name = py::str(py::module_::import("os.path").attr("basename")(path));
    } else {
      name = "image_" + std::to_string(i);
      if (!py::isinstance<py::array>(item)) throw py::type_error(name + ": expected a path or an 8-bit numpy image");
      array = uint8Image(item, name);
      gray = toMat(array, name);
    }
    if (i == 0) {
      width = gray.cols;
      height = gray.rows;
    } else if (gray.cols != width || gray.rows != height) {
      throw std::runtime_error("image '" + name + "' is " + std::to_string(gray.cols) + "x" +
                               std::to_string(gray.rows) + ", the first image is " + std::to_string(width) + "x" +
                               std::to_string(height) + ": one camera, one size");
    }
    metrology::Detection found;
    {
      py::gil_scoped_release release;
      found = metrology::detectTarget(target, gray, detection);
    }
    if (found.found) views.push_back({name, found.ids, found.pixels});
  }
  if (images.empty()) throw py::value_error("calibrateFromImages: no image given");
  py::gil_scoped_release release;
  return cal::calibrateCamera(target.points(), views, width, height, options);
}

void bindCalibrate(py::module_& m) {
  m.def(
      "calibrateCamera",
      [](const py::handle& target_points, const std::vector<cal::CalibrationView>& views, int width, int height,
         const cal::CalibrationOptions& options) {
        const auto points = toPoints3(target_points, "calibrateCamera: target_points");
        py::gil_scoped_release release;
        return cal::calibrateCamera(points, views, width, height, options);
      },
      py::arg("target_points"), py::arg("views"), py::arg("width"), py::arg("height"),
      py::arg("options") = cal::CalibrationOptions{},
      "Calibrates from the target's points (N, 3) and the views (CalibrationView: ids + pixels) that saw them.");
  m.def(
      "calibrateCamera",
      [](const py::list& object_points, const py::list& image_points, int width, int height,
         const cal::CalibrationOptions& options) {
        std::vector<std::vector<Eigen::Vector3d>> objects;
        std::vector<std::vector<Eigen::Vector2d>> pixels;
        for (const auto& o : object_points) objects.push_back(toPoints3(o, "calibrateCamera: object_points"));
        for (const auto& p : image_points) pixels.push_back(toPoints2(p, "calibrateCamera: image_points"));
        py::gil_scoped_release release;
        return cal::calibrateCamera(objects, pixels, width, height, options);
      },
      py::arg("object_points"), py::arg("image_points"), py::arg("width"), py::arg("height"),
      py::arg("options") = cal::CalibrationOptions{},
      "cv::calibrateCamera's shape: per-view object points (N_i, 3) and image points (N_i, 2).");
  m.def("calibrateFromImages", &calibrateFromImages, py::arg("target"), py::arg("images"),
        py::arg("options") = cal::CalibrationOptions{}, py::arg("detection") = metrology::DetectionOptions{},
        "Detects the target in every image (file paths or 8-bit numpy arrays; images where it is not found are "
        "left out, as `mire calibrate` does) and calibrates.");
}

}  // namespace

void bindCalibration(py::module_& m) {
  bindOptions(m);
  bindViews(m);
  bindResult(m);
  bindCalibrate(m);
}

}  // namespace mire::python
