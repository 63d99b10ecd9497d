// Python views of the backend's outputs, shared by backend.cc and io.cc
// (replay returns the same types).
#ifndef SYMBA_PYTHON_SRC_ESTIMATES_H_
#define SYMBA_PYTHON_SRC_ESTIMATES_H_

#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "symba/backend/estimates.h"

namespace symba::python {

namespace py = pybind11;

// Keyframe estimates as arrays: ids (N,) int64, timestamps (N,) float64,
// poses (N, 7) float64 [tx, ty, tz, qx, qy, qz, qw] (T_wc). The arrays own
// their memory; nothing is copied after they are built.
struct Trajectory {
  py::array_t<std::int64_t> ids;
  py::array_t<double> timestamps;
  py::array_t<double> poses;
};

Trajectory MakeTrajectory(const std::vector<KeyframeEstimate>& keyframes);

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_ESTIMATES_H_
