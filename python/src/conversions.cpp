// numpy <-> C++ conversions shared by the binding files.
#include "bindings.hpp"

#include <stdexcept>

namespace mire::python {

DoubleArray requirePoints(const py::handle& object, int dim, const std::string& what) {
  DoubleArray array = DoubleArray::ensure(object);
  if (!array) throw py::type_error(what + ": expected an array of numbers");
  if (array.ndim() == 1 && array.shape(0) == dim) return array.reshape({py::ssize_t{1}, py::ssize_t{dim}});
  if (array.ndim() != 2 || array.shape(1) != dim)
    throw py::value_error(
        what + ": expected an (N, " + std::to_string(dim) + ") array, got " + std::to_string(array.ndim()) +
        " dimension(s) of sizes " +
        py::str(py::cast(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()))).cast<std::string>());
  return array;
}

namespace {
template <int Dim>
py::array_t<double> pointsToArray(const std::vector<Eigen::Matrix<double, Dim, 1>>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{Dim}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < Dim; ++k) view(static_cast<py::ssize_t>(i), k) = points[i][k];
  return out;
}
template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> arrayToPoints(const py::handle& object, const std::string& what) {
  const DoubleArray array = requirePoints(object, Dim, what);
  const auto view = array.unchecked<2>();
  std::vector<Eigen::Matrix<double, Dim, 1>> points(static_cast<std::size_t>(view.shape(0)));
  for (py::ssize_t i = 0; i < view.shape(0); ++i)
    for (int k = 0; k < Dim; ++k) points[static_cast<std::size_t>(i)][k] = view(i, k);
  return points;
}
}  // namespace

py::array_t<double> toArray(const std::vector<Eigen::Vector2d>& points) { return pointsToArray<2>(points); }
py::array_t<double> toArray(const std::vector<Eigen::Vector3d>& points) { return pointsToArray<3>(points); }
std::vector<Eigen::Vector2d> toPoints2(const py::handle& object, const std::string& what) {
  return arrayToPoints<2>(object, what);
}
std::vector<Eigen::Vector3d> toPoints3(const py::handle& object, const std::string& what) {
  return arrayToPoints<3>(object, what);
}

cv::Mat toMat(const ByteArray& image, const std::string& what) {
  const int rows = image.ndim() >= 2 ? static_cast<int>(image.shape(0)) : 0;
  const int cols = image.ndim() >= 2 ? static_cast<int>(image.shape(1)) : 0;
  if (image.ndim() == 2) return cv::Mat(rows, cols, CV_8UC1, const_cast<unsigned char*>(image.data()));
  if (image.ndim() == 3 && (image.shape(2) == 1 || image.shape(2) == 3))
    return cv::Mat(rows, cols, image.shape(2) == 1 ? CV_8UC1 : CV_8UC3, const_cast<unsigned char*>(image.data()));
  throw py::value_error(what + ": expected an 8-bit image of shape (H, W) or (H, W, 3)");
}

ByteArray uint8Image(const py::handle& image, const std::string& what) {
  if (!py::isinstance<py::array>(image)) throw py::type_error(what + ": expected an 8-bit numpy image");
  const auto array = py::reinterpret_borrow<py::array>(image);
  if (!py::isinstance<py::array_t<unsigned char>>(array))
    throw py::value_error(what + ": an 8-bit image (dtype uint8) is expected, not " + std::string(py::str(array.dtype())) +
                          ": convert it explicitly (e.g. np.clip(image, 0, 255).astype(np.uint8))");
  return ByteArray::ensure(array);
}

Eigen::Matrix4d toMatrix(const Eigen::Isometry3d& transform) { return transform.matrix(); }

Eigen::Isometry3d toIsometry(const Eigen::Matrix4d& matrix, const std::string& what) {
  if (!matrix.allFinite()) throw py::value_error(what + ": non-finite entries");
  const Eigen::Matrix3d r = matrix.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      matrix.row(3).transpose() != Eigen::Vector4d(0, 0, 0, 1))
    throw py::value_error(what + ": not a rigid transform (4x4, orthonormal rotation, last row 0 0 0 1)");
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = r;
  transform.translation() = matrix.topRightCorner<3, 1>();
  return transform;
}

}  // namespace mire::python
