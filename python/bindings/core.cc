// core: the error tiers in Python (docs/python.md). core::InputError (bad input) is a
// ValueError with the CLI's one-line message; a failed HRIB_CHECK (a bug) raises
// hribench.CheckError instead of aborting the interpreter.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "core/errors.h"
#include "core/version.h"

namespace py = pybind11;

namespace hribench::python {

void bind_core(py::module_& m) {
  core::set_check_failure_throws(true);
  static py::exception<core::CheckError> check_error(m, "CheckError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const core::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const core::CheckError& e) {
      check_error(e.what());
    }
  });
  m.attr("__version__") = std::string(core::version());
  // A failed check on demand, so the tests see the tier-1 translation (tests/python).
  m.def("_fail_check_for_tests", [] { HRIB_CHECK(false) << "(a test of the check tier)"; });
}

}  // namespace hribench::python
