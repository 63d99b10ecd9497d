// What a front end hands the backend: Keyframe (KeyframeInput), Detection
// (DetectionInput) and Odometry, built from NumPy arrays once and then
// passed to Backend.add_keyframe or LogWriter.write without conversion.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "symba/backend/keyframe_input.h"

namespace symba::python {
namespace {

std::vector<double> WeightsFromPython(const py::object& value,
                                      size_t count,
                                      const std::string& name) {
  if (value.is_none()) return std::vector<double>(count, 1.0);
  const py::array array = Float64Array(value, name);
  if (array.ndim() != 1 || static_cast<size_t>(array.shape(0)) != count) {
    ThrowValueError(name,
                    "expected shape (" + std::to_string(count) +
                        ",), one weight per hypothesis, got shape " +
                        ShapeString(array));
  }
  CheckFinite(array, name);
  const auto w = array.unchecked<double, 1>();
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
      .def_readwrite("sigma_r", &Odometry::sigma_r);
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
  py::class_<KeyframeInput>(
      m,
      "Keyframe",
      "One keyframe as a front end hands it over (a log line): id, "
      "timestamp, T_wc and/or odometry, detections, point observations "
      "(ids (M,) int64, uv (M, 2) float64 pixels, depth (M,) float64 metres, "
      "0 meaning no depth).")
      .def(py::init([](std::int64_t id,
                       double timestamp,
                       const py::object& T_wc,
                       std::optional<Odometry> odometry,
                       std::vector<DetectionInput> detections,
                       const py::object& point_ids,
                       const py::object& point_uv,
                       const py::object& point_depth) {
             KeyframeInput keyframe;
             keyframe.id = id;
             keyframe.timestamp = *OptionalFinite(timestamp, "timestamp");
             if (!T_wc.is_none()) keyframe.T_wc = PoseFromPython(T_wc, "T_wc");
             keyframe.odometry = std::move(odometry);
             keyframe.detections = std::move(detections);
             SetPoints(keyframe, point_ids, point_uv, point_depth);
             return keyframe;
           }),
           py::arg("id"),
           py::arg("timestamp"),
           py::arg("T_wc") = py::none(),
           py::arg("odometry") = py::none(),
           py::arg("detections") = std::vector<DetectionInput>(),
           py::arg("point_ids") = py::none(),
           py::arg("point_uv") = py::none(),
           py::arg("point_depth") = py::none())
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
}

}  // namespace

void BindInputs(py::module_& m) {
  BindOdometry(m);
  BindDetection(m);
  BindKeyframe(m);
}

}  // namespace symba::python
