// Measurement: one pose from a list of images (numpy arrays, files or a folder), with its 6×6
// covariance parts and the flags `mire measure` writes; poses.csv and its covariance side file.
#include "bindings.hpp"

#include "mire/metrology/campaign_screening.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/shared_term_csv.hpp"
#include "mire/support/side_files.hpp"

#include <filesystem>

namespace mire::python {
namespace {

namespace met = metrology;

void bindOptions(py::module_& m) {
  py::class_<met::AveragingOptions>(m, "AveragingOptions")
      .def(py::init<>())
      .def_readwrite("rejection_confidence", &met::AveragingOptions::rejection_confidence)
      .def_readwrite("pooled_prior_dof", &met::AveragingOptions::pooled_prior_dof)
      .def_readwrite("min_feature_fraction", &met::AveragingOptions::min_feature_fraction)
      .def_readwrite("reject_images", &met::AveragingOptions::reject_images);
  py::class_<met::PoseOptions>(m, "PoseOptions")
      .def(py::init<>())
      .def_readwrite("ambiguity_ratio", &met::PoseOptions::ambiguity_ratio)
      .def_readwrite("covariance_floor_px", &met::PoseOptions::covariance_floor_px)
      .def_readwrite("inflate_by_residuals", &met::PoseOptions::inflate_by_residuals)
      .def_readwrite("max_iterations", &met::PoseOptions::max_iterations);
  py::enum_<met::SplitPolicy>(m, "SplitPolicy")
      .value("Fail", met::SplitPolicy::Fail)
      .value("KeepLargest", met::SplitPolicy::KeepLargest);
  py::class_<met::IntegrityOptions>(m, "IntegrityOptions")
      .def(py::init<>())
      .def_readwrite("enabled", &met::IntegrityOptions::enabled)
      .def_readwrite("false_alarm", &met::IntegrityOptions::false_alarm)
      .def_readwrite("duplicate_tolerance_px", &met::IntegrityOptions::duplicate_tolerance_px)
      .def_readwrite("split", &met::IntegrityOptions::split);
  py::class_<met::MeasurementOptions>(m, "MeasurementOptions")
      .def(py::init<>())
      .def_readwrite("detection", &met::MeasurementOptions::detection)
      .def_readwrite("averaging", &met::MeasurementOptions::averaging)
      .def_readwrite("pose", &met::MeasurementOptions::pose)
      .def_readwrite("integrity", &met::MeasurementOptions::integrity);
}

void bindResults(py::module_& m) {
  using I = met::IntegrityResult;
  py::class_<I>(m, "IntegrityResult")
      .def_readonly("consistent", &I::consistent)
      .def_readonly("error", &I::error)
      .def_readonly("notes", &I::notes)
      .def_readonly("duplicate_of", &I::duplicate_of)
      .def_readonly("moved", &I::moved)
      .def_readonly("use", &I::use)
      .def_readonly("threshold", &I::threshold)
      .def_readonly("max_statistic", &I::max_statistic)
      .def_readonly("global_statistic", &I::global_statistic)
      .def_readonly("global_threshold", &I::global_threshold)
      .def_readonly("tested_images", &I::tested_images)
      .def_readonly("noise_covariance", &I::noise_covariance);
  using A = met::AveragedFeatures;
  py::class_<A>(m, "AveragedFeatures")
      .def_readonly("ids", &A::ids)
      .def_property_readonly("pixels", [](const A& a) { return toArray(a.pixels); })
      .def_property_readonly(
          "covariance",
          [](const A& a) {
            py::array_t<double> out({static_cast<py::ssize_t>(a.covariance.size()), py::ssize_t{2}, py::ssize_t{2}});
            auto view = out.mutable_unchecked<3>();
            for (std::size_t i = 0; i < a.covariance.size(); ++i)
              for (int r = 0; r < 2; ++r)
                for (int c = 0; c < 2; ++c) view(static_cast<py::ssize_t>(i), r, c) = a.covariance[i](r, c);
            return out;
          })
      .def_readonly("observations", &A::observations)
      .def_readonly("images_used", &A::images_used)
      .def_readonly("images_total", &A::images_total)
      .def_readonly("rejected_images", &A::rejected_images)
      .def_readonly("rejected_observations", &A::rejected_observations)
      .def_readonly("pooled_covariance", &A::pooled_covariance)
      .def_readonly("pooled_dof", &A::pooled_dof);
  using E = met::PoseEstimate;
  py::class_<E>(m, "PoseEstimate", "cTm with its precision; covariances in (tx ty tz rx ry rz) order, SI.")
      .def_readonly("valid", &E::valid)
      .def_readonly("reason", &E::reason)
      .def_property_readonly(
          "cTm", [](const E& e) { return toMatrix(e.cTm); }, "4×4 camera <- target")
      .def_readonly("translation", &E::translation)
      .def_readonly("rotation_vector", &E::rotation_vector)
      .def_readonly("covariance_pixel_noise", &E::covariance_pixel_noise)
      .def_readonly("covariance_noise", &E::covariance_noise)
      .def_readonly("covariance_intrinsics", &E::covariance_intrinsics)
      .def_readonly("covariance", &E::covariance)
      .def_readonly("rms_px", &E::rms_px)
      .def_readonly("reduced_chi2", &E::reduced_chi2)
      .def_readonly("feature_count", &E::feature_count)
      .def_readonly("scatter_from_residuals", &E::scatter_from_residuals)
      .def_readonly("ambiguous", &E::ambiguous)
      .def_readonly("ambiguity_cost_ratio", &E::ambiguity_cost_ratio)
      .def_property_readonly("alternative_cTm", [](const E& e) { return toMatrix(e.alternative_cTm); })
      .def_property_readonly(
          "sigmas", [](const E& e) { return Eigen::Matrix<double, 6, 1>(E::sigmas(e.covariance)); },
          "1-σ of (tx ty tz rx ry rz), m and rad");
  using P = met::PoseMeasurement;
  py::class_<P>(m, "PoseMeasurement")
      .def_readonly("ok", &P::ok)
      .def_readonly("error", &P::error)
      .def_readonly("warnings", &P::warnings)
      .def_readonly("notes", &P::notes)
      .def_readonly("integrity", &P::integrity)
      .def_readonly("features", &P::features)
      .def_readonly("estimate", &P::estimate)
      .def_readonly("detections", &P::detections)
      .def_property_readonly(
          "flags", [](const P& p) { return met::measurementFlags(p); },
          "the codes `mire measure` writes in poses.csv's flags column");
}

met::PoseMeasurement measureArrays(const calibration::Camera& camera, const met::Target& target, const py::list& images,
                                   const std::vector<std::string>& names, const met::MeasurementOptions& options) {
  std::vector<ByteArray> arrays;  // keep the buffers alive while the Mats point into them
  std::vector<cv::Mat> mats;
  if (!names.empty() && names.size() != images.size())
    throw py::value_error("measurePose: " + std::to_string(names.size()) + " names for " +
                          std::to_string(images.size()) + " images (one name per image, or none)");
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string what = "measurePose: image " + std::to_string(i);
    arrays.push_back(uint8Image(images[i], what));
    mats.push_back(toMat(arrays.back(), what));
  }
  py::gil_scoped_release release;
  return met::measurePose(camera, target, mats, names, options);
}

void bindMeasure(py::module_& m) {
  m.def("measurePose", &measureArrays, py::arg("camera"), py::arg("target"), py::arg("images"),
        py::arg("names") = std::vector<std::string>{}, py::arg("options") = met::MeasurementOptions{},
        "One static pose from 8-bit numpy images.");
  m.def(
      "measurePoseFromFiles",
      [](const calibration::Camera& camera, const met::Target& target, const std::vector<std::filesystem::path>& images,
         const met::MeasurementOptions& options) {
        py::gil_scoped_release release;
        return met::measurePoseFromFiles(camera, target, images, options);
      },
      py::arg("camera"), py::arg("target"), py::arg("images"), py::arg("options") = met::MeasurementOptions{});
  m.def(
      "measurePoseFromFolder",
      [](const calibration::Camera& camera, const met::Target& target, const std::filesystem::path& folder,
         const met::MeasurementOptions& options) {
        py::gil_scoped_release release;
        const auto images = met::listPoseImages(folder);
        if (images.empty()) throw std::runtime_error("no image files in " + folder.string());
        return met::measurePoseFromFiles(camera, target, images, options);
      },
      py::arg("camera"), py::arg("target"), py::arg("folder"), py::arg("options") = met::MeasurementOptions{},
      "One pose from every image of a pose folder (listPoseImages: regular files sorted by name).");
  m.def("listPoseImages", &met::listPoseImages, py::arg("folder"));
}

void bindPosesCsv(py::module_& m) {
  using MP = met::MeasuredPose;
  py::class_<MP>(m, "MeasuredPose")
      .def(py::init<std::string, int, int, met::PoseEstimate, std::vector<std::string>>(), py::arg("pose_id"),
           py::arg("images_used"), py::arg("images_total"), py::arg("estimate"),
           py::arg("flags") = std::vector<std::string>{})
      .def_readwrite("pose_id", &MP::pose_id)
      .def_readwrite("images_used", &MP::images_used)
      .def_readwrite("images_total", &MP::images_total)
      .def_readwrite("estimate", &MP::estimate)
      .def_readwrite("flags", &MP::flags);
  m.def("posesCsvString", &met::posesCsvString, py::arg("poses"));
  m.def("posesCovarianceCsvString", &met::posesCovarianceCsvString, py::arg("poses"));
  m.def("writePosesCsv", &met::writePosesCsv, py::arg("path"), py::arg("poses"));
  m.def("writePosesCovarianceCsv", &met::writePosesCovarianceCsv, py::arg("path"), py::arg("poses"));
  m.def("covarianceSidePath", &mire::support::covarianceSidePath, py::arg("poses_csv"));
  m.def(
      "screenCampaign",
      [](std::vector<MP> poses) {
        const met::ScreeningResult result = met::screenCampaign(&poses);
        return py::make_tuple(poses, result.applied, result.reasons);
      },
      py::arg("poses"),
      "Campaign screening as `mire measure` does: returns (poses with their flags added, applied, reasons per pose).");
}

}  // namespace

// The shared-term file as `mire measure` writes it: the camera's covariance and the detector's
// bias every pose repeats (metrology/detector_bias.hpp).
void bindSharedTerm(py::module_& m) {
  using B = met::DetectorBiasTerm;
  py::class_<B>(m, "DetectorBiasTerm", "The detector's bias shared by every pose: sigma_b and its modes.")
      .def(py::init<>())
      .def_readonly("sigma_px", &B::sigma_px)
      .def_readonly("feature_error_rms_px", &B::feature_error_rms_px)
      .def_readonly("significance", &B::significance)
      .def_readonly("features", &B::features)
      .def_readonly("poses", &B::poses)
      .def_readonly("retained", &B::retained)
      .def_readonly("names", &B::names)
      .def_readonly("sensitivity", &B::sensitivity)
      .def("empty", &B::empty)
      .def("text", &B::text);
  m.def(
      "estimateDetectorBias",
      [](const calibration::Camera& camera, const met::Target& target, const std::vector<std::string>& pose_ids,
         const std::vector<met::PoseMeasurement>& measurements, const met::PoseOptions& options) {
        std::vector<const met::PoseMeasurement*> pointers;
        for (const met::PoseMeasurement& m : measurements) pointers.push_back(&m);
        return met::estimateDetectorBias(camera, target, pose_ids, pointers, options);
      },
      py::arg("camera"), py::arg("target"), py::arg("pose_ids"), py::arg("measurements"),
      py::arg("options") = met::PoseOptions{}, "As `mire measure` does over the poses that succeeded.");
  m.def("sharedTermSidePath", &mire::support::sharedTermSidePath, py::arg("poses_csv"));
  m.def("sharedTermCsvString", &met::sharedTermCsvString, py::arg("camera"), py::arg("poses"), py::arg("bias") = B{});
  m.def("writeSharedTermCsv", &met::writeSharedTermCsv, py::arg("path"), py::arg("camera"), py::arg("poses"),
        py::arg("bias") = B{});
}

void bindMeasurement(py::module_& m) {
  bindOptions(m);
  bindResults(m);
  bindMeasure(m);
  bindPosesCsv(m);
  bindSharedTerm(m);
}

}  // namespace mire::python
