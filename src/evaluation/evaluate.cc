#include "symba/evaluation/evaluate.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "evaluation/fixed.h"
#include "io/json_writer.h"
#include "io/text_file.h"
#include "symba/geometry/angle.h"
#include "symba/io/format_double.h"
#include "symba/io/ground_truth_objects.h"
#include "symba/io/objects_json.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

using internal::Approx;
using internal::At;
using internal::Fixed;
using internal::IsBlank;
using internal::ParseDouble;
using internal::ParseInteger;
using internal::Quoted;
using internal::ReadText;
using internal::SplitLines;

using io_internal::JsonWriter;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string JoinPath(const std::string& dir, const char* name) {
  if (dir.empty() || dir.back() == '/') return dir + name;
  return dir + "/" + name;
}

// The rotation angle between two unit quaternions, in [0, pi].
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

// The angle between two lines through the origin (sign-free), in [0, pi/2].
double LineAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d u = a.normalized();
  const Eigen::Vector3d v = b.normalized();
  // atan2 of |u x v| and |u . v| is accurate at 0 and at pi/2.
  return std::atan2(u.cross(v).norm(), std::abs(u.dot(v)));
}

// ---------------------------------------------------------------------------
// TUM trajectories.

Status ReadTum(const std::string& path, std::vector<TrajectoryPose>* poses) {
  TumReadOptions options;
  options.allow_empty = true;
  Status status = ReadTumTrajectory(path, options, poses);
  if (!status.ok()) return status;
  if (poses->empty()) return Status::Error(path + ": no keyframes");
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// associations.csv.

// Splits one CSV record into fields ('"' quotes a field, '""' is a quote).
bool SplitCsv(std::string_view line, std::vector<std::string>* fields) {
  fields->assign(1, std::string());
  bool quoted = false;
  bool was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    std::string& field = fields->back();
    if (quoted) {
      if (c != '"') {
        field += c;
      } else if (i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == ',') {
      fields->emplace_back();
      was_quoted = false;
    } else if (c == '"' && field.empty() && !was_quoted) {
      quoted = true;
      was_quoted = true;
    } else if (was_quoted) {
      return false;  // text after a closing quote
    } else {
      field += c;
    }
  }
  return !quoted;
}

Status ReadAssociations(const std::string& path,
                        std::vector<AssociationRow>* rows) {
  std::string text;
  Status status = ReadText(path, &text);
  if (!status.ok()) return status;
  rows->clear();
  const std::vector<std::string_view> lines = SplitLines(text);
  static constexpr std::string_view kHeader =
      "keyframe,detection,object,symmetry";
  if (lines.empty() || lines[0] != kHeader) {
    return Status::Error(At(path, 1) + ": expected the header " +
                         std::string(kHeader));
  }
  std::set<std::string> seen;
  std::vector<std::string> fields;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const int number = static_cast<int>(i) + 1;
    if (lines[i].empty()) continue;
    if (!SplitCsv(lines[i], &fields)) {
      return Status::Error(At(path, number) + ": malformed quoted field");
    }
    if (fields.size() != 4) {
      return Status::Error(At(path, number) + ": expected 4 fields, found " +
                           std::to_string(fields.size()));
    }
    AssociationRow row;
    row.line = number;
    if (!ParseInteger(fields[0], &row.keyframe)) {
      return Status::Error(At(path, number) + ": keyframe " +
                           Quoted(fields[0]) + " is not an integer");
    }
    row.detection = fields[1];
    if (row.detection.empty()) {
      return Status::Error(At(path, number) + ": empty detection id");
    }
    if (!ParseInteger(fields[2], &row.object)) {
      return Status::Error(At(path, number) + ": object " + Quoted(fields[2]) +
                           " is not an integer");
    }
    const std::optional<SymmetryType> type = ParseSymmetryType(fields[3]);
    if (!type) {
      return Status::Error(At(path, number) + ": symmetry " +
                           Quoted(fields[3]) +
                           " is not asymmetric, discrete or continuous");
    }
    row.symmetry = *type;
    if (!seen.insert(row.detection).second) {
      return Status::Error(At(path, number) + ": duplicate detection " +
                           Quoted(row.detection));
    }
    rows->push_back(std::move(row));
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Formatting.

std::string Percent(int correct, int total) {
  if (total == 0) return "n/a";
  return Fixed(100.0 * correct / total, 1) + " % (" + std::to_string(correct) +
         "/" + std::to_string(total) + ")";
}

// One entry of the report's "objects"; NaN errors are written as null.
void ObjectJson(const ObjectEvaluation& o, JsonWriter* json) {
  json->BeginObject()
      .Member("gt_id", o.gt_id)
      .Member("class", o.class_name)
      .Member("symmetry", ToString(o.symmetry))
      .Member("order", o.order)
      .Member("detections", o.detections)
      .Member("rejected", o.rejected)
      .Member("map_objects", o.map_objects);
  json->Key("detections_per_map_object").BeginObject();
  for (const auto& [id, count] : o.detections_per_map_object) {
    json->Member(std::to_string(id), count);
  }
  json->EndObject().Key("main_object");
  if (o.main_object >= 0) {
    json->Int(o.main_object);
    json->Member("main_object_symmetry", ToString(o.main_object_symmetry));
  } else {
    json->Null().Key("main_object_symmetry").Null();
  }
  json->Member("translation_error", o.translation_error)
      .Member("axis_error_deg", o.axis_error_deg)
      .Member("rotation_error_deg", o.rotation_error_deg)
      .Member("position_nees", o.position_nees)
      .Member("categorized_correctly", o.categorized_correctly)
      .Member("categorization_accuracy", o.categorization_accuracy)
      .EndObject();
}

}  // namespace

// ---------------------------------------------------------------------------

Status ReadGroundTruth(const std::string& gt_dir, GroundTruth* gt) {
  *gt = GroundTruth();
  gt->trajectory_path = JoinPath(gt_dir, "gt_trajectory.tum");
  gt->objects_path = JoinPath(gt_dir, "gt_objects.json");
  Status status = ReadTum(gt->trajectory_path, &gt->keyframes);
  if (!status.ok()) return status;
  return ReadGroundTruthObjectsJson(
      gt->objects_path, &gt->objects, &gt->detections);
}

Status ReadReplayOutputs(const std::string& result_dir,
                         ReplayOutputs* outputs) {
  *outputs = ReplayOutputs();
  outputs->trajectory_path = JoinPath(result_dir, "trajectory.tum");
  outputs->objects_path = JoinPath(result_dir, "objects.json");
  outputs->associations_path = JoinPath(result_dir, "associations.csv");
  Status status = ReadTum(outputs->trajectory_path, &outputs->keyframes);
  if (!status.ok()) return status;
  status = ReadObjectsJson(outputs->objects_path, &outputs->objects);
  if (!status.ok()) return status;
  return ReadAssociations(outputs->associations_path, &outputs->associations);
}

int Evaluation::MaxFragmentation() const {
  int largest = 0;
  for (const ObjectEvaluation& o : objects) {
    largest = std::max(largest, o.map_objects);
  }
  return largest;
}

double PositionNees(const MapObjectEstimate& m, const Eigen::Vector3d& t_true) {
  if (!m.covariance) return kNaN;
  const Eigen::LLT<Eigen::Matrix3d> llt(m.covariance->position);
  if (llt.info() != Eigen::Success) return kNaN;
  const Eigen::Vector3d e = m.t_wo - t_true;
  return e.dot(llt.solve(e));
}

Status EvaluateReplay(const GroundTruth& gt,
                      const ReplayOutputs& result,
                      Evaluation* evaluation) {
  Evaluation e;

  // Keyframes, matched by timestamp (both lists increase strictly).
  std::vector<bool> gt_matched(gt.keyframes.size(), false);
  double sum_position = 0.0;
  double sum_rotation = 0.0;
  for (const TrajectoryPose& kf : result.keyframes) {
    const auto it = std::lower_bound(
        gt.keyframes.begin(),
        gt.keyframes.end(),
        kf.timestamp - kTimestampTolerance,
        [](const TrajectoryPose& p, double t) { return p.timestamp < t; });
    if (it == gt.keyframes.end() ||
        it->timestamp > kf.timestamp + kTimestampTolerance) {
      return Status::Error(At(result.trajectory_path, kf.line) +
                           ": no keyframe of " + gt.trajectory_path +
                           " has timestamp " + FormatDouble(kf.timestamp));
    }
    gt_matched[it - gt.keyframes.begin()] = true;
    const double position_error = (kf.T_wc.t - it->T_wc.t).norm();
    const double rotation_error = AngleBetween(it->T_wc.q, kf.T_wc.q);
    sum_position += position_error * position_error;
    sum_rotation += rotation_error * rotation_error;
    e.max_position_error = std::max(e.max_position_error, position_error);
  }
  for (std::size_t i = 0; i < gt.keyframes.size(); ++i) {
    if (!gt_matched[i]) {
      return Status::Error(At(gt.trajectory_path, gt.keyframes[i].line) +
                           ": the keyframe at timestamp " +
                           FormatDouble(gt.keyframes[i].timestamp) +
                           " has no estimate in " + result.trajectory_path);
    }
  }
  e.keyframes = static_cast<int>(result.keyframes.size());
  e.position_rmse = std::sqrt(sum_position / e.keyframes);
  e.rotation_rmse_deg =
      kDegreesPerRadian * std::sqrt(sum_rotation / e.keyframes);

  // Map objects by id.
  std::map<int, const MapObjectEstimate*> map_objects;
  for (const MapObjectEstimate& o : result.objects) map_objects[o.id] = &o;
  e.map_objects = static_cast<int>(result.objects.size());

  // Detections: ground-truth object and map object of each.
  std::map<int, std::size_t> gt_index;
  for (std::size_t i = 0; i < gt.objects.size(); ++i) {
    gt_index[gt.objects[i].id] = i;
    ObjectEvaluation o;
    o.gt_id = gt.objects[i].id;
    o.class_name = gt.objects[i].class_name;
    o.symmetry = gt.objects[i].symmetry;
    o.order = gt.objects[i].order;
    e.objects.push_back(std::move(o));
  }
  std::set<std::string> associated;
  for (const AssociationRow& row : result.associations) {
    const auto detection = gt.detections.find(row.detection);
    if (detection == gt.detections.end()) {
      return Status::Error(At(result.associations_path, row.line) +
                           ": detection " + Quoted(row.detection) +
                           " is not in " + gt.objects_path);
    }
    // Object -1: the backend rejected the detection as an outlier.
    if (row.object != -1 && map_objects.count(row.object) == 0) {
      return Status::Error(At(result.associations_path, row.line) +
                           ": map object " + std::to_string(row.object) +
                           " is not in " + result.objects_path);
    }
    associated.insert(row.detection);
    ObjectEvaluation& o = e.objects[gt_index.at(detection->second)];
    ++o.detections;
    if (row.object == -1) {
      ++o.rejected;
    } else {
      ++o.detections_per_map_object[row.object];
    }
    const bool correct = row.symmetry == o.symmetry;
    o.categorized_correctly += correct ? 1 : 0;
    e.categorized_correctly += correct ? 1 : 0;
    ++e.detections;
    ++e.confusion[static_cast<int>(o.symmetry)][static_cast<int>(row.symmetry)];
  }
  for (const auto& [id, object] : gt.detections) {
    (void)object;
    if (associated.count(id) == 0) {
      return Status::Error(gt.objects_path + ": detection " + Quoted(id) +
                           " has no row in " + result.associations_path);
    }
  }
  e.categorization_accuracy =
      e.detections > 0
          ? static_cast<double>(e.categorized_correctly) / e.detections
          : kNaN;

  // Per ground-truth object.
  for (std::size_t i = 0; i < gt.objects.size(); ++i) {
    const GroundTruthObject& g = gt.objects[i];
    ObjectEvaluation& o = e.objects[i];
    o.map_objects = static_cast<int>(o.detections_per_map_object.size());
    o.translation_error = kNaN;
    o.position_nees = kNaN;
    o.axis_error_deg = kNaN;
    o.rotation_error_deg = kNaN;
    o.categorization_accuracy =
        o.detections > 0
            ? static_cast<double>(o.categorized_correctly) / o.detections
            : kNaN;
    int most = 0;
    for (const auto& [id, count] : o.detections_per_map_object) {
      if (count > most) {  // ascending ids: ties keep the lowest
        most = count;
        o.main_object = id;
      }
    }
    if (o.main_object < 0) continue;
    const MapObjectEstimate& m = *map_objects.at(o.main_object);
    o.main_object_symmetry = m.symmetry;
    o.translation_error = (m.t_wo - g.T_wo.t).norm();
    o.position_nees = PositionNees(m, g.T_wo.t);
    if (g.symmetry != SymmetryType::kAsymmetric) {
      const Eigen::Vector3d a_w =
          m.symmetry != SymmetryType::kAsymmetric
              ? m.axis_w
              : Eigen::Vector3d(m.poses[0].q * g.axis_o);
      o.axis_error_deg = kDegreesPerRadian * LineAngle(a_w, g.axis_w);
    }
    if (g.symmetry == SymmetryType::kContinuous) {
      o.rotation_error_deg = o.axis_error_deg;
    } else {
      const int n = g.symmetry == SymmetryType::kDiscrete ? g.order : 1;
      double best = kPi;
      for (int k = 0; k < n; ++k) {
        const Eigen::Quaterniond q_k =
            g.symmetry == SymmetryType::kDiscrete
                ? g.T_wo.q * Eigen::Quaterniond(
                                 Eigen::AngleAxisd(kTwoPi * k / n, g.axis_o))
                : g.T_wo.q;
        for (const Rigid3d& T : m.poses) {
          best = std::min(best, AngleBetween(q_k, T.q));
        }
      }
      o.rotation_error_deg = kDegreesPerRadian * best;
    }
  }
  *evaluation = std::move(e);
  return Status::Ok();
}

Status Evaluate(const std::string& gt_dir,
                const std::string& result_dir,
                Evaluation* evaluation) {
  GroundTruth gt;
  Status status = ReadGroundTruth(gt_dir, &gt);
  if (!status.ok()) return status;
  ReplayOutputs result;
  status = ReadReplayOutputs(result_dir, &result);
  if (!status.ok()) return status;
  return EvaluateReplay(gt, result, evaluation);
}

std::string FormatEvaluationTable(const Evaluation& e) {
  std::ostringstream out;
  out << "| keyframes | position RMSE [m] | rotation RMSE [deg] | max position "
         "error [m] | map objects | categorisation |\n"
      << "|---:|---:|---:|---:|---:|---:|\n"
      << "| " << e.keyframes << " | " << Fixed(e.position_rmse, 3) << " | "
      << Fixed(e.rotation_rmse_deg, 2) << " | "
      << Fixed(e.max_position_error, 3) << " | " << e.map_objects << " | "
      << Percent(e.categorized_correctly, e.detections) << " |\n\n";
  out << "| GT object | class | symmetry | detections | map objects | main "
         "object | translation error [m] | axis error [deg] | rotation error "
         "[deg] | categorisation |\n"
      << "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const ObjectEvaluation& o : e.objects) {
    std::string symmetry = ToString(o.symmetry);
    if (o.symmetry == SymmetryType::kDiscrete) {
      symmetry += " (" + std::to_string(o.order) + ")";
    }
    out << "| " << o.gt_id << " | " << o.class_name << " | " << symmetry
        << " | " << o.detections << " | " << o.map_objects << " | "
        << (o.main_object >= 0 ? std::to_string(o.main_object) + " (" +
                                     ToString(o.main_object_symmetry) + ")"
                               : std::string("none"))
        << " | " << Fixed(o.translation_error, 3) << " | "
        << Fixed(o.axis_error_deg, 2) << " | " << Fixed(o.rotation_error_deg, 2)
        << " | " << Percent(o.categorized_correctly, o.detections) << " |\n";
  }
  out << "\n| GT type \\ categorised | asymmetric | discrete | continuous "
         "|\n"
      << "|---|---:|---:|---:|\n";
  for (int g = 0; g < 3; ++g) {
    out << "| " << ToString(static_cast<SymmetryType>(g));
    for (int c = 0; c < 3; ++c) out << " | " << e.confusion[g][c];
    out << " |\n";
  }
  return out.str();
}

std::string FormatEvaluationJson(const Evaluation& e) {
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("keyframes", e.keyframes)
      .Member("position_rmse", e.position_rmse)
      .Member("rotation_rmse_deg", e.rotation_rmse_deg)
      .Member("max_position_error", e.max_position_error)
      .Member("map_objects", e.map_objects)
      .Member("max_fragmentation", e.MaxFragmentation())
      .Member("detections", e.detections)
      .Member("categorized_correctly", e.categorized_correctly)
      .Member("categorization_accuracy", e.categorization_accuracy);
  json.Key("confusion").BeginObject();
  for (int g = 0; g < 3; ++g) {
    json.Key(ToString(static_cast<SymmetryType>(g))).BeginObject();
    for (int c = 0; c < 3; ++c) {
      json.Member(ToString(static_cast<SymmetryType>(c)), e.confusion[g][c]);
    }
    json.EndObject();
  }
  json.EndObject().Key("objects").BeginArray();
  for (const ObjectEvaluation& o : e.objects) ObjectJson(o, &json);
  json.EndArray().EndObject();
  out.push_back('\n');
  return out;
}

}  // namespace symba
