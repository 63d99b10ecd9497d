// Logs (LogHeader, LogReader, LogWriter, read_log, write_log), replay, the
// TUM and BOP importers and the simulator.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "estimates.h"
#include "repr.h"
#include "symba/common/count_phrase.h"
#include "symba/import/bop_import.h"
#include "symba/import/class_prior_spec.h"
#include "symba/import/tum_import.h"
#include "symba/io/file_output.h"
#include "symba/io/log_file.h"
#include "symba/io/log_format.h"
#include "symba/io/map_file.h"
#include "symba/replay/replay.h"
#include "symba/simulation/simulator.h"

namespace symba::python {
namespace {

// A LogReader and the end-of-file state, iterated by Python.
struct PyLogReader {
  std::unique_ptr<LogReader> reader;
  bool end = false;
};

// A LogWriter that can be closed once.
struct PyLogWriter {
  std::unique_ptr<LogWriter> writer;
};

LogWriter& OpenWriter(PyLogWriter& w) {
  if (!w.writer) throw StatusError("LogWriter: already closed");
  return *w.writer;
}

void CloseWriter(PyLogWriter& w) {
  if (!w.writer) return;
  const Status status = w.writer->Close();
  w.writer.reset();
  ThrowIfError(status);
}

// ReplayResult with the trajectory as arrays.
struct PyReplayResult {
  LogHeader header;
  Trajectory trajectory;
  std::vector<MapObjectEstimate> objects;
  std::vector<DetectionAssignment> assignments;
  BackendStatistics statistics;
  SolveReport last_solve;
  double seconds = 0.0;
  std::optional<RelocalizationReport> relocalization;
  std::vector<LoopClosureReport> loop_closures;
  std::vector<ClassNoiseEstimate> noise;
  MotionNoiseReport motion;
};

// Binds `f(lead..., const TumImportOptions&)` as the Python function that
// `def(function, args...)` defines, with the importer's keyword arguments
// after `lead_args` (import_tum and import_tum_to_log spell the same names
// and defaults).
template <typename... Lead, typename Def, typename F, typename... LeadArgs>
void DefWithImportOptions(Def def, F f, LeadArgs... lead_args) {
  def(
      [f](Lead... lead,
          const std::string& trajectory,
          const std::vector<std::pair<std::string, std::string>>& objects,
          int stride,
          double odometry_sigma_t,
          double odometry_sigma_r,
          const std::string& first_pose,
          std::optional<double> detection_sigma_t,
          std::optional<double> detection_sigma_r,
          const std::map<std::string, ClassPrior>& classes) {
        TumImportOptions options;
        options.trajectory = trajectory;
        for (const auto& [class_name, path] : objects) {
          options.objects.push_back({class_name, path});
        }
        options.stride = stride;
        options.odometry_sigma_t = odometry_sigma_t;
        options.odometry_sigma_r = odometry_sigma_r;
        options.first_pose = first_pose;
        options.detection_sigma_t = detection_sigma_t;
        options.detection_sigma_r = detection_sigma_r;
        options.classes = classes;
        return f(std::forward<Lead>(lead)..., options);
      },
      lead_args...,
      py::arg("trajectory"),
      py::arg("objects"),
      py::arg("stride") = 5,
      py::arg("odometry_sigma_t") = 0.005,
      py::arg("odometry_sigma_r") = 0.01,
      py::arg("first_pose") = "",
      py::arg("detection_sigma_t") = py::none(),
      py::arg("detection_sigma_r") = py::none(),
      py::arg("classes") = std::map<std::string, ClassPrior>());
}

// Binds `f(lead..., const BopImportOptions&)` as the Python function that
// `def(function, args...)` defines, with the BOP importer's keyword
// arguments after `lead_args` (import_bop and import_bop_to_log spell the
// same names and defaults, those of `symba import bop`).
template <typename... Lead, typename Def, typename F, typename... LeadArgs>
void DefWithBopImportOptions(Def def, F f, LeadArgs... lead_args) {
  def(
      [f](Lead... lead,
          const std::string& results,
          const std::string& scene_camera,
          const std::string& models_info,
          const std::string& trajectory,
          const std::string& image_times,
          std::optional<int> scene,
          const std::map<int, std::string>& class_names,
          std::optional<double> gate,
          bool skip_images_without_pose,
          double time_tolerance,
          std::optional<double> detection_sigma_t,
          std::optional<double> detection_sigma_r) {
        BopImportOptions options;
        options.results = results;
        options.scene_camera = scene_camera;
        options.models_info = models_info;
        options.trajectory = trajectory;
        options.image_times = image_times;
        options.scene = scene;
        options.class_names = class_names;
        options.gate = gate;
        options.skip_images_without_pose = skip_images_without_pose;
        options.time_tolerance = time_tolerance;
        options.detection_sigma_t = detection_sigma_t;
        options.detection_sigma_r = detection_sigma_r;
        return f(std::forward<Lead>(lead)..., options);
      },
      lead_args...,
      py::arg("results"),
      py::arg("scene_camera"),
      py::arg("models_info") = "",
      py::arg("trajectory") = "",
      py::arg("image_times") = "",
      py::arg("scene") = py::none(),
      py::arg("class_names") = std::map<int, std::string>(),
      py::arg("gate") = py::none(),
      py::arg("skip_images_without_pose") = false,
      py::arg("time_tolerance") = 0.02,
      py::arg("detection_sigma_t") = py::none(),
      py::arg("detection_sigma_r") = py::none());
}

void BindLogs(py::module_& m) {
  py::class_<BopSource>(m,
                        "BopSource",
                        "Where a log converted from BOP files came from (the "
                        "header's \"bop\" key): the scene id and each "
                        "class's obj_id.")
      .def(py::init([](int scene_id, const std::map<std::string, int>& ids) {
             return BopSource{scene_id, ids};
           }),
           py::arg("scene_id") = 0,
           py::arg("obj_ids") = std::map<std::string, int>())
      .def_readwrite("scene_id", &BopSource::scene_id)
      .def_readwrite("obj_ids", &BopSource::obj_ids)
      .def("__repr__", [](const BopSource& b) {
        return "BopSource(scene_id=" + std::to_string(b.scene_id) + ", " +
               std::to_string(b.obj_ids.size()) + " obj_ids)";
      });

  py::class_<LogHeader>(m,
                        "LogHeader",
                        "A log's header: camera intrinsics (or None), "
                        "class priors by class name, and the BOP source "
                        "(or None).")
      .def(py::init([](const std::optional<PinholeIntrinsics>& camera,
                       const std::map<std::string, ClassPrior>& classes,
                       const std::optional<BopSource>& bop) {
             LogHeader header;
             header.camera = camera;
             header.classes = classes;
             header.bop = bop;
             return header;
           }),
           py::arg("camera") = py::none(),
           py::arg("classes") = std::map<std::string, ClassPrior>(),
           py::arg("bop") = py::none())
      .def_readonly("version", &LogHeader::version)
      .def_readwrite("camera", &LogHeader::camera)
      .def_readwrite("classes", &LogHeader::classes)
      .def_readwrite("bop", &LogHeader::bop)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "LogHeader", {"version", "camera", "classes", "bop"});
      });

  py::class_<PyLogReader>(m,
                          "LogReader",
                          "Reads a log v1 keyframe by keyframe: iterate it. "
                          "Errors raise symba.Error with FILE:LINE: reason.")
      .def(py::init([](const std::string& path) {
             auto reader = std::make_unique<PyLogReader>();
             ThrowIfError(LogReader::Open(path, &reader->reader));
             return reader;
           }),
           py::arg("path"))
      .def_property_readonly(
          "header", [](const PyLogReader& r) { return r.reader->header(); })
      .def_property_readonly(
          "line",
          [](const PyLogReader& r) { return r.reader->line(); },
          "The 1-based line of the last keyframe returned.")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__",
           [](PyLogReader& r) {
             if (r.end) throw py::stop_iteration();
             KeyframeInput keyframe;
             ThrowIfError(r.reader->Next(&keyframe, &r.end));
             if (r.end) throw py::stop_iteration();
             return keyframe;
           })
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyLogReader&, py::args) { return false; });

  py::class_<PyLogWriter>(m,
                          "LogWriter",
                          "Writes a log v1 keyframe by keyframe; close() (or "
                          "leaving a with block) flushes and reports a write "
                          "error.")
      .def(py::init([](const std::string& path, const LogHeader& header) {
             PyLogWriter w;
             ThrowIfError(LogWriter::Open(path, header, &w.writer));
             return w;
           }),
           py::arg("path"),
           py::arg("header"))
      .def(
          "write",
          [](PyLogWriter& w, const KeyframeInput& keyframe) {
            ThrowIfError(OpenWriter(w).Write(keyframe));
          },
          py::arg("keyframe"))
      .def("close", &CloseWriter)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyLogWriter& w, py::args) {
        CloseWriter(w);
        return false;
      });

  m.def(
      "read_log",
      [](const std::string& path) {
        std::unique_ptr<LogReader> reader;
        ThrowIfError(LogReader::Open(path, &reader));
        std::vector<KeyframeInput> keyframes;
        KeyframeInput keyframe;
        bool end = false;
        while (true) {
          ThrowIfError(reader->Next(&keyframe, &end));
          if (end) break;
          keyframes.push_back(keyframe);
        }
        return std::make_pair(reader->header(), std::move(keyframes));
      },
      py::arg("path"),
      "Reads a whole log: (LogHeader, list[Keyframe]).");

  m.def(
      "write_log",
      [](const std::string& path,
         const LogHeader& header,
         const std::vector<KeyframeInput>& keyframes) {
        ThrowIfError(WriteLogAtomically(path, header, keyframes));
      },
      py::arg("path"),
      py::arg("header"),
      py::arg("keyframes"),
      "Writes a whole log atomically: on an error the file is left as it "
      "was.");
}

void BindReplay(py::module_& m) {
  py::class_<PyReplayResult>(m, "ReplayResult", "What replay() returns.")
      .def_readonly("header", &PyReplayResult::header)
      .def_readonly("trajectory", &PyReplayResult::trajectory)
      .def_readonly("objects", &PyReplayResult::objects)
      .def_readonly("assignments", &PyReplayResult::assignments)
      .def_readonly("statistics", &PyReplayResult::statistics)
      .def_readonly("last_solve", &PyReplayResult::last_solve)
      .def_readonly("seconds", &PyReplayResult::seconds)
      .def_readonly("relocalization",
                    &PyReplayResult::relocalization,
                    "A RelocalizationReport with relocalize=True, else None.")
      .def_readonly("loop_closures",
                    &PyReplayResult::loop_closures,
                    "Every loop closure of the log (LoopClosureReport).")
      .def_readonly("noise",
                    &PyReplayResult::noise,
                    "Backend.noise() at the end (ClassNoise per class); "
                    "summary.json's \"noise\".")
      .def_readonly("motion",
                    &PyReplayResult::motion,
                    "Backend.motion_noise() at the end (MotionNoise); "
                    "summary.json's \"motion\".")
      .def("__repr__", [](const PyReplayResult& r) {
        return "ReplayResult(" +
               symba::CountPhrase(
                   static_cast<long long>(r.trajectory.ids.size()),
                   "keyframe") +
               ", " +
               symba::CountPhrase(static_cast<long long>(r.objects.size()),
                                  "map object") +
               ", " +
               symba::CountPhrase(static_cast<long long>(r.assignments.size()),
                                  "assignment") +
               ", seconds=" +
               py::repr(py::float_(r.seconds)).cast<std::string>() + ")";
      });

  m.def(
      "replay",
      [](const std::string& log_path,
         const std::optional<BackendOptions>& options,
         const std::string& mode,
         bool final_batch,
         const std::optional<std::string>& map_in,
         const std::optional<std::string>& map_out,
         bool relocalize) {
        ReplayOptions replay_options;
        replay_options.final_batch = final_batch;
        if (relocalize) {
          if (!map_in) ThrowValueError("relocalize", "needs map_in");
          replay_options.relocalize.emplace();
        }
        if (map_in) {
          replay_options.map_in.emplace();
          ThrowIfError(ReadMapFile(*map_in, &*replay_options.map_in));
        }
        replay_options.save_map = map_out.has_value();
        if (!ParseReplayMode(mode, &replay_options.mode)) {
          ThrowValueError("mode",
                          "unknown value \"" + mode +
                              "\" (expected \"window\" or \"batch\")");
        }
        replay_options.backend = options.value_or(BackendOptions());
        ReplayResult result;
        Status status;
        {
          py::gil_scoped_release release;
          status = ReplayLog(log_path, replay_options, &result);
        }
        ThrowIfError(status);
        if (map_out) {
          ThrowIfError(
              WriteFileAtomically(*map_out, FormatMapFile(*result.map)));
        }
        return PyReplayResult{std::move(result.header),
                              MakeTrajectory(result.keyframes),
                              std::move(result.objects),
                              std::move(result.assignments),
                              result.statistics,
                              result.last_solve,
                              result.seconds,
                              result.relocalization,
                              std::move(result.loop_closures),
                              std::move(result.noise),
                              result.motion};
      },
      py::arg("log_path"),
      py::arg("options") = py::none(),
      py::arg("mode") = "window",
      py::arg("final_batch") = false,
      py::arg("map_in") = py::none(),
      py::arg("map_out") = py::none(),
      py::arg("relocalize") = false,
      "Replays a log v1 as `symba replay` does (mode \"window\": optimise "
      "the window after every keyframe; \"batch\": one solve at the end; "
      "final_batch: in window mode, one batch solve after the last keyframe "
      "as well, like `symba replay --final-batch`; map_in, map_out: start "
      "from a map file, write the map at the end, like --map-in and "
      "--map-out; relocalize: the log is not in the map's frame, like "
      "--relocalize).");
}

void BindImport(py::module_& m) {
  DefWithImportOptions(
      [&](auto function, auto... args) {
        m.def("import_tum",
              function,
              args...,
              "Imports a TUM trajectory and per-object TUM detection files "
              "(objects: [(class_name, path)]) as `symba import tum` does; "
              "returns (LogHeader, list[Keyframe]).");
      },
      [](const TumImportOptions& options) {
        LogHeader header;
        std::vector<KeyframeInput> keyframes;
        ThrowIfError(ImportTum(options, &header, &keyframes));
        return std::make_pair(std::move(header), std::move(keyframes));
      });
  DefWithImportOptions<const std::string&>(
      [&](auto function, auto... args) {
        m.def("import_tum_to_log",
              function,
              args...,
              "import_tum, then writes the log atomically; returns "
              "(keyframes, detections).");
      },
      [](const std::string& log_path, const TumImportOptions& options) {
        TumImportCounts counts;
        ThrowIfError(ImportTumToLog(options, log_path, &counts));
        return std::make_pair(counts.keyframes, counts.detections);
      },
      py::arg("log_path"));

  py::class_<BopImportReport>(m,
                              "BopImportReport",
                              "What import_bop read: rows of the scene, "
                              "keyframes, detections, skipped images and "
                              "their rows, rows of other scenes, and how "
                              "symmetries BOP gives that "
                              "symba's three types cannot express exactly "
                              "were mapped.")
      .def_readonly("rows", &BopImportReport::rows)
      .def_readonly("keyframes", &BopImportReport::keyframes)
      .def_readonly("detections", &BopImportReport::detections)
      .def_readonly("skipped_images", &BopImportReport::skipped_images)
      .def_readonly("skipped_rows", &BopImportReport::skipped_rows)
      .def_readonly("other_scene_rows", &BopImportReport::other_scene_rows)
      .def_readonly("symmetry_notes", &BopImportReport::symmetry_notes)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "BopImportReport",
                             {"rows",
                              "keyframes",
                              "detections",
                              "skipped_images",
                              "skipped_rows",
                              "other_scene_rows",
                              "symmetry_notes"});
      });
  DefWithBopImportOptions(
      [&](auto function, auto... args) {
        m.def("import_bop",
              function,
              args...,
              "Imports a BOP results CSV with scene_camera.json (and "
              "models_info.json, or a front end's TUM trajectory with the "
              "image times) as `symba import bop` does; returns (LogHeader, "
              "list[Keyframe], BopImportReport).");
      },
      [](const BopImportOptions& options) {
        LogHeader header;
        std::vector<KeyframeInput> keyframes;
        BopImportReport report;
        ThrowIfError(ImportBop(options, &header, &keyframes, &report));
        return std::make_tuple(
            std::move(header), std::move(keyframes), std::move(report));
      });
  DefWithBopImportOptions<const std::string&>(
      [&](auto function, auto... args) {
        m.def("import_bop_to_log",
              function,
              args...,
              "import_bop, then writes the log atomically; returns the "
              "BopImportReport.");
      },
      [](const std::string& log_path, const BopImportOptions& options) {
        BopImportReport report;
        ThrowIfError(ImportBopToLog(options, log_path, &report));
        return report;
      },
      py::arg("log_path"));

  m.def(
      "parse_class_prior",
      [](const std::string& spec) {
        std::string name;
        ClassPrior prior;
        ThrowIfError(ParseClassPriorSpec(spec, &name, &prior));
        return std::make_pair(name, prior);
      },
      py::arg("spec"),
      "Parses NAME=asymmetric, NAME=discrete:ORDER[:ax,ay,az] or "
      "NAME=continuous[:ax,ay,az]; returns (name, ClassPrior).");
}

void BindSimulation(py::module_& m) {
  py::class_<SimulatedObject>(m, "SimulatedObject", "A true scene object.")
      .def_readonly("class_name", &SimulatedObject::class_name)
      .def_property_readonly("symmetry",
                             [](const SimulatedObject& o) {
                               return std::string(ToString(o.symmetry));
                             })
      .def_readonly("order", &SimulatedObject::order)
      .def_property_readonly(
          "axis_o",
          [](const SimulatedObject& o) { return VectorToPython(o.axis_o); })
      .def_property_readonly(
          "T_wo", [](const SimulatedObject& o) { return PoseToPython(o.T_wo); })
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self,
            "SimulatedObject",
            {"class_name", "symmetry", "order", "axis_o", "T_wo"});
      });

  py::class_<SimulatedSequence>(m,
                                "Simulation",
                                "A simulated sequence: the log's header and "
                                "keyframes and the ground truth.")
      .def_readonly("scene", &SimulatedSequence::scene)
      .def_readonly("seed", &SimulatedSequence::seed)
      .def_readonly("header", &SimulatedSequence::header)
      .def_readonly("keyframes", &SimulatedSequence::keyframes)
      .def_readonly("objects", &SimulatedSequence::objects)
      .def_property_readonly(
          "true_poses",
          [](const SimulatedSequence& s) {
            return PosesToPython(
                s.T_wc_true,
                [](const Rigid3d& T) -> const Rigid3d& { return T; });
          },
          "True T_wc per keyframe, (N, 7) [tx, ty, tz, qx, qy, qz, qw].")
      .def("__repr__", [](const SimulatedSequence& s) {
        return "Simulation(scene='" + s.scene +
               "', seed=" + std::to_string(s.seed) + ", " +
               std::to_string(s.keyframes.size()) + " keyframes, " +
               std::to_string(s.objects.size()) + " objects)";
      });

  m.def("scene_names", &SceneNames, "The scenes simulate() knows.");
  m.def(
      "simulate",
      [](const std::string& scene_name,
         std::uint32_t seed,
         std::optional<int> num_keyframes) {
        SimulationOptions options;
        Scene scene;
        ThrowIfError(MakeScene(scene_name, &scene));
        options.num_keyframes =
            num_keyframes.value_or(scene.default_num_keyframes);
        SimulatedSequence sequence;
        Status status;
        {
          py::gil_scoped_release release;
          status = Simulate(scene_name, options, seed, &sequence);
        }
        ThrowIfError(status);
        return sequence;
      },
      py::arg("scene"),
      py::arg("seed") = 1,
      py::arg("num_keyframes") = py::none(),
      "Simulates a scene as `symba simulate` does with default options "
      "(num_keyframes: the scene's default when None).");
}

}  // namespace

void BindIo(py::module_& m) {
  BindLogs(m);
  BindReplay(m);
  BindImport(m);
  BindSimulation(m);
}

}  // namespace symba::python
