#include "symba/io/ground_truth_objects.h"

#include <cstdint>
#include <limits>
#include <set>
#include <utility>

#include "io/json_file.h"
#include "io/json_writer.h"

namespace symba {
namespace {

using internal::Json;
using internal::JsonReader;
using internal::Quoted;
using io_internal::JsonWriter;

// gt_objects.json: "axis" must be pose.q * "axis_o" to this (unit vectors).
constexpr double kAxisConsistency = 1e-3;

}  // namespace

// Each object and each detection on a line of its own.
std::string FormatGroundTruthObjectsJson(
    const std::vector<GroundTruthObject>& objects,
    const std::vector<std::pair<std::string, int>>& detections) {
  std::string out;
  JsonWriter json(&out, /*wrap_depth=*/2);
  json.BeginObject().Key("objects").BeginArray();
  for (const GroundTruthObject& o : objects) {
    json.BeginObject()
        .Member("id", o.id)
        .Member("class", o.class_name)
        .Member("symmetry", ToString(o.symmetry))
        .Member("order", o.order);
    if (o.symmetry != SymmetryType::kAsymmetric) {
      json.Key("axis_o").Doubles(o.axis_o.data(), 3);
      json.Key("axis").Doubles(o.axis_w.data(), 3);
    }
    const Eigen::Quaterniond& q = o.T_wo.q;
    const double coeffs[4] = {q.x(), q.y(), q.z(), q.w()};
    json.Key("pose").BeginObject();
    json.Key("t").Doubles(o.T_wo.t.data(), 3);
    json.Key("q").Doubles(coeffs, 4);
    json.EndObject().EndObject();
  }
  json.EndArray().Key("detections").BeginObject();
  for (const auto& [detection, object] : detections) {
    json.Member(detection, object);
  }
  json.EndObject().EndObject();
  out.push_back('\n');
  return out;
}

Status ReadGroundTruthObjectsJson(
    const std::string& path,
    std::vector<GroundTruthObject>* result,
    std::map<std::string, int>* detection_objects) {
  Json root;
  const Json* objects = nullptr;
  Status status = internal::ReadObjectsArray(path, &root, &objects);
  if (!status.ok()) return status;
  const JsonReader r(path);
  std::set<int> ids;
  for (std::size_t i = 0; i < objects->size(); ++i) {
    const Json& json = (*objects)[i];
    const std::string where = JsonReader::Index("objects", i);
    GroundTruthObject o;
    status = r.ObjectIdentity(json, where, &o.id, &o.class_name, &o.symmetry);
    if (status.ok()) status = r.Int(json, where, "order", &o.order);
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) {
      return r.Error(JsonReader::Sub(where, "id"),
                     "duplicate id " + std::to_string(o.id));
    }
    if (o.symmetry == SymmetryType::kDiscrete ? o.order < 2 : o.order != 0) {
      return r.Error(JsonReader::Sub(where, "order"),
                     o.symmetry == SymmetryType::kDiscrete
                         ? "a discrete object needs an order of at least 2"
                         : "must be 0 for an object that is not discrete");
    }
    const Json* pose = nullptr;
    status = r.Member(json, where, "pose", &pose);
    if (status.ok()) {
      status = r.Pose(*pose, JsonReader::Sub(where, "pose"), &o.T_wo);
    }
    if (!status.ok()) return status;
    if (o.symmetry != SymmetryType::kAsymmetric) {
      status = r.UnitVector(json, where, "axis_o", &o.axis_o);
      if (status.ok()) status = r.UnitVector(json, where, "axis", &o.axis_w);
      if (!status.ok()) return status;
      if ((o.T_wo.q * o.axis_o - o.axis_w).norm() > kAxisConsistency) {
        return r.Error(JsonReader::Sub(where, "axis"),
                       "is not pose.q * axis_o");
      }
    }
    result->push_back(std::move(o));
  }
  const Json* detections = nullptr;
  status = r.Member(root, "top level", "detections", &detections);
  if (!status.ok()) return status;
  if (!detections->is_object()) {
    return r.Error("detections", "expected a JSON object");
  }
  for (const auto& [id, value] : detections->items()) {
    const std::string where = "detections[" + Quoted(id) + "]";
    if (!value.is_number_integer()) {
      return r.Error(where, "expected an integer (a ground-truth object id)");
    }
    const int64_t object = value.get<int64_t>();
    if (object < std::numeric_limits<int>::min() ||
        object > std::numeric_limits<int>::max() ||
        ids.count(static_cast<int>(object)) == 0) {
      return r.Error(where,
                     "object " + std::to_string(object) + " is not in objects");
    }
    (*detection_objects)[id] = static_cast<int>(object);
  }
  return Status::Ok();
}

}  // namespace symba
