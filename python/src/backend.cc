// Backend and what it reports: Trajectory, MapObject, Assignment,
// SolveReport, BackendStatistics.
//
// The GIL is held during every Backend call: the backend is not
// thread-safe, and holding the GIL keeps two Python threads from using one
// backend at once.
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "estimates.h"
#include "journaled_backend.h"
#include "keyframe_arrays.h"
#include "repr.h"
#include "symba/backend/backend.h"
#include "symba/io/file_output.h"
#include "symba/io/map_file.h"

namespace symba::python {

Trajectory MakeTrajectory(const std::vector<KeyframeEstimate>& keyframes) {
  std::vector<std::int64_t> ids;
  std::vector<double> timestamps;
  ids.reserve(keyframes.size());
  timestamps.reserve(keyframes.size());
  for (const KeyframeEstimate& k : keyframes) {
    ids.push_back(k.id);
    timestamps.push_back(k.timestamp);
  }
  return Trajectory{
      OwnedArray(std::move(ids)),
      DoublesToPython(std::move(timestamps)),
      PosesToPython(
          keyframes,
          [](const KeyframeEstimate& k) -> const auto& { return k.T_wc; })};
}

namespace {

py::object UpgradeToPython(const MapObjectEstimate& o) {
  if (!o.upgrade) return py::none();
  py::dict upgrade;
  upgrade["keyframe"] = o.upgrade->keyframe;
  upgrade["evidence"] = o.upgrade->evidence;
  upgrade["order"] = o.upgrade->order;
  upgrade["angle"] = o.upgrade->angle;
  return std::move(upgrade);
}

// A square matrix as an (n, n) array, row-major.
template <int N>
py::object MatrixToPython(const Eigen::Matrix<double, N, N>& m) {
  std::vector<double> values(N * N);
  for (int r = 0; r < N; ++r) {
    for (int c = 0; c < N; ++c) values[N * r + c] = m(r, c);
  }
  return OwnedArray(std::move(values), {N, N});
}

py::object Matrix3ToPython(const Eigen::Matrix3d& m) {
  return MatrixToPython<3>(m);
}

// {id, position, rotation, axis, angle_variances, source}: 3x3 arrays (or
// None where the type has no such part), a list of floats or None.
py::dict CovarianceToPython(const MapObjectCovariance& c) {
  py::dict out;
  out["id"] = c.id;
  out["position"] = Matrix3ToPython(c.position);
  out["rotation"] = c.rotation ? Matrix3ToPython(*c.rotation) : py::none();
  out["axis"] = c.axis ? Matrix3ToPython(*c.axis) : py::none();
  py::list variances;
  for (const std::optional<double>& v : c.angle_variances) {
    variances.append(v ? py::object(py::float_(*v)) : py::none());
  }
  out["angle_variances"] = variances;
  out["source"] = CovarianceSourceName(c.source);
  return out;
}

}  // namespace

void BindEstimates(py::module_& m) {
  py::class_<Trajectory>(m,
                         "Trajectory",
                         "Keyframe estimates: ids (N,) int64, timestamps (N,) "
                         "float64, poses (N, 7) float64 T_wc as [tx, ty, tz, "
                         "qx, qy, qz, qw].")
      .def_readonly("ids", &Trajectory::ids)
      .def_readonly("timestamps", &Trajectory::timestamps)
      .def_readonly("poses", &Trajectory::poses)
      .def("__len__", [](const Trajectory& t) { return t.ids.size(); })
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "Trajectory", {"ids", "timestamps", "poses"});
      });

  py::class_<MapObjectEstimate>(
      m,
      "MapObject",
      "A confirmed map object: t_wo (3,), unit axes axis_w and axis_o (3,) "
      "(zero if asymmetric), angles (K,) rad (discrete), poses (K, 7) "
      "[tx, ty, tz, qx, qy, qz, qw] (one; one per angle; or the angle-0 "
      "pose).")
      .def_readonly("id", &MapObjectEstimate::id)
      .def_readonly("class_name", &MapObjectEstimate::class_name)
      .def_property_readonly("symmetry",
                             [](const MapObjectEstimate& o) {
                               return std::string(ToString(o.symmetry));
                             })
      .def_property_readonly(
          "t_wo",
          [](const MapObjectEstimate& o) { return VectorToPython(o.t_wo); })
      .def_property_readonly(
          "axis_w",
          [](const MapObjectEstimate& o) { return VectorToPython(o.axis_w); })
      .def_property_readonly(
          "axis_o",
          [](const MapObjectEstimate& o) { return VectorToPython(o.axis_o); })
      .def_property_readonly(
          "angles",
          [](const MapObjectEstimate& o) { return DoublesToPython(o.angles); })
      .def_property_readonly(
          "angle_evidence",
          [](const MapObjectEstimate& o) {
            return DoublesToPython(o.angle_evidence);
          },
          "(K,) discrete: the detections' evidence for each angle (each "
          "detection shares one unit among the angles its modes went to)")
      .def_property_readonly(
          "angle_probabilities",
          [](const MapObjectEstimate& o) {
            return DoublesToPython(o.angle_probabilities);
          },
          "(K,) discrete: angle_evidence normalised to sum 1")
      .def_property_readonly(
          "poses",
          [](const MapObjectEstimate& o) {
            return PosesToPython(
                o.poses, [](const Rigid3d& T) -> const Rigid3d& { return T; });
          })
      .def_readonly("observations", &MapObjectEstimate::observations)
      .def_property_readonly("upgrade",
                             &UpgradeToPython,
                             "None, or {keyframe, evidence, order, angle} "
                             "when an asymmetric object became symmetric.")
      .def_property_readonly(
          "covariance",
          [](const MapObjectEstimate& o) -> py::object {
            if (!o.covariance) return py::none();
            return CovarianceToPython(*o.covariance);
          },
          "None (Backend.objects() does not compute it), or the dict of "
          "Backend.object_covariances() (a replay fills it).")
      .def("__repr__", [](const MapObjectEstimate& o) {
        return "MapObject(id=" + std::to_string(o.id) + ", class_name='" +
               o.class_name + "', symmetry='" + ToString(o.symmetry) +
               "', observations=" + std::to_string(o.observations) + ")";
      });

  py::class_<DetectionAssignment>(m,
                                  "Assignment",
                                  "The map object a detection went to (-1: "
                                  "none) and the type it was categorised as.")
      .def_readonly("keyframe", &DetectionAssignment::keyframe)
      .def_readonly("detection", &DetectionAssignment::detection)
      .def_readonly("object", &DetectionAssignment::object)
      .def_property_readonly("symmetry",
                             [](const DetectionAssignment& a) {
                               return std::string(ToString(a.symmetry));
                             })
      .def("__repr__", [](const DetectionAssignment& a) {
        return "Assignment(keyframe=" + std::to_string(a.keyframe) +
               ", detection='" + a.detection +
               "', object=" + std::to_string(a.object) + ", symmetry='" +
               ToString(a.symmetry) + "')";
      });

  py::class_<SolveReport>(m, "SolveReport", "Statistics of one solve.")
      .def_readonly("iterations", &SolveReport::iterations)
      .def_readonly("initial_cost", &SolveReport::initial_cost)
      .def_readonly("final_cost", &SolveReport::final_cost)
      .def_readonly("seconds", &SolveReport::seconds)
      .def_readonly("converged", &SolveReport::converged)
      .def_readonly("free_keyframes", &SolveReport::free_keyframes)
      .def_readonly("residual_blocks", &SolveReport::residual_blocks)
      .def_readonly("parameter_blocks", &SolveReport::parameter_blocks)
      .def_readonly("prior_size", &SolveReport::prior_size)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "SolveReport",
                             {"iterations",
                              "initial_cost",
                              "final_cost",
                              "seconds",
                              "converged",
                              "free_keyframes",
                              "residual_blocks",
                              "parameter_blocks",
                              "prior_size"});
      });

  using R = RelocalizationReport;
  py::class_<R>(m,
                "RelocalizationReport",
                "Where relocalisation against a loaded map stands "
                "(docs/relocalization.md).")
      .def_property_readonly(
          "state",
          [](const R& r) { return std::string(ToString(r.state)); },
          "'searching', 'relocalized' or 'gave up'.")
      .def_readonly("keyframes", &R::keyframes)
      .def_readonly("attempts", &R::attempts)
      .def_readonly("last_outcome", &R::last_outcome)
      .def_readonly("keyframe",
                    &R::keyframe,
                    "The keyframe whose solve matched, or None.")
      .def_property_readonly(
          "T_map_run",
          [](const R& r) { return PoseToPython(r.T_map_run); },
          "The run's own frame in the map's: [tx, ty, tz, qx, qy, qz, qw].")
      .def_property_readonly(
          "correspondences",
          [](const R& r) {
            py::list out;
            for (const ObjectCorrespondence& c : r.correspondences) {
              out.append(py::make_tuple(c.local, c.map));
            }
            return out;
          },
          "(the search's object id, the map object's id) per match.")
      .def_readonly("position_rmse", &R::position_rmse)
      .def_readonly("seconds", &R::seconds)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "RelocalizationReport",
                             {"state", "keyframes", "attempts", "keyframe"});
      });

  using S = BackendStatistics;
  py::class_<S>(m, "BackendStatistics", "Counters over the backend's life.")
      .def_readonly("keyframes", &S::keyframes)
      .def_readonly("detections", &S::detections)
      .def_readonly("objects", &S::objects)
      .def_readonly("points", &S::points)
      .def_readonly("object_upgrades", &S::object_upgrades)
      .def_readonly("objects_turned", &S::objects_turned)
      .def_readonly("objects_dropped", &S::objects_dropped)
      .def_readonly("rotation_outliers", &S::rotation_outliers)
      .def_readonly("folded_angles", &S::folded_angles)
      .def_readonly("marginalized_keyframes", &S::marginalized_keyframes)
      .def_readonly("ambiguous_edges_dropped", &S::ambiguous_edges_dropped)
      .def_readonly("solves", &S::solves)
      .def_readonly("solve_seconds", &S::solve_seconds)
      .def_readonly("solve_iterations", &S::solve_iterations)
      .def_readonly("point_observations_behind", &S::point_observations_behind)
      .def_readonly("loop_closures", &S::loop_closures)
      .def_readonly("loop_closures_moved_past", &S::loop_closures_moved_past)
      .def_readonly("loop_closure_seconds", &S::loop_closure_seconds)
      .def_readonly("object_loop_closures", &S::object_loop_closures)
      .def_readonly("objects_merged", &S::objects_merged)
      .def_readonly("revisits_moved_past", &S::revisits_moved_past)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "BackendStatistics",
                             {"keyframes",
                              "detections",
                              "objects",
                              "points",
                              "object_upgrades",
                              "objects_turned",
                              "objects_dropped",
                              "rotation_outliers",
                              "folded_angles",
                              "marginalized_keyframes",
                              "ambiguous_edges_dropped",
                              "solves",
                              "solve_seconds",
                              "solve_iterations",
                              "loop_closures",
                              "object_loop_closures",
                              "objects_merged",
                              "revisits_moved_past"});
      });

  using P = LoopObjectPair;
  py::class_<P>(m,
                "LoopObjectPair",
                "A map object a revisit mapped again, and whether the "
                "duplicate was merged into it (docs/loop-closure.md).")
      .def_readonly("map", &P::map)
      .def_readonly("duplicate", &P::duplicate)
      .def_readonly("merged", &P::merged)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "LoopObjectPair", {"map", "duplicate", "merged"});
      });

  using L = LoopClosureReport;
  py::class_<L>(m,
                "LoopClosureReport",
                "What one loop closure did (docs/loop-closure.md).")
      .def_readonly("keyframe", &L::keyframe)
      .def_readonly("other", &L::other)
      .def_readonly("moved_past", &L::moved_past)
      .def_readonly("correction_m", &L::correction_m)
      .def_readonly("correction_deg", &L::correction_deg)
      .def_readonly("keyframes_moved", &L::keyframes_moved)
      .def_readonly("initial_cost", &L::initial_cost)
      .def_readonly("final_cost", &L::final_cost)
      .def_readonly("seconds", &L::seconds)
      .def_readonly("waiting", &L::waiting)
      .def_readonly("message", &L::message)
      .def_readonly("from_objects", &L::from_objects)
      .def_readonly("objects", &L::objects)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "LoopClosureReport",
                             {"keyframe",
                              "other",
                              "from_objects",
                              "waiting",
                              "moved_past",
                              "correction_m",
                              "correction_deg"});
      });
}

namespace {

// A pickle's state: (1, options as (name, value) pairs, inputs, [map
// texts], calls); journaled_backend.h.
// The pickled state's layout: 2 since keyframes carry loop closures.
constexpr int kJournalVersion = 2;

py::tuple JournalToPython(const BackendJournal& journal) {
  py::list options;
  for (const auto& [name, value] : journal.options) {
    options.append(py::make_tuple(
        name, std::visit([](const auto& v) { return py::cast(v); }, value)));
  }
  py::list maps;
  for (const std::string& map : journal.maps) maps.append(py::bytes(map));
  return py::make_tuple(kJournalVersion,
                        options,
                        py::bytes(journal.inputs),
                        maps,
                        py::bytes(journal.calls));
}

OptionValue OptionValueFromPython(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<int>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  return value.cast<std::string>();
}

// Raises symba.Error for anything but a state this version wrote.
BackendJournal JournalFromPython(const py::tuple& state) {
  BackendJournal journal;
  bool valid = state.size() == 5;
  try {
    valid = valid && py::isinstance<py::int_>(state[0]) &&
            state[0].cast<int>() == kJournalVersion;
    if (valid) {
      for (const py::handle& entry : state[1].cast<py::list>()) {
        const py::tuple pair = entry.cast<py::tuple>();
        if (pair.size() != 2) throw py::cast_error();
        journal.options.emplace_back(pair[0].cast<std::string>(),
                                     OptionValueFromPython(pair[1]));
      }
      journal.inputs = state[2].cast<py::bytes>();
      for (const py::handle& map : state[3].cast<py::list>()) {
        journal.maps.push_back(map.cast<py::bytes>());
      }
      journal.calls = state[4].cast<py::bytes>();
    }
  } catch (const py::cast_error&) {
    valid = false;
  }
  if (!valid) {
    ThrowIfError(Status::Error(
        "cannot unpickle the Backend: not a state this version of symba "
        "wrote"));
  }
  return journal;
}

// The whole file, or an error naming it as the map reader does.
std::string ReadMapText(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  if (!file || file.bad()) {
    SavedMap map;
    ThrowIfError(ReadMapFile(path, &map));  // its message for the failure
    ThrowIfError(Status::Error(path + ": cannot read"));
  }
  return text.str();
}

}  // namespace

void BindBackend(py::module_& m) {
  using J = JournaledBackend;
  py::class_<J, std::unique_ptr<J>> backend_class(
      m,
      "Backend",
      "The object-SLAM backend (docs/backend.md). Not thread-safe: use one "
      "backend from one thread. Pickling makes the same calls again in a "
      "new backend (docs/python.md, Pickling).");
  backend_class
      .def(py::init([](const std::optional<BackendOptions>& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       const std::map<std::string, ClassPrior>& class_priors,
                       bool keep_journal) {
             std::unique_ptr<J> backend;
             ThrowIfError(J::Create(options.value_or(BackendOptions()),
                                    intrinsics,
                                    class_priors,
                                    keep_journal,
                                    &backend));
             return backend;
           }),
           py::arg("options") = py::none(),
           py::arg("intrinsics") = py::none(),
           py::arg("class_priors") = std::map<std::string, ClassPrior>(),
           py::kw_only(),
           py::arg("keep_journal") = true,
           "Raises symba.Error with BackendOptions.validate's message for "
           "invalid options. keep_journal=False saves the memory of every "
           "accepted keyframe, and the backend can then not be pickled.")
      .def(
          "add_keyframe",
          [](J& self, const KeyframeInput& keyframe) {
            std::vector<DetectionAssignment> assignments;
            ThrowIfError(self.AddKeyframe(keyframe, &assignments));
            return assignments;
          },
          py::arg("keyframe"),
          "Adds one keyframe; returns its detections' assignments in input "
          "order. On an error (symba.Error) nothing is added.")
      .def(
          "optimize_window",
          [](J& self) {
            SolveReport report;
            ThrowIfError(self.OptimizeWindow(&report));
            return report;
          },
          "Solves the window (options.window_size keyframes).")
      .def(
          "optimize_batch",
          [](J& self) {
            SolveReport report;
            ThrowIfError(self.OptimizeBatch(&report));
            return report;
          },
          "Solves everything but the first keyframe.")
      .def(
          "keyframe",
          [](const J& self, KeyframeId id) -> py::object {
            const std::optional<KeyframeEstimate> k =
                self.backend().Keyframe(id);
            if (!k) return py::none();
            return PoseToPython(k->T_wc);
          },
          py::arg("id"),
          "The keyframe's T_wc as (7,) [tx, ty, tz, qx, qy, qz, qw], or None "
          "for an unknown id.")
      .def(
          "object",
          [](const J& self, ObjectId id) { return self.backend().Object(id); },
          py::arg("id"),
          "A confirmed map object, or None.")
      .def(
          "keyframes",
          [](const J& self) {
            return MakeTrajectory(self.backend().Keyframes());
          },
          "Every keyframe estimate as a Trajectory.")
      .def(
          "objects",
          [](const J& self) { return self.backend().Objects(); },
          "Every confirmed map object.")
      .def(
          "object_covariances",
          [](J& self) {
            std::vector<MapObjectCovariance> covariances;
            ThrowIfError(self.ObjectCovariances(&covariances));
            py::list out;
            for (const MapObjectCovariance& c : covariances) {
              out.append(CovarianceToPython(c));
            }
            return out;
          },
          "Each confirmed map object's covariance at the current estimate "
          "(docs/backend.md, Covariances): dicts {id, position (3, 3) m^2, "
          "rotation (3, 3) rad^2 or None, axis (3, 3) or None, "
          "angle_variances [rad^2 or None], source 'solve' or 'prior'}; "
          "objects without one are left out. Raises symba.Error if the last "
          "solve's problem is rank deficient.")
      .def(
          "keyframe_covariances",
          [](const J& self, const std::vector<KeyframeId>& ids) {
            std::vector<KeyframeCovariance> covariances;
            ThrowIfError(self.backend().KeyframeCovariances(ids, &covariances));
            py::list out;
            for (const KeyframeCovariance& c : covariances) {
              py::dict d;
              d["id"] = c.id;
              d["covariance"] = MatrixToPython<6>(c.covariance);
              out.append(d);
            }
            return out;
          },
          py::arg("ids"),
          "The keyframes' covariances in the world frame, in the order of "
          "`ids` (docs/backend.md, Covariances): dicts {id, covariance "
          "(6, 6): [t_wc m; world rotation vector rad]}, zero for the first "
          "keyframe. Raises symba.Error for an unknown id.")
      .def(
          "save_map",
          [](J& self, const std::optional<std::string>& path) {
            SavedMap map;
            ThrowIfError(self.SaveMap(&map));
            std::string text = FormatMapFile(map);
            if (path) ThrowIfError(WriteFileAtomically(*path, text));
            return text;
          },
          py::arg("path") = py::none(),
          "The map as it stands as a map file's text (docs/map-format.md: "
          "the confirmed objects with their covariances, each class's "
          "noise), also written to `path` (atomically) if given.")
      .def(
          "load_map",
          [](J& self,
             const std::optional<std::string>& path,
             const std::optional<std::string>& text,
             bool relocalize) {
            if (path.has_value() == text.has_value()) {
              ThrowValueError("load_map", "give exactly one of path and text");
            }
            if (path) {
              ThrowIfError(self.LoadMap(ReadMapText(*path), *path, relocalize));
            } else {
              ThrowIfError(self.LoadMap(*text, "<text>", relocalize));
            }
          },
          py::arg("path") = py::none(),
          py::kw_only(),
          py::arg("text") = py::none(),
          py::arg("relocalize") = false,
          "Starts the run from a map file (its path, or text=its text), "
          "before the first keyframe: the objects keep their ids and "
          "covariances (as priors), the classes their noise; keyframes "
          "are then in the map's frame, or, with relocalize=True, in a "
          "frame of their own that the backend finds from the objects "
          "(relocalization(); docs/relocalization.md). Raises symba.Error "
          "on a malformed map (naming the file and member) or after a "
          "keyframe.")
      .def(
          "add_loop_closure",
          [](J& self, KeyframeId keyframe, const LoopClosureInput& closure) {
            LoopClosureReport report;
            ThrowIfError(self.AddLoopClosure(keyframe, closure, &report));
            return report;
          },
          py::arg("keyframe"),
          py::arg("closure"),
          "A relative pose the host knows between two keyframes (its own "
          "loop closure, docs/loop-closure.md): closure.T is `keyframe`'s "
          "pose in closure.keyframe's frame. If that keyframe left the "
          "window, the past moves. Returns a LoopClosureReport; raises "
          "symba.Error on an unknown keyframe or bad numbers.")
      .def(
          "loop_closures",
          [](const J& self) { return self.backend().LoopClosures(); },
          "Every loop closure so far (LoopClosureReport): the closed ones "
          "in the order they were closed, then the waiting ones "
          "(waiting=True).")
      .def("give_up_relocalization",
           &J::GiveUpRelocalization,
           "Ends a search that has not matched: the run goes on in its own "
           "frame without the map (nothing otherwise).")
      .def(
          "relocalization",
          [](const J& self) { return self.backend().Relocalization(); },
          "A RelocalizationReport, or None without load_map(relocalize="
          "True).")
      .def(
          "assignments",
          [](const J& self) { return self.backend().Assignments(); },
          "Every detection's assignment, in input order.")
      .def("statistics",
           [](const J& self) { return self.backend().Statistics(); })
      .def(
          "noise",
          [](const J& self) { return self.backend().Noise(); },
          "Per class with detections, by name: the detection noise estimated "
          "so far and what the class's detections are weighed with "
          "(ClassNoise; docs/backend.md, Real detectors). Empty without "
          "options.estimate_noise.")
      .def(
          "motion_noise",
          [](const J& self) { return self.backend().MotionNoise(); },
          "The noise the front end stated for the camera's motion and the "
          "objects' test of it (MotionNoise; docs/backend.md, Real "
          "detectors, 7).")
      .def(
          "covariance_noise",
          [](const J& self) { return self.backend().CovarianceNoise(); },
          "The noise each group of the keyframe graph's edges was taken to "
          "have by the last covariances computed from that graph "
          "(CovarianceNoiseGroup; docs/backend.md, Covariances); empty "
          "before any or without options.calibrate_covariances.")
      .def_property_readonly(
          "options",
          [](const J& self) { return self.backend().options(); },
          "A copy of the options.")
      .def(py::pickle(
          [](const J& self) {
            BackendJournal journal;
            ThrowIfError(self.Journal(&journal));
            return JournalToPython(journal);
          },
          [](const py::tuple& state) {
            std::unique_ptr<J> backend;
            ThrowIfError(J::Restore(JournalFromPython(state), &backend));
            return backend;
          }));
  DefWithKeyframeArrays<J&>(
      [&](auto function, auto... args) {
        backend_class.def(
            "add_keyframe_arrays",
            function,
            args...,
            "add_keyframe(Keyframe.from_arrays(...)) in one call: the "
            "keyframe's arrays are converted in C++ and added (the same "
            "arguments and errors as Keyframe.from_arrays).");
      },
      [](J& self, const KeyframeArrays& arrays) {
        KeyframeInput keyframe;
        FillKeyframe(arrays, keyframe);
        std::vector<DetectionAssignment> assignments;
        ThrowIfError(self.AddKeyframe(keyframe, &assignments));
        return assignments;
      });
}

}  // namespace symba::python
