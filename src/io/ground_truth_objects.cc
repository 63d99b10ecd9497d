#include "symba/io/ground_truth_objects.h"

#include <cstdint>
#include <limits>
#include <set>
#include <utility>

#include "io/json_file.h"
#include "io/json_text.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

using internal::Json;
using internal::JsonReader;
using internal::Quoted;
using io_internal::AppendJsonString;

// gt_objects.json: "axis" must be pose.q * "axis_o" to this (unit vectors).
constexpr double kAxisConsistency = 1e-3;

void AppendNumbers(const double* values, int count, std::string* out) {
  out->push_back('[');
  for (int i = 0; i < count; ++i) {
    if (i > 0) out->append(", ");
    AppendDouble(values[i], out);
  }
  out->push_back(']');
}

void AppendVector(const Eigen::Vector3d& v, std::string* out) {
  AppendNumbers(v.data(), 3, out);
}

}  // namespace

std::string FormatGroundTruthObjectsJson(
    const std::vector<GroundTruthObject>& objects,
    const std::vector<std::pair<std::string, int>>& detections) {
  std::string out = "{\"objects\": [";
  for (size_t i = 0; i < objects.size(); ++i) {
    const GroundTruthObject& o = objects[i];
    out.append(i == 0 ? "\n  " : ",\n  ");
    out.append("{\"id\": " + std::to_string(o.id) + ", \"class\": ");
    AppendJsonString(o.class_name, &out);
    out.append(", \"symmetry\": ");
    AppendJsonString(ToString(o.symmetry), &out);
    out.append(", \"order\": " + std::to_string(o.order));
    const Eigen::Quaterniond& q = o.T_wo.q;
    if (o.symmetry != SymmetryType::kAsymmetric) {
      out.append(", \"axis_o\": ");
      AppendVector(o.axis_o, &out);
      out.append(", \"axis\": ");
      AppendVector(o.axis_w, &out);
    }
    out.append(", \"pose\": {\"t\": ");
    AppendVector(o.T_wo.t, &out);
    out.append(", \"q\": ");
    const double coeffs[4] = {q.x(), q.y(), q.z(), q.w()};
    AppendNumbers(coeffs, 4, &out);
    out.append("}}");
  }
  out.append(objects.empty() ? "],\n" : "\n],\n");
  out.append("\"detections\": {");
  bool first = true;
  for (const auto& [detection, object] : detections) {
    out.append(first ? "\n  " : ",\n  ");
    first = false;
    AppendJsonString(detection, &out);
    out.append(": " + std::to_string(object));
  }
  out.append(first ? "}}\n" : "\n}}\n");
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
