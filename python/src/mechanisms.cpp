#include "bindings.hpp"
namespace mire::python {
void bindMechanisms(py::module_&) {}
}
