// What a front end hands the backend: Keyframe (KeyframeInput), Detection
// (DetectionInput) and Odometry, built from NumPy arrays once and then
// passed to Backend.add_keyframe or LogWriter.write without conversion;
// and KeyframeFromArrays (keyframe_arrays.h), a whole keyframe in one call.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "keyframe_arrays.h"
#include "repr.h"
#include "symba/backend/keyframe_input.h"

namespace symba::python {
namespace {

// The weights (H,) of H hypotheses, checked; nullopt for None (all 1).
std::optional<py::array> WeightsArray(const py::object& value,
                                      size_t count,
                                      const char* name) {
  if (value.is_none()) return std::nullopt;
  py::array array = Float64Array(value, name);
  if (array.ndim() != 1 || static_cast<size_t>(array.shape(0)) != count) {
    ThrowValueError(name,
                    "expected shape (" + std::to_string(count) +
                        ",), one weight per hypothesis, got shape " +
                        ShapeString(array));
  }
  CheckFinite(array, name);
  return array;
}

std::vector<double> WeightsFromPython(const py::object& value,
                                      size_t count,
                                      const char* name) {
  const std::optional<py::array> array = WeightsArray(value, count, name);
  if (!array) return std::vector<double>(count, 1.0);
  const auto w = array->unchecked<double, 1>();
  std::vector<double> weights(count);
  for (size_t i = 0; i < count; ++i) weights[i] = w(i);
  return weights;
}

void SetHypotheses(DetectionInput& detection,
                   const py::object& hypotheses,
                   const py::object& weights) {
  const std::vector<Rigid3d> poses = PosesFromPython(hypotheses, "hypotheses");
  const std::vector<double> w =
      WeightsFromPython(weights, poses.size(), "weights");
  detection.hypotheses.resize(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    detection.hypotheses[i].T_co = poses[i];
    detection.hypotheses[i].weight = w[i];
  }
}

std::optional<double> OptionalFinite(const std::optional<double>& value,
                                     const char* name) {
  if (value && !std::isfinite(*value)) {
    ThrowValueError(name,
                    "expected a finite number, got " +
                        py::str(py::float_(*value)).cast<std::string>());
  }
  return value;
}

// Points from ids (M,), uv (M, 2) and depth (M,) (0: no depth) or None.
void SetPoints(KeyframeInput& keyframe,
               const py::object& ids_value,
               const py::object& uv_value,
               const py::object& depth_value) {
  keyframe.points.clear();
  if (ids_value.is_none() && uv_value.is_none() && depth_value.is_none()) {
    return;
  }
  if (ids_value.is_none() || uv_value.is_none()) {
    throw py::value_error(
        "point_ids, point_uv: give both (and point_depth optionally) or "
        "neither");
  }
  const py::array ids = Int64Array(ids_value, "point_ids");
  if (ids.ndim() != 1) {
    ThrowValueError("point_ids",
                    "expected shape (M,), got shape " + ShapeString(ids));
  }
  const py::ssize_t m = ids.shape(0);
  const std::string m_text = std::to_string(m);
  const py::array uv = Float64Array(uv_value, "point_uv");
  if (uv.ndim() != 2 || uv.shape(0) != m || uv.shape(1) != 2) {
    ThrowValueError("point_uv",
                    "expected shape (" + m_text +
                        ", 2), one [u, v] per point id, got shape " +
                        ShapeString(uv));
  }
  CheckFinite(uv, "point_uv");
  std::optional<py::array> depth;
  if (!depth_value.is_none()) {
    depth = Float64Array(depth_value, "point_depth");
    if (depth->ndim() != 1 || depth->shape(0) != m) {
      ThrowValueError("point_depth",
                      "expected shape (" + m_text +
                          ",), one depth per point id, got shape " +
                          ShapeString(*depth));
    }
    CheckFinite(*depth, "point_depth");
  }
  const auto id = ids.unchecked<std::int64_t, 1>();
  const auto p = uv.unchecked<double, 2>();
  keyframe.points.resize(m);
  for (py::ssize_t i = 0; i < m; ++i) {
    PointObservation& point = keyframe.points[i];
    point.id = id(i);
    point.uv = Eigen::Vector2d(p(i, 0), p(i, 1));
    point.depth.reset();
    if (depth) {
      const double d = depth->unchecked<double, 1>()(i);
      if (d != 0.0) point.depth = d;
    }
  }
}

// One value per detection: a (D,) float64 array, or nullopt for None.
std::optional<py::array> PerDetection(const py::object& value,
                                      py::ssize_t count,
                                      const char* name,
                                      const char* what) {
  if (value.is_none()) return std::nullopt;
  py::array array = Float64Array(value, name);
  if (array.ndim() != 1 || array.shape(0) != count) {
    ThrowValueError(name,
                    "expected shape (" + std::to_string(count) + ",), one " +
                        what + " per detection, got shape " +
                        ShapeString(array));
  }
  CheckFinite(array, name);
  return array;
}

// Sets `field` of every detection from a list (or tuple) of str, one per
// detection; None sets them empty unless `required`.
void SetStrings(const py::object& value,
                std::vector<DetectionInput>& detections,
                std::string DetectionInput::*field,
                const char* name,
                bool required) {
  const auto count = [&] { return std::to_string(detections.size()); };
  if (value.is_none()) {
    if (!required || detections.empty()) {
      for (DetectionInput& detection : detections) (detection.*field).clear();
      return;
    }
    ThrowValueError(
        name,
        "expected a list of " + count() + " str, one per detection, got None");
  }
  if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr())) {
    ThrowValueError(name,
                    "expected a list of " + count() +
                        " str, one per detection, got a single " +
                        Py_TYPE(value.ptr())->tp_name);
  }
  const py::object items =
      py::reinterpret_steal<py::object>(PySequence_Fast(value.ptr(), ""));
  if (!items) {
    PyErr_Clear();
    ThrowValueError(name,
                    "expected a list of " + count() +
                        " str, one per detection, got " +
                        Py_TYPE(value.ptr())->tp_name);
  }
  const py::ssize_t n = PySequence_Fast_GET_SIZE(items.ptr());
  if (static_cast<size_t>(n) != detections.size()) {
    ThrowValueError(name,
                    "expected " + count() + " str, one per detection, got " +
                        std::to_string(n));
  }
  PyObject** item = PySequence_Fast_ITEMS(items.ptr());
  for (py::ssize_t i = 0; i < n; ++i) {
    if (!PyUnicode_Check(item[i])) {
      ThrowValueError(
          std::string(name) + "[" + std::to_string(i) + "]",
          std::string("expected a str, got ") + Py_TYPE(item[i])->tp_name);
    }
    Py_ssize_t size = 0;
    const char* text = PyUnicode_AsUTF8AndSize(item[i], &size);
    if (text == nullptr) throw py::error_already_set();
    (detections[i].*field).assign(text, static_cast<size_t>(size));
  }
}

// The stacked hypotheses (H, 7) or (H, 4, 4): a C-contiguous (H, 7) array
// (the usual case) is read in place (`rows`), anything else (strided
// views, (H, 4, 4)) through PosesFromPython (`poses`).
struct StackedHypotheses {
  py::array array;
  const double* rows = nullptr;
  std::vector<Rigid3d> poses;
  py::ssize_t size = 0;

  Rigid3d operator[](py::ssize_t i) const {
    if (rows == nullptr) return poses[i];
    // [tx, ty, tz, qx, qy, qz, qw]; Eigen's constructor takes w first.
    const double* r = rows + 7 * i;
    Rigid3d pose;
    pose.t = Eigen::Vector3d(r[0], r[1], r[2]);
    pose.q = Eigen::Quaterniond(r[6], r[3], r[4], r[5]);
    return pose;
  }
};

StackedHypotheses ReadHypotheses(const py::object& value) {
  StackedHypotheses stacked;
  stacked.array = Float64Array(value, "hypotheses");
  const py::array& array = stacked.array;
  if (array.ndim() == 2 && array.shape(1) == 7 &&
      (array.flags() & py::array::c_style)) {
    CheckFinite(array, "hypotheses");
    stacked.rows = static_cast<const double*>(array.data());
    stacked.size = array.shape(0);
  } else {
    stacked.poses = PosesFromPython(array, "hypotheses");
    stacked.size = static_cast<py::ssize_t>(stacked.poses.size());
  }
  return stacked;
}

// The hypothesis count of each detection, (D,) int64 adding up to `h`.
py::array ReadCounts(const py::object& value, py::ssize_t h) {
  py::array counts = Int64Array(value, "counts");
  if (counts.ndim() != 1) {
    ThrowValueError("counts",
                    "expected shape (D,), one hypothesis count per "
                    "detection, got shape " +
                        ShapeString(counts));
  }
  const auto c = counts.unchecked<std::int64_t, 1>();
  std::int64_t total = 0;
  for (py::ssize_t i = 0; i < c.shape(0); ++i) {
    if (c(i) < 0) {
      ThrowValueError("counts[" + std::to_string(i) + "]",
                      "expected a count >= 0, got " + std::to_string(c(i)));
    }
    total += c(i);
  }
  if (total != h) {
    ThrowValueError("counts",
                    "the counts add up to " + std::to_string(total) +
                        ", but hypotheses has " + std::to_string(h) + " rows");
  }
  return counts;
}

// Entry i of a (N,) array, or `fallback` without the array.
double EntryOr(const std::optional<py::array>& array,
               py::ssize_t i,
               double fallback) {
  return array ? array->unchecked<double, 1>()(i) : fallback;
}

// A sigma of detection i: none when not given or 0.
std::optional<double> DetectionSigma(const std::optional<py::array>& array,
                                     py::ssize_t i) {
  const double sigma = EntryOr(array, i, 0.0);
  if (sigma == 0.0) return std::nullopt;
  return sigma;
}

// The detections from the stacked hypotheses, the hypothesis count of each
// detection (D,) and the per-detection values; every field of every
// detection is overwritten.
void SetDetections(const KeyframeArrays& arrays,
                   std::vector<DetectionInput>& detections) {
  if (arrays.hypotheses.is_none() != arrays.counts.is_none()) {
    throw py::value_error(
        "hypotheses, counts: give both (with class_names) or neither");
  }
  StackedHypotheses stacked;
  std::optional<py::array> counts;
  if (!arrays.hypotheses.is_none()) {
    stacked = ReadHypotheses(arrays.hypotheses);
    counts = ReadCounts(arrays.counts, stacked.size);
  }
  const std::optional<py::array> weights = WeightsArray(
      arrays.weights, static_cast<size_t>(stacked.size), "weights");
  const py::ssize_t d = counts ? counts->shape(0) : 0;
  detections.resize(d);
  SetStrings(arrays.class_names,
             detections,
             &DetectionInput::class_name,
             "class_names",
             true);
  SetStrings(arrays.detection_ids,
             detections,
             &DetectionInput::id,
             "detection_ids",
             false);
  const std::optional<py::array> scores =
      PerDetection(arrays.scores, d, "scores", "score");
  const std::optional<py::array> sigma_t = PerDetection(
      arrays.detection_sigma_t, d, "detection_sigma_t", "sigma (0: none)");
  const std::optional<py::array> sigma_r = PerDetection(
      arrays.detection_sigma_r, d, "detection_sigma_r", "sigma (0: none)");
  py::ssize_t next = 0;
  for (py::ssize_t i = 0; i < d; ++i) {
    DetectionInput& detection = detections[i];
    detection.hypotheses.resize(counts->unchecked<std::int64_t, 1>()(i));
    for (PoseHypothesis& hypothesis : detection.hypotheses) {
      hypothesis.T_co = stacked[next];
      hypothesis.weight = EntryOr(weights, next, 1.0);
      ++next;
    }
    detection.score = EntryOr(scores, i, 1.0);
    detection.sigma_t = DetectionSigma(sigma_t, i);
    detection.sigma_r = DetectionSigma(sigma_r, i);
  }
}

void BindOdometry(py::module_& m) {
  py::class_<Odometry>(m,
                       "Odometry",
                       "The keyframe's pose in the previous keyframe's frame, "
                       "T_prev_cur ([tx, ty, tz, qx, qy, qz, qw] or 4 x 4), "
                       "with isotropic sigmas (m, rad).")
      .def(
          py::init(
              [](const py::object& T_prev_cur, double sigma_t, double sigma_r) {
                Odometry odometry;
                odometry.T_prev_cur = PoseFromPython(T_prev_cur, "T_prev_cur");
                odometry.sigma_t = *OptionalFinite(sigma_t, "sigma_t");
                odometry.sigma_r = *OptionalFinite(sigma_r, "sigma_r");
                return odometry;
              }),
          py::arg("T_prev_cur"),
          py::arg("sigma_t") = 0.01,
          py::arg("sigma_r") = 0.005)
      .def_property(
          "T_prev_cur",
          [](const Odometry& o) { return PoseToPython(o.T_prev_cur); },
          [](Odometry& o, const py::object& value) {
            o.T_prev_cur = PoseFromPython(value, "T_prev_cur");
          })
      .def_readwrite("sigma_t", &Odometry::sigma_t)
      .def_readwrite("sigma_r", &Odometry::sigma_r)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "Odometry", {"T_prev_cur", "sigma_t", "sigma_r"});
      });

  py::class_<LoopClosureInput>(
      m,
      "LoopClosure",
      "A relative pose the host system knows between an earlier keyframe "
      "and a later one (its own loop closure, docs/loop-closure.md): T is "
      "the later keyframe's pose in the earlier one's frame ([tx, ty, tz, "
      "qx, qy, qz, qw] or 4 x 4), with isotropic sigmas (m, rad).")
      .def(py::init([](std::int64_t keyframe,
                       const py::object& T,
                       double sigma_t,
                       double sigma_r) {
             LoopClosureInput closure;
             closure.keyframe = keyframe;
             closure.T = PoseFromPython(T, "T");
             closure.sigma_t = *OptionalFinite(sigma_t, "sigma_t");
             closure.sigma_r = *OptionalFinite(sigma_r, "sigma_r");
             return closure;
           }),
           py::arg("keyframe"),
           py::arg("T"),
           py::arg("sigma_t") = 0.05,
           py::arg("sigma_r") = 0.02)
      .def_readwrite("keyframe", &LoopClosureInput::keyframe)
      .def_property(
          "T",
          [](const LoopClosureInput& c) { return PoseToPython(c.T); },
          [](LoopClosureInput& c, const py::object& value) {
            c.T = PoseFromPython(value, "T");
          })
      .def_readwrite("sigma_t", &LoopClosureInput::sigma_t)
      .def_readwrite("sigma_r", &LoopClosureInput::sigma_r)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "LoopClosure", {"keyframe", "T", "sigma_t", "sigma_r"});
      });
}

void BindDetection(py::module_& m) {
  py::class_<DetectionInput>(
      m,
      "Detection",
      "One multi-hypothesis detection: hypotheses T_co as (N, 7) "
      "[tx, ty, tz, qx, qy, qz, qw] or (N, 4, 4) float64, optional weights "
      "(N,) (default 1).")
      .def(py::init([](const std::string& class_name,
                       const py::object& hypotheses,
                       const py::object& weights,
                       const std::string& id,
                       std::optional<double> sigma_t,
                       std::optional<double> sigma_r,
                       double score) {
             DetectionInput detection;
             detection.class_name = class_name;
             detection.id = id;
             SetHypotheses(detection, hypotheses, weights);
             detection.sigma_t = OptionalFinite(sigma_t, "sigma_t");
             detection.sigma_r = OptionalFinite(sigma_r, "sigma_r");
             detection.score = *OptionalFinite(score, "score");
             return detection;
           }),
           py::arg("class_name"),
           py::arg("hypotheses"),
           py::arg("weights") = py::none(),
           py::arg("id") = "",
           py::arg("sigma_t") = py::none(),
           py::arg("sigma_r") = py::none(),
           py::arg("score") = 1.0)
      .def_readwrite("id", &DetectionInput::id)
      .def_readwrite("class_name", &DetectionInput::class_name)
      .def_readwrite("sigma_t", &DetectionInput::sigma_t)
      .def_readwrite("sigma_r", &DetectionInput::sigma_r)
      .def_readwrite("score", &DetectionInput::score)
      .def_property_readonly(
          "hypotheses",
          [](const DetectionInput& d) {
            return PosesToPython(
                d.hypotheses,
                [](const PoseHypothesis& h) -> const auto& { return h.T_co; });
          })
      .def_property_readonly("weights",
                             [](const DetectionInput& d) {
                               std::vector<double> w;
                               w.reserve(d.hypotheses.size());
                               for (const auto& h : d.hypotheses) {
                                 w.push_back(h.weight);
                               }
                               return DoublesToPython(std::move(w));
                             })
      .def("set_hypotheses",
           &SetHypotheses,
           py::arg("hypotheses"),
           py::arg("weights") = py::none(),
           "Replaces the hypotheses (and weights, default 1).")
      .def("__repr__", [](const DetectionInput& d) {
        return "Detection(class_name='" + d.class_name + "', id='" + d.id +
               "', " + std::to_string(d.hypotheses.size()) + " hypotheses)";
      });
}

void BindKeyframe(py::module_& m) {
  py::class_<KeyframeInput> keyframe_class(
      m,
      "Keyframe",
      "One keyframe as a front end hands it over (a log line): id, "
      "timestamp, T_wc and/or odometry, detections, point observations "
      "(ids (M,) int64, uv (M, 2) float64 pixels, depth (M,) float64 metres, "
      "0 meaning no depth).");
  keyframe_class
      .def(py::init([](std::int64_t id,
                       double timestamp,
                       const py::object& T_wc,
                       std::optional<Odometry> odometry,
                       std::vector<DetectionInput> detections,
                       const py::object& point_ids,
                       const py::object& point_uv,
                       const py::object& point_depth,
                       std::vector<LoopClosureInput> loop_closures) {
             KeyframeInput keyframe;
             keyframe.id = id;
             keyframe.timestamp = *OptionalFinite(timestamp, "timestamp");
             if (!T_wc.is_none()) keyframe.T_wc = PoseFromPython(T_wc, "T_wc");
             keyframe.odometry = std::move(odometry);
             keyframe.detections = std::move(detections);
             SetPoints(keyframe, point_ids, point_uv, point_depth);
             keyframe.loop_closures = std::move(loop_closures);
             return keyframe;
           }),
           py::arg("id"),
           py::arg("timestamp"),
           py::arg("T_wc") = py::none(),
           py::arg("odometry") = py::none(),
           py::arg("detections") = std::vector<DetectionInput>(),
           py::arg("point_ids") = py::none(),
           py::arg("point_uv") = py::none(),
           py::arg("point_depth") = py::none(),
           py::arg("loop_closures") = std::vector<LoopClosureInput>())
      .def_readwrite("id", &KeyframeInput::id)
      .def_readwrite("timestamp", &KeyframeInput::timestamp)
      .def_property(
          "T_wc",
          [](const KeyframeInput& k) -> py::object {
            if (!k.T_wc) return py::none();
            return PoseToPython(*k.T_wc);
          },
          [](KeyframeInput& k, const py::object& value) {
            if (value.is_none()) {
              k.T_wc.reset();
            } else {
              k.T_wc = PoseFromPython(value, "T_wc");
            }
          })
      .def_readwrite("odometry", &KeyframeInput::odometry)
      .def_readwrite("detections",
                     &KeyframeInput::detections,
                     "A copy of the detections (assign a list to change "
                     "them).")
      .def_readwrite("loop_closures",
                     &KeyframeInput::loop_closures,
                     "A copy of the keyframe's loop closures (LoopClosure; "
                     "assign a list to change them).")
      .def_property_readonly("point_ids",
                             [](const KeyframeInput& k) {
                               std::vector<std::int64_t> ids;
                               ids.reserve(k.points.size());
                               for (const auto& p : k.points) {
                                 ids.push_back(p.id);
                               }
                               return OwnedArray(std::move(ids));
                             })
      .def_property_readonly(
          "point_uv",
          [](const KeyframeInput& k) {
            std::vector<double> uv;
            uv.reserve(2 * k.points.size());
            for (const auto& p : k.points) {
              uv.push_back(p.uv.x());
              uv.push_back(p.uv.y());
            }
            return OwnedArray(std::move(uv),
                              {static_cast<py::ssize_t>(k.points.size()), 2});
          })
      .def_property_readonly("point_depth",
                             [](const KeyframeInput& k) {
                               std::vector<double> depth;
                               depth.reserve(k.points.size());
                               for (const auto& p : k.points) {
                                 depth.push_back(p.depth.value_or(0.0));
                               }
                               return DoublesToPython(std::move(depth));
                             })
      .def("set_points",
           &SetPoints,
           py::arg("point_ids"),
           py::arg("point_uv"),
           py::arg("point_depth") = py::none(),
           "Replaces the point observations.")
      .def("__repr__", [](const KeyframeInput& k) {
        return "Keyframe(id=" + std::to_string(k.id) + ", " +
               std::to_string(k.detections.size()) + " detections, " +
               std::to_string(k.points.size()) + " points)";
      });
  DefWithKeyframeArrays(
      [&](auto function, auto... args) {
        keyframe_class.def_static(
            "from_arrays",
            function,
            args...,
            "The whole keyframe in one call: hypotheses (H, 7) or (H, 4, 4) "
            "stacked over the detections, counts (D,) int64 hypotheses per "
            "detection, weights (H,) (default 1), class_names and "
            "detection_ids lists of D str, scores, detection_sigma_t and "
            "detection_sigma_r (D,) (0: the options' default); odometry an "
            "Odometry or a T_prev_cur pose with odometry_sigma_t/_r.");
      },
      [](const KeyframeArrays& arrays) {
        KeyframeInput keyframe;
        FillKeyframe(arrays, keyframe);
        return keyframe;
      });
}

// The odometry: an Odometry, or a T_prev_cur pose with optional sigmas.
std::optional<Odometry> OdometryFromArrays(const KeyframeArrays& arrays) {
  const bool sigmas = arrays.odometry_sigma_t || arrays.odometry_sigma_r;
  if (arrays.odometry.is_none()) {
    if (!sigmas) return std::nullopt;
    throw py::value_error(
        "odometry_sigma_t, odometry_sigma_r: given without odometry");
  }
  if (py::isinstance<Odometry>(arrays.odometry)) {
    if (sigmas) {
      throw py::value_error(
          "odometry_sigma_t, odometry_sigma_r: give them only with an "
          "odometry array (an Odometry has its own sigmas)");
    }
    return arrays.odometry.cast<Odometry>();
  }
  Odometry odometry;
  odometry.T_prev_cur = PoseFromPython(arrays.odometry, "odometry");
  if (arrays.odometry_sigma_t) {
    odometry.sigma_t =
        *OptionalFinite(arrays.odometry_sigma_t, "odometry_sigma_t");
  }
  if (arrays.odometry_sigma_r) {
    odometry.sigma_r =
        *OptionalFinite(arrays.odometry_sigma_r, "odometry_sigma_r");
  }
  return odometry;
}

}  // namespace

void FillKeyframe(const KeyframeArrays& arrays, KeyframeInput& keyframe) {
  keyframe.id = arrays.id;
  keyframe.timestamp = *OptionalFinite(arrays.timestamp, "timestamp");
  keyframe.T_wc.reset();
  if (!arrays.T_wc.is_none()) {
    keyframe.T_wc = PoseFromPython(arrays.T_wc, "T_wc");
  }
  keyframe.odometry = OdometryFromArrays(arrays);
  SetDetections(arrays, keyframe.detections);
  SetPoints(keyframe, arrays.point_ids, arrays.point_uv, arrays.point_depth);
}

void BindInputs(py::module_& m) {
  BindOdometry(m);
  BindDetection(m);
  BindKeyframe(m);
}

}  // namespace symba::python
