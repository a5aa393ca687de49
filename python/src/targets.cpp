// Targets: target.yaml, feature positions, detection in a numpy image (features out as arrays),
// and the detections file (mire's CSV, mrcal's corners vnlog).
#include "bindings.hpp"

#include "mire/metrology/detection.hpp"
#include "mire/metrology/detections_file.hpp"
#include "mire/metrology/target.hpp"

namespace mire::python {
namespace {

namespace met = metrology;

void bindSpec(py::module_& m) {
  py::enum_<met::TargetType>(m, "TargetType")
      .value("Chessboard", met::TargetType::Chessboard)
      .value("Circles", met::TargetType::Circles)
      .value("AsymmetricCircles", met::TargetType::AsymmetricCircles)
      .value("AprilTag", met::TargetType::AprilTag)
      .value("Charuco", met::TargetType::Charuco)
      .value("ArucoGrid", met::TargetType::ArucoGrid);
  m.def("targetTypeName", &met::targetTypeName);
  py::class_<met::TagPlacement>(m, "TagPlacement")
      .def(py::init<>())
      .def(py::init([](int id, double x, double y) {
             return met::TagPlacement{id, x, y};
           }),
           py::arg("id"), py::arg("x_m"), py::arg("y_m"))
      .def_readwrite("id", &met::TagPlacement::id)
      .def_readwrite("x_m", &met::TagPlacement::x_m)
      .def_readwrite("y_m", &met::TagPlacement::y_m);
  using S = met::TargetSpec;
  py::class_<S>(m, "TargetSpec")
      .def(py::init<>())
      .def_readwrite("type", &S::type)
      .def_readwrite("cols", &S::cols)
      .def_readwrite("rows", &S::rows)
      .def_readwrite("square_size_m", &S::square_size_m)
      .def_readwrite("spacing_m", &S::spacing_m)
      .def_readwrite("diameter_m", &S::diameter_m)
      .def_readwrite("family", &S::family)
      .def_readwrite("tag_size_m", &S::tag_size_m)
      .def_readwrite("tag_spacing_m", &S::tag_spacing_m)
      .def_readwrite("first_id", &S::first_id)
      .def_readwrite("tags", &S::tags)
      .def_readwrite("dictionary", &S::dictionary)
      .def_readwrite("marker_size_m", &S::marker_size_m)
      .def_readwrite("marker_spacing_m", &S::marker_spacing_m);
  py::class_<met::Target>(m, "Target")
      .def(py::init<met::TargetSpec>(), py::arg("spec"))
      .def_static("fromFile", &met::Target::fromFile, py::arg("path"))
      .def("spec", &met::Target::spec)
      .def(
          "points", [](const met::Target& t) { return toArray(t.points()); }, "Feature points (N, 3) in frame M, m.")
      .def("isRotationallyAmbiguous", &met::Target::isRotationallyAmbiguous)
      .def("featureSpacing", &met::Target::featureSpacing)
      .def("tagIndex", &met::Target::tagIndex, py::arg("tag_id"))
      .def("tagLayout", &met::Target::tagLayout)
      .def("yamlString", &met::Target::yamlString);
}

void bindDetection(py::module_& m) {
  py::class_<met::DetectionOptions>(m, "DetectionOptions")
      .def(py::init<>())
      .def_readwrite("subpixel", &met::DetectionOptions::subpixel)
      .def_readwrite("subpixel_window_px", &met::DetectionOptions::subpixel_window_px)
      .def_readwrite("allow_partial", &met::DetectionOptions::allow_partial);
  py::class_<met::Detection>(m, "Detection")
      .def(py::init<>())
      .def_readwrite("found", &met::Detection::found)
      .def_readwrite("reason", &met::Detection::reason)
      .def_readwrite("ids", &met::Detection::ids)
      .def_property(
          "pixels", [](const met::Detection& d) { return toArray(d.pixels); },
          [](met::Detection& d, const py::handle& a) { d.pixels = toPoints2(a, "Detection.pixels"); })
      .def("__len__", &met::Detection::size);
  py::class_<met::TagDetection>(m, "TagDetection")
      .def_readonly("id", &met::TagDetection::id)
      .def_readonly("hamming", &met::TagDetection::hamming)
      .def_readonly("decision_margin", &met::TagDetection::decision_margin)
      .def_property_readonly("corners", [](const met::TagDetection& t) {
        return toArray(std::vector<Eigen::Vector2d>(t.corners.begin(), t.corners.end()));
      });
  m.def(
      "detectTarget",
      [](const met::Target& target, const py::handle& image, const met::DetectionOptions& options) {
        const ByteArray bytes = uint8Image(image, "detectTarget: image");
        const cv::Mat mat = toMat(bytes, "detectTarget: image");
        py::gil_scoped_release release;
        return met::detectTarget(target, mat, options);
      },
      py::arg("target"), py::arg("image"), py::arg("options") = met::DetectionOptions{},
      "Detects the target in an 8-bit image (H, W) grey or (H, W, 3) BGR.");
  m.def(
      "detectTargetCandidates",
      [](const met::Target& target, const py::handle& image, const met::DetectionOptions& options) {
        const ByteArray bytes = uint8Image(image, "detectTargetCandidates: image");
        const cv::Mat mat = toMat(bytes, "detectTargetCandidates: image");
        py::gil_scoped_release release;
        return met::detectTargetCandidates(target, mat, options);
      },
      py::arg("target"), py::arg("image"), py::arg("options") = met::DetectionOptions{});
  m.def(
      "refineDetection",
      [](const met::Target& target, const py::handle& image, const met::Detection& initial,
         const met::DetectionOptions& options) {
        const ByteArray bytes = uint8Image(image, "refineDetection: image");
        const cv::Mat mat = toMat(bytes, "refineDetection: image");
        py::gil_scoped_release release;
        return met::refineDetection(target, mat, initial, options);
      },
      py::arg("target"), py::arg("image"), py::arg("initial"), py::arg("options") = met::DetectionOptions{});
  m.def(
      "detectAprilTags",
      [](const py::handle& image, const std::string& family, bool refine_edges) {
        const ByteArray bytes = uint8Image(image, "detectAprilTags: image");
        const cv::Mat mat = toMat(bytes, "detectAprilTags: image");
        py::gil_scoped_release release;
        return met::detectAprilTags(mat, family, refine_edges);
      },
      py::arg("image"), py::arg("family"), py::arg("refine_edges") = true);
}

void bindDetectionsFile(py::module_& m) {
  py::class_<met::ImageDetections>(m, "ImageDetections")
      .def(py::init<>())
      .def_readwrite("image", &met::ImageDetections::image)
      .def_readwrite("ids", &met::ImageDetections::ids)
      .def_property(
          "pixels", [](const met::ImageDetections& d) { return toArray(d.pixels); },
          [](met::ImageDetections& d, const py::handle& a) { d.pixels = toPoints2(a, "ImageDetections.pixels"); });
  py::class_<met::DetectionsFile>(m, "DetectionsFile")
      .def_readonly("images", &met::DetectionsFile::images)
      .def_readonly("width", &met::DetectionsFile::width)
      .def_readonly("height", &met::DetectionsFile::height);
  m.def("readDetectionsFile", &met::readDetectionsFile, py::arg("path"), py::arg("target"));
  m.def("detectionsCsv", &met::detectionsCsv, py::arg("target"), py::arg("images"), py::arg("width"), py::arg("height"));
}

}  // namespace

void bindTargets(py::module_& m) {
  bindSpec(m);
  bindDetection(m);
  bindDetectionsFile(m);
}

}  // namespace mire::python
