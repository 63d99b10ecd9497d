#include "symba/evaluation/evaluate_trajectory.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "evaluation/fixed.h"
#include "io/json_tree_reader.h"
#include "io/json_writer.h"
#include "io/text_file.h"
#include "symba/evaluation/evaluate.h"
#include "symba/geometry/angle.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

using internal::Fixed;
using io_internal::JsonWriter;

constexpr double kUnitTolerance = 1e-3;  // as the TUM reader's
const double kNan = std::numeric_limits<double>::quiet_NaN();

Status ParseObjectLine(const std::string& path,
                       int number,
                       std::string_view line,
                       GroundTruthObjectPose* object) {
  const std::vector<std::string_view> fields = internal::SplitFields(line);
  if (fields.size() != 8) {
    return Status::Error(internal::At(path, number) +
                         ": expected a class and 7 numbers (CLASS tx ty tz qx "
                         "qy qz qw), found " +
                         std::to_string(fields.size()) + " fields");
  }
  double v[7];
  for (int k = 0; k < 7; ++k) {
    if (!internal::ParseDouble(fields[k + 1], &v[k])) {
      return Status::Error(internal::At(path, number) + ": " +
                           io_internal::QuoteForMessage(fields[k + 1]) +
                           " is not a finite number");
    }
  }
  object->class_name = std::string(fields[0]);
  object->T_wo.t = Eigen::Vector3d(v[0], v[1], v[2]);
  object->T_wo.q = Eigen::Quaterniond(v[6], v[3], v[4], v[5]);
  object->line = number;
  const double norm = object->T_wo.q.norm();
  if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
    return Status::Error(internal::At(path, number) + ": quaternion norm " +
                         internal::Approx(norm) + " is not 1");
  }
  object->T_wo.q.normalize();
  return Status::Ok();
}

// The front end's poses at the result's keyframes (nearest within the
// tolerance; keyframes without one are left out).
std::vector<TrajectoryPose> AtKeyframes(
    const std::vector<TrajectoryPose>& frontend,
    const std::vector<TrajectoryPose>& keyframes,
    double tolerance) {
  std::vector<TrajectoryPose> poses;
  for (const TrajectoryPose& keyframe : keyframes) {
    const TrajectoryPose* pose =
        NearestPose(frontend, keyframe.timestamp, tolerance);
    if (pose == nullptr) continue;
    TrajectoryPose at_keyframe = *pose;
    at_keyframe.timestamp = keyframe.timestamp;
    poses.push_back(at_keyframe);
  }
  return poses;
}

Status EvaluateFrontend(const TrajectoryEvalInputs& inputs,
                        const std::vector<TrajectoryPose>& keyframes,
                        const std::vector<TrajectoryPose>& gt,
                        GroundTruthTrajectoryEvaluation* e) {
  std::vector<TrajectoryPose> frontend;
  Status status = ReadTumTrajectory(inputs.frontend, &frontend);
  if (!status.ok()) return status;
  const std::vector<TrajectoryPose> poses =
      AtKeyframes(frontend, keyframes, inputs.options.time_tolerance);
  if (poses.empty()) {
    return Status::Error(inputs.frontend + ": no pose within " +
                         internal::Approx(inputs.options.time_tolerance) +
                         " s of a keyframe of " + e->result_path);
  }
  status = EvaluateTrajectory(poses,
                              inputs.frontend,
                              gt,
                              inputs.gt_trajectory,
                              inputs.options,
                              &e->frontend);
  if (!status.ok()) return status;
  e->has_frontend = true;
  e->frontend_path = inputs.frontend;
  e->ate_ratio = e->result.ate.position_rmse / e->frontend.ate.position_rmse;
  return Status::Ok();
}

// The least rotation angle between the ground truth and any of the map
// object's poses, all in the ground truth's world [rad].
double LeastRotationError(const MapObjectEstimate& map_object,
                          const Eigen::Quaterniond& R_ref_est,
                          const Eigen::Quaterniond& q_gt) {
  double least = kNan;
  for (const Rigid3d& pose : map_object.poses) {
    const double angle = q_gt.angularDistance(R_ref_est * pose.q);
    if (!(angle >= least)) least = angle;
  }
  return least;
}

ObjectPositionError MatchObject(const GroundTruthObjectPose& gt,
                                const std::vector<MapObjectEstimate>& map,
                                const TrajectoryEvaluation& alignment) {
  ObjectPositionError error;
  error.gt = gt;
  error.position_error = kNan;
  error.rotation_error_deg = kNan;
  const MapObjectEstimate* nearest = nullptr;
  for (const MapObjectEstimate& m : map) {
    if (m.class_name != gt.class_name) continue;
    ++error.map_objects_of_class;
    const Eigen::Vector3d t =
        alignment.scale * (alignment.T_ref_est.q * m.t_wo) +
        alignment.T_ref_est.t;
    const double d = (t - gt.T_wo.t).norm();
    if (nearest == nullptr || d < error.position_error) {
      nearest = &m;
      error.position_error = d;
    }
  }
  if (nearest == nullptr) return error;
  error.nearest_map_object = nearest->id;
  if (nearest->symmetry != SymmetryType::kContinuous) {
    error.rotation_error_deg =
        kDegreesPerRadian *
        LeastRotationError(*nearest, alignment.T_ref_est.q, gt.T_wo.q);
  }
  return error;
}

void TrajectoryRow(const std::string& name,
                   const TrajectoryEvaluation& t,
                   std::ostringstream* out) {
  *out << "| " << name << " | " << t.matched << " of " << t.poses << " | "
       << Fixed(t.ate.position_rmse, 4) << " | "
       << Fixed(t.ate.max_position_error, 4) << " | "
       << Fixed(t.rotation_rmse_deg, 2) << " | "
       << Fixed(t.rpe_translation_rmse, 4) << " | "
       << Fixed(t.rpe_rotation_rmse_deg, 2) << " |\n";
}

void TrajectoryJson(const TrajectoryEvaluation& t, JsonWriter* json) {
  json->BeginObject()
      .Member("poses", t.poses)
      .Member("matched", t.matched)
      .Member("alignment", TrajectoryAlignmentName(t.alignment))
      .Member("scale", t.scale)
      .Member("ate", t.ate.position_rmse)
      .Member("ate_max", t.ate.max_position_error)
      .Member("rotation_rmse_deg", t.rotation_rmse_deg)
      .Member("rpe_pairs", t.rpe_pairs)
      .Member("rpe_translation_rmse", t.rpe_translation_rmse)
      .Member("rpe_rotation_rmse_deg", t.rpe_rotation_rmse_deg)
      .EndObject();
}

}  // namespace

Status ReadGroundTruthObjectList(const std::string& path,
                                 std::vector<GroundTruthObjectPose>* objects) {
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  objects->clear();
  const std::vector<std::string_view> lines = internal::SplitLines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (internal::IsBlank(lines[i]) ||
        internal::SplitFields(lines[i]).front().front() == '#') {
      continue;
    }
    GroundTruthObjectPose object;
    status = ParseObjectLine(path, static_cast<int>(i) + 1, lines[i], &object);
    if (!status.ok()) return status;
    objects->push_back(object);
  }
  if (objects->empty()) return Status::Error(path + ": no objects");
  return Status::Ok();
}

Status EvaluateAgainstTrajectory(const TrajectoryEvalInputs& inputs,
                                 GroundTruthTrajectoryEvaluation* evaluation) {
  GroundTruthTrajectoryEvaluation e;
  std::vector<TrajectoryPose> gt;
  Status status = ReadTumTrajectory(inputs.gt_trajectory, &gt);
  ReplayOutputs result;
  if (status.ok()) status = ReadReplayOutputs(inputs.result_dir, &result);
  std::vector<GroundTruthObjectPose> gt_objects;
  if (status.ok() && !inputs.gt_objects.empty()) {
    status = ReadGroundTruthObjectList(inputs.gt_objects, &gt_objects);
  }
  if (!status.ok()) return status;
  e.gt_path = inputs.gt_trajectory;
  e.result_path = result.trajectory_path;
  status = EvaluateTrajectory(result.keyframes,
                              result.trajectory_path,
                              gt,
                              inputs.gt_trajectory,
                              inputs.options,
                              &e.result);
  if (!status.ok()) return status;
  e.ate_ratio = kNan;
  if (!inputs.frontend.empty()) {
    status = EvaluateFrontend(inputs, result.keyframes, gt, &e);
    if (!status.ok()) return status;
  }
  e.map_objects = static_cast<int>(result.objects.size());
  for (const GroundTruthObjectPose& object : gt_objects) {
    e.objects.push_back(MatchObject(object, result.objects, e.result));
  }
  *evaluation = e;
  return Status::Ok();
}

std::string FormatTrajectoryEvaluationTable(
    const GroundTruthTrajectoryEvaluation& e) {
  std::ostringstream out;
  out << "ground truth " << e.gt_path << "; alignment "
      << TrajectoryAlignmentName(e.result.alignment);
  if (e.result.alignment == TrajectoryAlignment::kSim3) {
    out << " (scale " << Fixed(e.result.scale, 4) << ")";
  }
  out << "\n\n| trajectory | keyframes matched | ATE [m] | max [m] | "
         "rotation RMSE [deg] | RPE [m] | RPE [deg] |\n"
      << "|---|---:|---:|---:|---:|---:|---:|\n";
  TrajectoryRow("result " + e.result_path, e.result, &out);
  if (e.has_frontend) {
    TrajectoryRow("front end " + e.frontend_path, e.frontend, &out);
    out << "\nATE result / front end: " << Fixed(e.ate_ratio, 3) << "\n";
  }
  if (!e.objects.empty()) {
    out << "\n| GT object | class | map objects of its class | nearest | "
           "position error [m] | rotation error [deg] |\n"
        << "|---:|---|---:|---:|---:|---:|\n";
    for (const ObjectPositionError& o : e.objects) {
      out << "| line " << o.gt.line << " | " << o.gt.class_name << " | "
          << o.map_objects_of_class << " | "
          << (o.nearest_map_object >= 0 ? std::to_string(o.nearest_map_object)
                                        : std::string("none"))
          << " | " << Fixed(o.position_error, 4) << " | "
          << Fixed(o.rotation_error_deg, 2) << " |\n";
    }
  }
  return out.str();
}

std::string FormatTrajectoryEvaluationJson(
    const GroundTruthTrajectoryEvaluation& e) {
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("gt_trajectory", e.gt_path)
      .Member("result", e.result_path);
  json.Key("camera");
  TrajectoryJson(e.result, &json);
  if (e.has_frontend) {
    json.Member("frontend", e.frontend_path).Key("frontend_camera");
    TrajectoryJson(e.frontend, &json);
  }
  json.Member("ate_ratio", e.ate_ratio).Member("map_objects", e.map_objects);
  json.Key("objects").BeginArray();
  for (const ObjectPositionError& o : e.objects) {
    json.BeginObject()
        .Member("line", o.gt.line)
        .Member("class", o.gt.class_name)
        .Member("map_objects_of_class", o.map_objects_of_class)
        .Member("nearest_map_object", o.nearest_map_object)
        .Member("position_error", o.position_error)
        .Member("rotation_error_deg", o.rotation_error_deg)
        .EndObject();
  }
  json.EndArray().EndObject();
  out.push_back('\n');
  return out;
}

}  // namespace symba
