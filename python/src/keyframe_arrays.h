// A whole keyframe from NumPy arrays in one call: Keyframe.from_arrays and
// Backend.add_keyframe_arrays (docs/python.md). The detections' hypotheses
// come as ONE stacked (H, 7) (or (H, 4, 4)) array with a count per
// detection, so that a keyframe costs one call into the module and no
// Python object per detection or hypothesis.
#ifndef SYMBA_PYTHON_SRC_KEYFRAME_ARRAYS_H_
#define SYMBA_PYTHON_SRC_KEYFRAME_ARRAYS_H_

#include <cstdint>
#include <optional>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "symba/backend/keyframe_input.h"

namespace symba::python {

namespace py = pybind11;

// Builds the keyframe; ValueError naming the argument for a wrong dtype,
// shape, length or a non-finite number (inputs.cc).
KeyframeInput KeyframeFromArrays(std::int64_t id,
                                 double timestamp,
                                 const py::object& T_wc,
                                 const py::object& odometry,
                                 std::optional<double> odometry_sigma_t,
                                 std::optional<double> odometry_sigma_r,
                                 const py::object& hypotheses,
                                 const py::object& counts,
                                 const py::object& weights,
                                 const py::object& class_names,
                                 const py::object& detection_ids,
                                 const py::object& scores,
                                 const py::object& detection_sigma_t,
                                 const py::object& detection_sigma_r,
                                 const py::object& point_ids,
                                 const py::object& point_uv,
                                 const py::object& point_depth);

// Calls def(args...) with the py::arg list of KeyframeFromArrays (every
// argument after `timestamp` keyword-only), so that both bindings of it
// spell the same names and defaults.
template <typename Def>
void WithKeyframeArrayArgs(Def def) {
  def(py::arg("id"),
      py::arg("timestamp"),
      py::kw_only(),
      py::arg("T_wc") = py::none(),
      py::arg("odometry") = py::none(),
      py::arg("odometry_sigma_t") = py::none(),
      py::arg("odometry_sigma_r") = py::none(),
      py::arg("hypotheses") = py::none(),
      py::arg("counts") = py::none(),
      py::arg("weights") = py::none(),
      py::arg("class_names") = py::none(),
      py::arg("detection_ids") = py::none(),
      py::arg("scores") = py::none(),
      py::arg("detection_sigma_t") = py::none(),
      py::arg("detection_sigma_r") = py::none(),
      py::arg("point_ids") = py::none(),
      py::arg("point_uv") = py::none(),
      py::arg("point_depth") = py::none());
}

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_KEYFRAME_ARRAYS_H_
