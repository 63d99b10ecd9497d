// The binding units of the _symba module; module.cc calls each once.
#ifndef SYMBA_PYTHON_SRC_BINDINGS_H_
#define SYMBA_PYTHON_SRC_BINDINGS_H_

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace symba::python {

namespace py = pybind11;

void BindOptions(py::module_& m);     // options.cc
void BindInputs(py::module_& m);      // inputs.cc
void BindEstimates(py::module_& m);   // backend.cc
void BindNoise(py::module_& m);       // noise.cc
void BindBackend(py::module_& m);     // backend.cc
void BindCategorize(py::module_& m);  // categorize.cc
void BindIo(py::module_& m);          // io.cc: logs, replay, import, simulate

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_BINDINGS_H_
