#include "bindings.hpp"
namespace mire::python {
void bindCalibration(py::module_&) {}
}
