#include "bindings.hpp"
namespace mire::python {
void bindMeasurement(py::module_&) {}
}
