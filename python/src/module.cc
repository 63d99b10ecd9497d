// The _symba extension module; python/symba/__init__.py re-exports it as
// `symba` (docs/python.md).
#include "bindings.h"
#include "convert.h"

PYBIND11_MODULE(_symba, m) {
  namespace py = pybind11;
  using namespace symba::python;
  m.doc() =
      "symba: the object-SLAM backend for symmetric objects. Poses are "
      "[tx, ty, tz, qx, qy, qz, qw] (quaternion scalar last) or 4 x 4.";
  py::register_exception<StatusError>(m, "Error", PyExc_RuntimeError);
  BindOptions(m);
  BindInputs(m);
  BindEstimates(m);
  BindNoise(m);
  BindBackend(m);
  BindCategorize(m);
  BindIo(m);
}
