#include "symba/io/ground_truth_objects.h"

#include <cstdint>
#include <limits>
#include <set>
#include <utility>

#include "io/json_tree_reader.h"
#include "io/json_writer.h"

namespace symba {
namespace {

using io_internal::JsonPath;
using io_internal::JsonTree;
using io_internal::JsonTreeReader;
using io_internal::JsonType;
using io_internal::JsonWriter;

// gt_objects.json: "axis" must be pose.q * "axis_o" to this (unit vectors).
constexpr double kAxisConsistency = 1e-3;

// One entry of "objects" (its id is checked for duplicates by the caller).
Status GroundTruthObjectAt(const JsonTreeReader& r,
                           JsonTree::Index e,
                           const JsonPath& where,
                           GroundTruthObject* o) {
  Status status = io_internal::ObjectIdentity(
      r, e, where, &o->id, &o->class_name, &o->symmetry);
  JsonTree::Index member = 0;
  if (status.ok()) status = r.Require(e, where, "order", "", &member);
  if (status.ok()) status = r.Int(member, where.Member("order"), &o->order);
  if (!status.ok()) return status;
  const bool discrete = o->symmetry == SymmetryType::kDiscrete;
  if (discrete ? o->order < 2 : o->order != 0) {
    return r.Fail(where.Member("order"),
                  discrete ? "a discrete object needs an order of at least 2"
                           : "must be 0 for an object that is not discrete");
  }
  status = r.Require(e, where, "pose", "", &member);
  if (status.ok()) status = r.Pose(member, where.Member("pose"), &o->T_wo);
  if (!status.ok() || o->symmetry == SymmetryType::kAsymmetric) return status;
  status = r.Require(e, where, "axis_o", "", &member);
  if (status.ok()) {
    status = r.UnitVector(member, where.Member("axis_o"), &o->axis_o);
  }
  if (status.ok()) status = r.Require(e, where, "axis", "", &member);
  if (status.ok()) {
    status = r.UnitVector(member, where.Member("axis"), &o->axis_w);
  }
  if (!status.ok()) return status;
  if ((o->T_wo.q * o->axis_o - o->axis_w).norm() > kAxisConsistency) {
    return r.Fail(where.Member("axis"), "is not pose.q * axis_o");
  }
  return Status::Ok();
}

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
  JsonTree tree;
  Status status = io_internal::ReadJsonFile(path, &tree);
  if (!status.ok()) return status;
  const JsonTreeReader r(path, 0, tree);
  JsonTree::Index objects = 0;
  status = io_internal::ObjectsArray(r, &objects);
  if (!status.ok()) return status;
  const JsonPath root;
  const JsonPath objects_path = root.Member("objects");
  std::set<int> ids;
  int i = 0;
  for (JsonTree::Index e = tree.node(objects).first; e != 0;
       e = tree.node(e).next, ++i) {
    GroundTruthObject o;
    const JsonPath where = objects_path.Element(i);
    status = GroundTruthObjectAt(r, e, where, &o);
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) {
      return r.Fail(where.Member("id"), "duplicate id " + std::to_string(o.id));
    }
    result->push_back(std::move(o));
  }
  JsonTree::Index detections = 0;
  status = r.Require(0, root, "detections", "", &detections);
  const JsonPath detections_path = root.Member("detections");
  if (status.ok()) status = r.Object(detections, detections_path);
  if (!status.ok()) return status;
  for (JsonTree::Index e = tree.node(detections).first; e != 0;
       e = tree.node(e).next) {
    const JsonPath where = detections_path.QuotedMember(tree.Key(e));
    int object = 0;
    status = r.Int(e, where, &object);
    if (!status.ok()) return status;
    if (ids.count(object) == 0) {
      return r.Fail(where,
                    "object " + std::to_string(object) + " is not in objects");
    }
    (*detection_objects)[std::string(tree.Key(e))] = object;
  }
  return Status::Ok();
}

}  // namespace symba
