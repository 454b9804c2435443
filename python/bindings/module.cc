// hribench._hribench: the layers' bindings in layer order (bindings.h).
#include <pybind11/pybind11.h>

#include "bindings.h"

PYBIND11_MODULE(_hribench, m) {
  m.doc() = "HRIBench's C++ layers (docs/python.md); use the package hribench.";
  hribench::python::bind_core(m);
  hribench::python::bind_policy(m);
  hribench::python::bind_eval(m);
  hribench::python::bind_gen(m);
}
