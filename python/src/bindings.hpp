#pragma once
// The Python module `mire` (doc/python.md): one binding file per area, numpy arrays in and
// out. Helpers shared by those files: conversions between numpy arrays and the C++ types
// (point lists, images, rigid transforms).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace mire::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using ByteArray = py::array_t<unsigned char, py::array::c_style | py::array::forcecast>;

// An (N, dim) array (a single point (dim,) is accepted as N = 1); throws ValueError naming
// `what` when the shape is wrong.
DoubleArray requirePoints(const py::handle& object, int dim, const std::string& what);
// N×2 / N×3 arrays from point lists, and back.
py::array_t<double> toArray(const std::vector<Eigen::Vector2d>& points);
py::array_t<double> toArray(const std::vector<Eigen::Vector3d>& points);
std::vector<Eigen::Vector2d> toPoints2(const py::handle& object, const std::string& what);
std::vector<Eigen::Vector3d> toPoints3(const py::handle& object, const std::string& what);
// A cv::Mat header over an 8-bit numpy image (H×W grey, H×W×3 BGR or H×W×1): no copy, valid
// while `image` lives.
cv::Mat toMat(const ByteArray& image, const std::string& what);
// An 8-bit image from any numpy array; ValueError naming `what` for another dtype (a float
// image cast to uint8 would be cut silently: 0.5 becomes 0, 300 becomes 44).
ByteArray uint8Image(const py::handle& image, const std::string& what);
// 4×4 homogeneous matrices for Eigen::Isometry3d.
Eigen::Matrix4d toMatrix(const Eigen::Isometry3d& transform);
Eigen::Isometry3d toIsometry(const Eigen::Matrix4d& matrix, const std::string& what);

void bindErrors(py::module_& m);
void bindCameras(py::module_& m);
void bindCalibration(py::module_& m);
void bindTargets(py::module_& m);
void bindMeasurement(py::module_& m);
void bindMechanisms(py::module_& m);  // calls bindIdentification
void bindIdentification(py::module_& m);
void bindExperiment(py::module_& m);  // plan / select (after bindMechanisms)
void bindHandEye(py::module_& m);     // after bindMechanisms (ParameterSet, IdentifiabilityReport)
void bindPipeline(py::module_& m);    // after bindMechanisms
// PredictionModel, ControllerFit in `mechanism`; compensate in `pipeline` (after bindMechanisms).
void bindCompensation(py::module_& mechanism, py::module_& pipeline);
void bindAccuracy(py::module_& m);  // after bindCompensation (PredictionModel)

}  // namespace mire::python
