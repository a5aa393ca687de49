#include "bindings.hpp"
namespace mire::python {
void bindTargets(py::module_&) {}
}
