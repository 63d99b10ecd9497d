#include "symba/io/objects_json.h"

#include <cmath>
#include <cstddef>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "io/json_file.h"

namespace symba {
namespace {

using internal::Json;
using internal::JsonReader;
using OrderedJson = nlohmann::ordered_json;

OrderedJson Vector(const Eigen::Vector3d& v) {
  return OrderedJson::array({v.x(), v.y(), v.z()});
}

OrderedJson Pose(const Rigid3d& T) {
  const Eigen::Quaterniond q = T.q.normalized();
  return OrderedJson{{"t", Vector(T.t)},
                     {"q", OrderedJson::array({q.x(), q.y(), q.z(), q.w()})}};
}

}  // namespace

std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects) {
  OrderedJson list = OrderedJson::array();
  for (const MapObjectEstimate& o : objects) {
    OrderedJson object{{"id", o.id},
                       {"class", o.class_name},
                       {"symmetry", ToString(o.symmetry)},
                       {"t", Vector(o.t_wo)}};
    if (o.symmetry != SymmetryType::kAsymmetric) {
      object["axis"] = Vector(o.axis_w);
    }
    if (o.symmetry == SymmetryType::kDiscrete) object["angles"] = o.angles;
    OrderedJson poses = OrderedJson::array();
    for (const Rigid3d& pose : o.poses) poses.push_back(Pose(pose));
    object["poses"] = std::move(poses);
    object["observations"] = o.observations;
    if (o.upgrade) {
      // An asymmetric object that became symmetric, and on what evidence.
      object["upgrade"] = OrderedJson{{"keyframe", o.upgrade->keyframe},
                                      {"evidence", o.upgrade->evidence},
                                      {"order", o.upgrade->order},
                                      {"angle", o.upgrade->angle}};
    }
    list.push_back(std::move(object));
  }
  return OrderedJson{{"objects", std::move(list)}}.dump(2) + "\n";
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
