#include "symba/replay/replay_output.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "io/json_writer.h"
#include "io/object_record.h"
#include "symba/backend/backend_option_table.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

using io_internal::JsonWriter;

std::string QuoteCsv(const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
  std::string quoted = "\"";
  for (char c : field) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

void WriteOptionValue(const OptionValue& value, JsonWriter* json) {
  if (const bool* b = std::get_if<bool>(&value)) {
    json->Bool(*b);
  } else if (const int* i = std::get_if<int>(&value)) {
    json->Int(*i);
  } else if (const double* d = std::get_if<double>(&value)) {
    json->Double(*d);
  } else {
    json->String(std::get<std::string>(value));
  }
}

// The nested struct a table name is in ("mixture" for
// "mixture.null_weight"; empty for a field of BackendOptions itself).
std::string GroupOf(const std::string& name) {
  const size_t dot = name.find('.');
  return dot == std::string::npos ? std::string() : name.substr(0, dot);
}

std::string MemberOf(const std::string& name) {
  const size_t dot = name.find('.');
  return dot == std::string::npos ? name : name.substr(dot + 1);
}

// "options": every field of the backend's option structs under its own
// name (backend_option_table.h), a nested struct as an object; then the
// keys older readers know: "window", "threads" and "null_hypothesis".
void WriteOptions(const BackendOptions& options, JsonWriter* json) {
  json->Key("options").BeginObject();
  std::string open_group;
  for (const OptionField<BackendOptions>& field : BackendOptionTable()) {
    const std::string group = GroupOf(field.name);
    if (group != open_group) {
      if (!open_group.empty()) json->EndObject();
      if (!group.empty()) json->Key(group).BeginObject();
      open_group = group;
    }
    json->Key(MemberOf(field.name));
    WriteOptionValue(field.get(options), json);
  }
  if (!open_group.empty()) json->EndObject();
  json->Member("window", options.window_size)
      .Member("threads", options.num_threads)
      .Member("null_hypothesis", options.mixture.use_null_hypothesis)
      .EndObject();
}

// "relocalization": where the search stands and, once relocalised, the
// keyframe, the log's frame in the map's and the matched objects
// (docs/relocalization.md).
void WriteRelocalization(const RelocalizationReport& r, JsonWriter* json) {
  json->Key("relocalization")
      .BeginObject()
      .Member("state", ToString(r.state))
      .Member("keyframes", r.keyframes)
      .Member("attempts", r.attempts)
      .Member("last_outcome", r.last_outcome)
      .Member("seconds", r.seconds);
  if (r.keyframe) {
    json->Member("keyframe", *r.keyframe);
    json->Key("T_map_log");
    io_internal::WritePose(r.T_map_run, json);
    json->Member("position_rmse", r.position_rmse);
    json->Key("matched").BeginArray();
    for (const ObjectCorrespondence& c : r.correspondences) {
      json->BeginObject()
          .Member("search_object", c.local)
          .Member("map_object", c.map)
          .EndObject();
    }
    json->EndArray();
  }
  json->EndObject();
}

// "loop_closures": how many the host gave, how many moved the past, how
// many still wait for a solve, and the closed ones' times (each one is in
// loop_closures.csv; docs/loop-closure.md).
void WriteLoopClosures(const std::vector<LoopClosureReport>& loops,
                       JsonWriter* json) {
  std::vector<double> seconds;
  int moved_past = 0;
  int waiting = 0;
  int from_objects = 0;
  int objects_merged = 0;
  double max_correction_m = 0.0;
  for (const LoopClosureReport& c : loops) {
    if (c.waiting) {
      ++waiting;
      continue;
    }
    seconds.push_back(c.seconds);
    moved_past += c.moved_past ? 1 : 0;
    from_objects += c.from_objects ? 1 : 0;
    for (const LoopObjectPair& pair : c.objects) {
      objects_merged += pair.merged ? 1 : 0;
    }
    max_correction_m = std::max(max_correction_m, c.correction_m);
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds.empty()
                            ? 0.0
                            : 0.5 * (seconds[(seconds.size() - 1) / 2] +
                                     seconds[seconds.size() / 2]);
  json->Key("loop_closures")
      .BeginObject()
      .Member("count", static_cast<int>(loops.size()))
      .Member("moved_past", moved_past)
      .Member("waiting", waiting)
      .Member("from_objects", from_objects)
      .Member("objects_merged", objects_merged)
      .Member("max_correction_m", max_correction_m)
      .Member("median_seconds", median)
      .Member("max_seconds", seconds.empty() ? 0.0 : seconds.back())
      .EndObject();
}

}  // namespace

std::string FormatAssociationsCsv(
    const std::vector<DetectionAssignment>& assignments) {
  std::string out = "keyframe,detection,object,symmetry\n";
  for (const DetectionAssignment& a : assignments) {
    out += std::to_string(a.keyframe) + "," + QuoteCsv(a.detection) + "," +
           std::to_string(a.object) + "," + ToString(a.symmetry) + "\n";
  }
  return out;
}

std::string FormatLoopClosuresCsv(
    const std::vector<LoopClosureReport>& loop_closures) {
  std::string out =
      "keyframe,other,moved_past,correction_m,correction_deg,"
      "keyframes_moved,initial_cost,final_cost,seconds,message,from_objects,"
      "objects,merged\n";
  for (const LoopClosureReport& c : loop_closures) {
    // The recognised objects as "MAP:DUPLICATE" pairs, space-separated.
    std::string objects;
    int merged = 0;
    for (const LoopObjectPair& pair : c.objects) {
      if (!objects.empty()) objects += " ";
      objects +=
          std::to_string(pair.map) + ":" + std::to_string(pair.duplicate);
      merged += pair.merged ? 1 : 0;
    }
    out += std::to_string(c.keyframe) + "," + std::to_string(c.other) + "," +
           (c.moved_past ? "true" : "false") + "," +
           FormatDouble(c.correction_m) + "," + FormatDouble(c.correction_deg) +
           "," + std::to_string(c.keyframes_moved) + "," +
           FormatDouble(c.initial_cost) + "," + FormatDouble(c.final_cost) +
           "," + FormatDouble(c.seconds) + "," + QuoteCsv(c.message) + "," +
           (c.from_objects ? "true" : "false") + "," + objects + "," +
           std::to_string(merged) + "\n";
  }
  return out;
}

std::string FormatReplaySummaryJson(const std::string& log_path,
                                    const ReplayOptions& options,
                                    const ReplayResult& result) {
  const BackendOptions& b = options.backend;
  const BackendStatistics& s = result.statistics;
  int by_type[3] = {0, 0, 0};
  for (const MapObjectEstimate& o : result.objects) {
    ++by_type[static_cast<int>(o.symmetry)];
  }
  const double ms_per_keyframe =
      s.keyframes > 0 ? 1e3 * result.seconds / s.keyframes : 0.0;
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("log", log_path)
      .Member("method", MethodName(b.method))
      .Member("mode", ReplayModeName(options.mode))
      .Member("final_batch", options.final_batch);
  json.Key("counts")
      .BeginObject()
      .Member("keyframes", s.keyframes)
      .Member("detections", s.detections)
      .Member("objects", s.objects)
      .Key("objects_by_symmetry")
      .BeginObject()
      .Member("asymmetric", by_type[0])
      .Member("discrete", by_type[1])
      .Member("continuous", by_type[2])
      .EndObject()
      .Member("points", s.points)
      .Member("object_upgrades", s.object_upgrades)
      .Member("objects_turned", s.objects_turned)
      .Member("objects_dropped", s.objects_dropped)
      .Member("objects_merged", s.objects_merged)
      .Member("revisits_moved_past", s.revisits_moved_past)
      .Member("rotation_outliers", s.rotation_outliers)
      .Member("folded_angles", s.folded_angles)
      .Member("marginalized_keyframes", s.marginalized_keyframes)
      .Member("ambiguous_edges_dropped", s.ambiguous_edges_dropped)
      .EndObject();
  int with_covariance = 0;
  for (const MapObjectEstimate& o : result.objects) {
    with_covariance += o.covariance ? 1 : 0;
  }
  json.Key("covariances")
      .BeginObject()
      .Member("objects", with_covariance)
      .Member("seconds", result.covariance_seconds);
  if (!result.covariance_note.empty()) {
    json.Member("unavailable", result.covariance_note);
  }
  json.Key("noise").BeginArray();
  for (const CovarianceNoiseGroup& g : result.covariance_noise) {
    json.BeginObject()
        .Member("name", g.name)
        .Member("edges", g.edges)
        .Member("residuals", g.residuals)
        .Member("held_by_others", g.held_by_others)
        .Member("residual_t", g.residual_t)
        .Member("residual_r", g.residual_r)
        .Member("correlation_t", g.correlation_t)
        .Member("correlation_r", g.correlation_r)
        .Member("factor_t", g.factor_t)
        .Member("factor_r", g.factor_r)
        .EndObject();
  }
  json.EndArray();
  json.EndObject();
  json.Key("timing")
      .BeginObject()
      .Member("seconds", result.seconds)
      .Member("solve_seconds", s.solve_seconds)
      .Member("ms_per_keyframe", ms_per_keyframe)
      .EndObject();
  json.Key("solver")
      .BeginObject()
      .Member("solves", s.solves)
      .Member("iterations", s.solve_iterations)
      .Key("last")
      .BeginObject()
      .Member("iterations", result.last_solve.iterations)
      .Member("initial_cost", result.last_solve.initial_cost)
      .Member("final_cost", result.last_solve.final_cost)
      .Member("converged", result.last_solve.converged)
      .Member("free_keyframes", result.last_solve.free_keyframes)
      .Member("residual_blocks", result.last_solve.residual_blocks)
      .Member("parameter_blocks", result.last_solve.parameter_blocks)
      .Member("prior_size", result.last_solve.prior_size)
      .EndObject()
      .EndObject();
  io_internal::WriteNoise(result.noise, &json);
  io_internal::WriteMotionNoise(result.motion, &json);
  WriteLoopClosures(result.loop_closures, &json);
  if (result.relocalization) WriteRelocalization(*result.relocalization, &json);
  WriteOptions(b, &json);
  json.EndObject();
  out.push_back('\n');
  return out;
}

std::vector<std::pair<std::string, std::string>> ReplayOutputFiles(
    const std::string& log_path,
    const ReplayOptions& options,
    const ReplayResult& result) {
  return {{"trajectory.tum", FormatTumTrajectory(result.keyframes)},
          {"objects.json",
           FormatObjectsJson(result.objects, result.noise, result.motion)},
          {"associations.csv", FormatAssociationsCsv(result.assignments)},
          {"loop_closures.csv", FormatLoopClosuresCsv(result.loop_closures)},
          {"summary.json", FormatReplaySummaryJson(log_path, options, result)}};
}

std::vector<std::pair<std::string, std::string>> PoseGraphOutputFiles(
    const std::string& graph_path,
    const PoseGraph& graph,
    const PoseGraphSolveSummary& summary) {
  std::vector<KeyframeEstimate> poses;
  for (const auto& [timestamp, T_w] : PoseGraphTrajectory(graph)) {
    poses.push_back({static_cast<int64_t>(timestamp), timestamp, T_w});
  }
  std::string json_text;
  JsonWriter json(&json_text, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("input", graph_path)
      .Member("kind", "g2o pose graph")
      .Member("vertices", summary.num_vertices)
      .Member("edges", summary.num_edges)
      .Member("given_cost", summary.given_cost)
      .Member("initial_cost", summary.initial_cost)
      .Member("initialization_seconds", summary.initialization_seconds)
      .Member("start", summary.chordal_start ? "chordal" : "given")
      .Member("final_cost", summary.final_cost)
      .Member("iterations", summary.iterations)
      .Member("converged", summary.converged)
      .Member("seconds", summary.seconds)
      .Member("message", summary.message)
      .EndObject();
  json_text.push_back('\n');
  return {{"trajectory.tum", FormatTumTrajectory(poses)},
          {"summary.json", std::move(json_text)}};
}

}  // namespace symba
