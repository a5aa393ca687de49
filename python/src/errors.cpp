// mire's errors as Python exceptions carrying the C++ message (file, line, key, image):
//   std::invalid_argument        -> ValueError            (pybind11's own translation)
//   std::runtime_error           -> RuntimeError          (pybind11's own translation)
//   support::YamlError           -> mire.YamlError        (a RuntimeError: bad input file)
#include "bindings.hpp"

#include "mire/support/yaml.hpp"

namespace mire::python {

void bindErrors(py::module_& m) {
  static py::exception<support::YamlError> yaml_error(m, "YamlError", PyExc_RuntimeError);
  yaml_error.doc() = "A YAML input file is malformed; the message names the file, the line and the key.";
  // pybind11::ExceptionTranslator takes the exception_ptr by value.
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const support::YamlError& e) {
      yaml_error(e.what());
    }
  });
}

}  // namespace mire::python
