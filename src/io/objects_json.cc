#include "symba/io/objects_json.h"

#include <cmath>
#include <cstddef>
#include <set>
#include <utility>

#include "io/json_tree_reader.h"
#include "io/json_writer.h"

namespace symba {
namespace {

using io_internal::JsonPath;
using io_internal::JsonTree;
using io_internal::JsonTreeReader;
using io_internal::JsonWriter;
using io_internal::ObjectIdentity;
using io_internal::ObjectsArray;
using io_internal::ReadJsonFile;

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

// "angles": an array of numbers (a discrete object's theta_i).
Status Angles(const JsonTreeReader& r,
              JsonTree::Index object,
              const JsonPath& where,
              std::vector<double>* angles) {
  JsonTree::Index array = 0;
  const JsonPath path = where.Member("angles");
  Status status = r.Require(object, where, "angles", "", &array);
  if (status.ok()) status = r.Array(array, path);
  int k = 0;
  for (JsonTree::Index e = status.ok() ? r.tree().node(array).first : 0; e != 0;
       e = r.tree().node(e).next, ++k) {
    double angle = 0.0;
    status = r.Number(e, path.Element(k), &angle);
    if (!status.ok()) return status;
    angles->push_back(angle);
  }
  return status;
}

// "poses": a non-empty array of poses.
Status Poses(const JsonTreeReader& r,
             JsonTree::Index object,
             const JsonPath& where,
             std::vector<Rigid3d>* poses) {
  JsonTree::Index array = 0;
  const JsonPath path = where.Member("poses");
  Status status = r.Require(object, where, "poses", "", &array);
  if (status.ok()) status = r.Array(array, path);
  if (!status.ok()) return status;
  if (r.tree().node(array).size == 0) {
    return r.Fail(path, "expected a non-empty array of poses");
  }
  int k = 0;
  for (JsonTree::Index e = r.tree().node(array).first; e != 0;
       e = r.tree().node(e).next, ++k) {
    Rigid3d T;
    status = r.Pose(e, path.Element(k), &T);
    if (!status.ok()) return status;
    poses->push_back(T);
  }
  return Status::Ok();
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
  JsonTree tree;
  Status status = ReadJsonFile(path, &tree);
  if (!status.ok()) return status;
  const JsonTreeReader r(path, 0, tree);
  const JsonPath root;
  JsonTree::Index objects = 0;
  status = ObjectsArray(r, &objects);
  if (!status.ok()) return status;
  const JsonPath objects_path = root.Member("objects");
  std::set<int> ids;
  result->clear();
  int i = 0;
  for (JsonTree::Index e = tree.node(objects).first; e != 0;
       e = tree.node(e).next, ++i) {
    const JsonPath where = objects_path.Element(i);
    MapObjectEstimate o;
    status = ObjectIdentity(r, e, where, &o.id, &o.class_name, &o.symmetry);
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) {
      return r.Fail(where.Member("id"), "duplicate id " + std::to_string(o.id));
    }
    JsonTree::Index member = 0;
    status = r.Require(e, where, "t", "", &member);
    if (status.ok())
      status = r.Numbers(member, where.Member("t"), 3, o.t_wo.data());
    if (status.ok()) status = r.Require(e, where, "observations", "", &member);
    if (status.ok()) {
      status = r.Int(member, where.Member("observations"), &o.observations);
    }
    if (status.ok() && o.symmetry != SymmetryType::kAsymmetric) {
      status = r.Require(e, where, "axis", "", &member);
      if (status.ok())
        status = r.UnitVector(member, where.Member("axis"), &o.axis_w);
    }
    if (status.ok() && o.symmetry == SymmetryType::kDiscrete) {
      status = Angles(r, e, where, &o.angles);
    }
    if (status.ok()) status = Poses(r, e, where, &o.poses);
    if (!status.ok()) return status;
    result->push_back(std::move(o));
  }
  return Status::Ok();
}

}  // namespace symba
