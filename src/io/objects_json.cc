#include "symba/io/objects_json.h"

#include <cmath>
#include <cstddef>
#include <set>
#include <utility>

#include "io/json_file.h"
#include "io/json_writer.h"

namespace symba {
namespace {

using internal::Json;
using internal::JsonReader;
using io_internal::JsonWriter;

void Pose(const Rigid3d& T, JsonWriter* json) {
  const Eigen::Quaterniond q = T.q.normalized();
  const double coeffs[4] = {q.x(), q.y(), q.z(), q.w()};
  json->BeginObject();
  json->Key("t").Doubles(T.t.data(), 3);
  json->Key("q").Doubles(coeffs, 4);
  json->EndObject();
}

void MapObject(const MapObjectEstimate& o, JsonWriter* json) {
  json->BeginObject()
      .Member("id", o.id)
      .Member("class", o.class_name)
      .Member("symmetry", ToString(o.symmetry));
  json->Key("t").Doubles(o.t_wo.data(), 3);
  if (o.symmetry != SymmetryType::kAsymmetric) {
    json->Key("axis").Doubles(o.axis_w.data(), 3);
  }
  if (o.symmetry == SymmetryType::kDiscrete) {
    json->Key("angles").Doubles(o.angles.data(),
                                static_cast<int>(o.angles.size()));
  }
  json->Key("poses").BeginArray();
  for (const Rigid3d& pose : o.poses) Pose(pose, json);
  json->EndArray().Member("observations", o.observations);
  if (o.upgrade) {
    // An asymmetric object that became symmetric, and on what evidence.
    json->Key("upgrade")
        .BeginObject()
        .Member("keyframe", o.upgrade->keyframe)
        .Member("evidence", o.upgrade->evidence)
        .Member("order", o.upgrade->order)
        .Member("angle", o.upgrade->angle)
        .EndObject();
  }
  json->EndObject();
}

}  // namespace

std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects) {
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject().Key("objects").BeginArray();
  for (const MapObjectEstimate& o : objects) MapObject(o, &json);
  json.EndArray().EndObject();
  out.push_back('\n');
  return out;
}

Status ReadObjectsJson(const std::string& path,
                       std::vector<MapObjectEstimate>* result) {
  Json root;
  const Json* objects = nullptr;
  Status status = internal::ReadObjectsArray(path, &root, &objects);
  if (!status.ok()) return status;
  const JsonReader r(path);
  std::set<int> ids;
  result->clear();
  for (std::size_t i = 0; i < objects->size(); ++i) {
    const Json& json = (*objects)[i];
    const std::string where = JsonReader::Index("objects", i);
    MapObjectEstimate o;
    status = r.ObjectIdentity(json, where, &o.id, &o.class_name, &o.symmetry);
    if (status.ok()) status = r.Vector(json, where, "t", &o.t_wo);
    if (status.ok()) {
      status = r.Int(json, where, "observations", &o.observations);
    }
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) {
      return r.Error(JsonReader::Sub(where, "id"),
                     "duplicate id " + std::to_string(o.id));
    }
    if (o.symmetry != SymmetryType::kAsymmetric) {
      status = r.UnitVector(json, where, "axis", &o.axis_w);
      if (!status.ok()) return status;
    }
    if (o.symmetry == SymmetryType::kDiscrete) {
      const Json* angles = nullptr;
      status = r.Member(json, where, "angles", &angles);
      if (!status.ok()) return status;
      const std::string angles_where = JsonReader::Sub(where, "angles");
      if (!angles->is_array()) {
        return r.Error(angles_where, "expected an array of numbers");
      }
      for (const Json& angle : *angles) {
        if (!angle.is_number() || !std::isfinite(angle.get<double>())) {
          return r.Error(angles_where, "expected an array of finite numbers");
        }
        o.angles.push_back(angle.get<double>());
      }
    }
    const Json* poses = nullptr;
    status = r.Member(json, where, "poses", &poses);
    if (!status.ok()) return status;
    const std::string poses_where = JsonReader::Sub(where, "poses");
    if (!poses->is_array() || poses->empty()) {
      return r.Error(poses_where, "expected a non-empty array of poses");
    }
    for (std::size_t k = 0; k < poses->size(); ++k) {
      Rigid3d T;
      status = r.Pose((*poses)[k], JsonReader::Index(poses_where, k), &T);
      if (!status.ok()) return status;
      o.poses.push_back(T);
    }
    result->push_back(std::move(o));
  }
  return Status::Ok();
}

}  // namespace symba
