// A whole keyframe from NumPy arrays in one call: Keyframe.from_arrays and
// Backend.add_keyframe_arrays (docs/python.md). The detections' hypotheses
// come as ONE stacked (H, 7) (or (H, 4, 4)) array with a count per
// detection, so that a keyframe costs one call into the module and no
// Python object per detection or hypothesis.
#ifndef SYMBA_PYTHON_SRC_KEYFRAME_ARRAYS_H_
#define SYMBA_PYTHON_SRC_KEYFRAME_ARRAYS_H_

#include <cstdint>
#include <optional>
#include <utility>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "symba/backend/keyframe_input.h"

namespace symba::python {

namespace py = pybind11;

// The arguments of both functions, as Python passed them (None: not
// given); docs/python.md, "A keyframe from arrays", says what each holds.
struct KeyframeArrays {
  std::int64_t id = 0;
  double timestamp = 0.0;
  py::object T_wc;
  py::object odometry;
  std::optional<double> odometry_sigma_t;
  std::optional<double> odometry_sigma_r;
  py::object hypotheses;
  py::object counts;
  py::object weights;
  py::object class_names;
  py::object detection_ids;
  py::object scores;
  py::object detection_sigma_t;
  py::object detection_sigma_r;
  py::object point_ids;
  py::object point_uv;
  py::object point_depth;
};

// Overwrites every field of `keyframe` from `arrays`, reusing the capacity
// of its vectors and strings (a keyframe refilled keyframe after keyframe
// allocates nothing once it has held the largest); ValueError naming the
// argument for a wrong dtype, shape, length or a non-finite number
// (inputs.cc). After an error `keyframe` holds a partial keyframe.
void FillKeyframe(const KeyframeArrays& arrays, KeyframeInput& keyframe);

// Binds `f(lead..., const KeyframeArrays&)` as the Python function that
// `def(function, args...)` defines, with the arguments id, timestamp and
// then the other fields of KeyframeArrays as keyword-only arguments
// defaulting to None: both functions spell the same names and defaults.
template <typename... Lead, typename Def, typename F>
void DefWithKeyframeArrays(Def def, F f) {
  def(
      [f](Lead... lead,
          std::int64_t id,
          double timestamp,
          py::object T_wc,
          py::object odometry,
          std::optional<double> odometry_sigma_t,
          std::optional<double> odometry_sigma_r,
          py::object hypotheses,
          py::object counts,
          py::object weights,
          py::object class_names,
          py::object detection_ids,
          py::object scores,
          py::object detection_sigma_t,
          py::object detection_sigma_r,
          py::object point_ids,
          py::object point_uv,
          py::object point_depth) {
        return f(std::forward<Lead>(lead)...,
                 KeyframeArrays{id,
                                timestamp,
                                std::move(T_wc),
                                std::move(odometry),
                                odometry_sigma_t,
                                odometry_sigma_r,
                                std::move(hypotheses),
                                std::move(counts),
                                std::move(weights),
                                std::move(class_names),
                                std::move(detection_ids),
                                std::move(scores),
                                std::move(detection_sigma_t),
                                std::move(detection_sigma_r),
                                std::move(point_ids),
                                std::move(point_uv),
                                std::move(point_depth)});
      },
      py::arg("id"),
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
