#include "symba/replay/replay_output.h"

#include <nlohmann/json.hpp>

namespace symba {
namespace {

using Json = nlohmann::ordered_json;

std::string QuoteCsv(const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
  std::string quoted = "\"";
  for (char c : field) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
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
  Json counts{{"keyframes", s.keyframes},
              {"detections", s.detections},
              {"objects", s.objects},
              {"objects_by_symmetry",
               {{"asymmetric", by_type[0]},
                {"discrete", by_type[1]},
                {"continuous", by_type[2]}}},
              {"points", s.points},
              {"object_upgrades", s.object_upgrades},
              {"objects_dropped", s.objects_dropped},
              {"rotation_outliers", s.rotation_outliers}};
  Json timing{{"seconds", result.seconds},
              {"solve_seconds", s.solve_seconds},
              {"ms_per_keyframe", ms_per_keyframe}};
  Json last{{"iterations", result.last_solve.iterations},
            {"initial_cost", result.last_solve.initial_cost},
            {"final_cost", result.last_solve.final_cost},
            {"converged", result.last_solve.converged},
            {"free_keyframes", result.last_solve.free_keyframes},
            {"residual_blocks", result.last_solve.residual_blocks}};
  Json solver{{"solves", s.solves},
              {"iterations", s.solve_iterations},
              {"last", std::move(last)}};
  Json used{{"window", b.window_size},
            {"max_iterations", b.max_iterations},
            {"batch_max_iterations", b.batch_max_iterations},
            {"threads", b.num_threads},
            {"hypothesis_sigma_t", b.hypothesis_sigma_t},
            {"hypothesis_sigma_r", b.hypothesis_sigma_r},
            {"gamma", b.gamma},
            {"axis_sigma", b.axis_sigma},
            {"object_loss", LossName(b.object_loss)},
            {"object_loss_scale", b.object_loss_scale},
            {"null_hypothesis", b.mixture.use_null_hypothesis},
            {"frontend_sigma_t", b.frontend_sigma_t},
            {"frontend_sigma_r", b.frontend_sigma_r},
            {"point_sigma_px", b.point_sigma_px},
            {"point_depth_sigma_relative", b.point_depth_sigma_relative},
            {"gate_position", b.gate_position},
            {"gate_axis", b.gate_axis},
            {"gate_rotation", b.gate_rotation},
            {"gate_angle", b.gate_angle},
            {"confirm_keyframes", b.confirm_keyframes},
            {"tentative_timeout", b.tentative_timeout},
            {"gate_sigmas", b.gate_sigmas},
            {"estimate_noise", b.estimate_noise},
            {"uncalibrated_sigma_t", b.uncalibrated_sigma_t},
            {"uncalibrated_sigma_r", b.uncalibrated_sigma_r},
            {"min_support", b.min_support},
            {"upgrade_evidence", b.upgrade_evidence},
            {"upgrade_min_fraction", b.upgrade_min_fraction},
            {"max_upgrade_order", b.max_upgrade_order}};
  Json summary{{"log", log_path},
               {"method", MethodName(b.method)},
               {"mode", ReplayModeName(options.mode)},
               {"counts", std::move(counts)},
               {"timing", std::move(timing)},
               {"solver", std::move(solver)},
               {"options", std::move(used)}};
  return summary.dump(2) + "\n";
}

std::vector<std::pair<std::string, std::string>> ReplayOutputFiles(
    const std::string& log_path,
    const ReplayOptions& options,
    const ReplayResult& result) {
  return {{"trajectory.tum", FormatTumTrajectory(result.keyframes)},
          {"objects.json", FormatObjectsJson(result.objects)},
          {"associations.csv", FormatAssociationsCsv(result.assignments)},
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
  Json json{{"input", graph_path},
            {"kind", "g2o pose graph"},
            {"vertices", summary.num_vertices},
            {"edges", summary.num_edges},
            {"initial_cost", summary.initial_cost},
            {"final_cost", summary.final_cost},
            {"iterations", summary.iterations},
            {"converged", summary.converged},
            {"seconds", summary.seconds},
            {"message", summary.message}};
  return {{"trajectory.tum", FormatTumTrajectory(poses)},
          {"summary.json", json.dump(2) + "\n"}};
}

}  // namespace symba
