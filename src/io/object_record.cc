#include "io/object_record.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace symba {
namespace io_internal {

void WritePose(const Rigid3d& T, JsonWriter* json) {
  // Normalised only if it is not unit already (to the reader's 8 eps):
  // normalising again may change the last bit, and a map read and written
  // again must keep its bytes.
  Eigen::Quaterniond q = T.q;
  if (std::abs(q.squaredNorm() - 1.0) > 8.0 * 2.220446049250313e-16) {
    q.normalize();
  }
  const double coeffs[4] = {q.x(), q.y(), q.z(), q.w()};
  json->BeginObject();
  json->Key("t").Doubles(T.t.data(), 3);
  json->Key("q").Doubles(coeffs, 4);
  json->EndObject();
}

namespace {

// Covariances are written with 6 significant digits: Ceres orders the
// blocks of a covariance by their addresses, so the last digits differ
// from run to run (round-off), and an uncertainty needs no more.
double Significant6(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return std::strtod(text, nullptr);
}

// A 3x3 matrix as three rows.
void Matrix3(const char* key, const Eigen::Matrix3d& m, JsonWriter* json) {
  json->Key(key).BeginArray();
  for (int r = 0; r < 3; ++r) {
    const double row[3] = {
        Significant6(m(r, 0)), Significant6(m(r, 1)), Significant6(m(r, 2))};
    json->Doubles(row, 3);
  }
  json->EndArray();
}

void Covariance(const MapObjectCovariance& c, JsonWriter* json) {
  Matrix3("position_covariance", c.position, json);
  if (c.rotation) Matrix3("rotation_covariance", *c.rotation, json);
  if (c.axis) Matrix3("axis_covariance", *c.axis, json);
  if (!c.angle_variances.empty()) {
    json->Key("angle_variances").BeginArray();
    for (const std::optional<double>& v : c.angle_variances) {
      if (v) {
        json->Double(Significant6(*v));
      } else {
        json->Null();
      }
    }
    json->EndArray();
  }
  json->Member("covariance_source", CovarianceSourceName(c.source));
}

void WriteObjectRecordImpl(const MapObjectEstimate& o, JsonWriter* json) {
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
    // The probabilities are derived from the evidence (a reader takes the
    // evidence only), written for readers of objects.json.
    // An estimate made without evidence (by a caller) has none: zeros.
    const std::vector<double> evidence =
        o.angle_evidence.size() == o.angles.size()
            ? o.angle_evidence
            : std::vector<double>(o.angles.size(), 0.0);
    const std::vector<double> probabilities = AngleProbabilities(evidence);
    json->Key("angle_evidence")
        .Doubles(evidence.data(), static_cast<int>(evidence.size()));
    json->Key("angle_probabilities")
        .Doubles(probabilities.data(), static_cast<int>(probabilities.size()));
  }
  json->Key("poses").BeginArray();
  for (const Rigid3d& pose : o.poses) WritePose(pose, json);
  json->EndArray().Member("observations", o.observations);
  if (o.covariance) Covariance(*o.covariance, json);
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

// "angle_evidence" (optional; a discrete object's, one count >= 0 per
// angle; absent: zeros).
Status AngleEvidence(const JsonTreeReader& r,
                     JsonTree::Index object,
                     const JsonPath& where,
                     MapObjectEstimate* o) {
  const JsonTree::Index array = r.Find(object, "angle_evidence");
  if (array == 0) {
    if (o->symmetry == SymmetryType::kDiscrete) {
      o->angle_evidence.assign(o->angles.size(), 0.0);
    }
    return Status::Ok();
  }
  const JsonPath path = where.Member("angle_evidence");
  Status status = r.Array(array, path);
  if (!status.ok()) return status;
  if (o->symmetry != SymmetryType::kDiscrete) {
    return r.Fail(path, "only a discrete object has it");
  }
  if (r.tree().node(array).size != o->angles.size()) {
    return r.Fail(path,
                  "expected " + std::to_string(o->angles.size()) +
                      " entries, one per angle");
  }
  int k = 0;
  for (JsonTree::Index e = r.tree().node(array).first; e != 0;
       e = r.tree().node(e).next, ++k) {
    double evidence = 0.0;
    status = r.Number(e, path.Element(k), &evidence);
    if (status.ok() && !(evidence >= 0.0)) {
      status = r.Fail(path.Element(k), "expected evidence >= 0");
    }
    if (!status.ok()) return status;
    o->angle_evidence.push_back(evidence);
  }
  return Status::Ok();
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

// An optional 3x3 symmetric matrix with a non-negative diagonal, as three
// rows of three numbers. False in *present if the member is not there.
Status OptionalMatrix3(const JsonTreeReader& r,
                       JsonTree::Index object,
                       const JsonPath& where,
                       const char* key,
                       bool* present,
                       Eigen::Matrix3d* m) {
  const JsonTree::Index rows = r.Find(object, key);
  *present = rows != 0;
  if (rows == 0) return Status::Ok();
  const JsonPath path = where.Member(key);
  Status status = r.Array(rows, path);
  if (status.ok() && r.tree().node(rows).size != 3) {
    return r.Fail(path, "expected 3 rows of 3 numbers");
  }
  int i = 0;
  for (JsonTree::Index e = status.ok() ? r.tree().node(rows).first : 0; e != 0;
       e = r.tree().node(e).next, ++i) {
    Eigen::RowVector3d row;
    status = r.Numbers(e, path.Element(i), 3, row.data());
    if (!status.ok()) return status;
    m->row(i) = row;
  }
  if (!status.ok()) return status;
  const double scale = m->cwiseAbs().maxCoeff();
  if ((*m - m->transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    return r.Fail(path, "expected a symmetric matrix");
  }
  if (m->diagonal().minCoeff() < 0.0) {
    return r.Fail(path, "expected a non-negative diagonal (variances)");
  }
  return Status::Ok();
}

// The covariance members (all optional; position_covariance present if any
// other is).
Status ReadCovariance(const JsonTreeReader& r,
                      JsonTree::Index object,
                      const JsonPath& where,
                      MapObjectEstimate* o) {
  MapObjectCovariance c;
  c.id = o->id;
  bool position = false;
  bool present = false;
  Status status = OptionalMatrix3(
      r, object, where, "position_covariance", &position, &c.position);
  Eigen::Matrix3d m;
  const bool asymmetric = o->symmetry == SymmetryType::kAsymmetric;
  if (status.ok()) {
    status =
        OptionalMatrix3(r, object, where, "rotation_covariance", &present, &m);
    if (status.ok() && present && !asymmetric) {
      status = r.Fail(where.Member("rotation_covariance"),
                      "only an asymmetric object has one");
    }
    if (present) c.rotation = m;
  }
  if (status.ok()) {
    status = OptionalMatrix3(r, object, where, "axis_covariance", &present, &m);
    if (status.ok() && present && asymmetric) {
      status = r.Fail(where.Member("axis_covariance"),
                      "only a symmetric object has one");
    }
    if (present) c.axis = m;
  }
  if (!status.ok()) return status;
  const JsonTree::Index variances = r.Find(object, "angle_variances");
  if (variances != 0) {
    const JsonPath path = where.Member("angle_variances");
    status = r.Array(variances, path);
    if (status.ok() && o->symmetry != SymmetryType::kDiscrete) {
      return r.Fail(path, "only a discrete object has them");
    }
    if (status.ok() && r.tree().node(variances).size != o->angles.size()) {
      return r.Fail(path,
                    "expected " + std::to_string(o->angles.size()) +
                        " entries, one per angle");
    }
    int k = 0;
    for (JsonTree::Index e = status.ok() ? r.tree().node(variances).first : 0;
         e != 0;
         e = r.tree().node(e).next, ++k) {
      if (r.Type(e) == io_internal::JsonType::kNull) {
        c.angle_variances.push_back(std::nullopt);
        continue;
      }
      double v = 0.0;
      status = r.Number(e, path.Element(k), &v);
      if (status.ok() && v < 0.0) {
        status = r.Fail(path.Element(k), "expected a variance (>= 0)");
      }
      if (!status.ok()) return status;
      c.angle_variances.push_back(v);
    }
    if (!status.ok()) return status;
  }
  const JsonTree::Index source = r.Find(object, "covariance_source");
  if (source != 0) {
    std::string_view name;
    status = r.String(source, where.Member("covariance_source"), &name);
    if (!status.ok()) return status;
    if (!CovarianceSourceFromName(name, &c.source)) {
      return r.Fail(where.Member("covariance_source"),
                    "expected \"solve\", \"prior\" or \"keyframe_graph\", "
                    "got " +
                        QuoteForMessage(name));
    }
  }
  const bool any = c.rotation || c.axis || variances != 0 || source != 0;
  if (any && !position) {
    return r.Fail(where, "a covariance without \"position_covariance\"");
  }
  if (position) o->covariance = c;
  return Status::Ok();
}

// "upgrade": {keyframe, evidence, order, angle} (optional).
Status ReadUpgrade(const JsonTreeReader& r,
                   JsonTree::Index object,
                   const JsonPath& where,
                   MapObjectEstimate* o) {
  const JsonTree::Index upgrade = r.Find(object, "upgrade");
  if (upgrade == 0) return Status::Ok();
  const JsonPath path = where.Member("upgrade");
  Status status = r.Object(upgrade, path);
  if (!status.ok()) return status;
  if (o->symmetry == SymmetryType::kAsymmetric) {
    return r.Fail(path, "only a symmetric object has one");
  }
  MapObjectEstimate::Upgrade u;
  JsonTree::Index member = 0;
  int64_t keyframe = 0;
  status = r.Require(upgrade, path, "keyframe", "", &member);
  if (status.ok()) {
    status = r.Integer(member, path.Member("keyframe"), &keyframe);
  }
  if (status.ok()) status = r.Require(upgrade, path, "evidence", "", &member);
  if (status.ok()) status = r.Int(member, path.Member("evidence"), &u.evidence);
  if (status.ok()) status = r.Require(upgrade, path, "order", "", &member);
  if (status.ok()) status = r.Int(member, path.Member("order"), &u.order);
  if (status.ok()) status = r.Require(upgrade, path, "angle", "", &member);
  if (status.ok()) status = r.Number(member, path.Member("angle"), &u.angle);
  if (!status.ok()) return status;
  u.keyframe = keyframe;
  o->upgrade = u;
  return Status::Ok();
}

}  // namespace

void WriteObjectRecord(const MapObjectEstimate& object, JsonWriter* json) {
  WriteObjectRecordImpl(object, json);
}

Status ReadObjectRecord(const JsonTreeReader& r,
                        JsonTree::Index e,
                        const JsonPath& where,
                        MapObjectEstimate* result) {
  MapObjectEstimate o;
  Status status =
      ObjectIdentity(r, e, where, &o.id, &o.class_name, &o.symmetry);
  JsonTree::Index member = 0;
  if (status.ok()) status = r.Require(e, where, "t", "", &member);
  if (status.ok())
    status = r.Numbers(member, where.Member("t"), 3, o.t_wo.data());
  if (status.ok()) status = r.Require(e, where, "observations", "", &member);
  if (status.ok()) {
    status = r.Int(member, where.Member("observations"), &o.observations);
  }
  if (status.ok() && o.observations < 0) {
    status = r.Fail(where.Member("observations"), "expected a count >= 0");
  }
  if (status.ok() && o.class_name.empty()) {
    status = r.Fail(where.Member("class"), "expected a class name");
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
  const size_t poses =
      o.symmetry == SymmetryType::kDiscrete ? o.angles.size() : 1;
  if (status.ok() && o.poses.size() != poses) {
    status = r.Fail(
        where.Member("poses"),
        "expected " + std::to_string(poses) +
            (o.symmetry == SymmetryType::kDiscrete ? " poses, one per angle"
                                                   : " pose"));
  }
  if (status.ok()) status = AngleEvidence(r, e, where, &o);
  if (status.ok()) o.angle_probabilities = AngleProbabilities(o.angle_evidence);
  if (status.ok()) status = ReadCovariance(r, e, where, &o);
  if (status.ok()) status = ReadUpgrade(r, e, where, &o);
  if (!status.ok()) return status;
  if (o.symmetry != SymmetryType::kAsymmetric) {
    o.axis_o = (o.poses.front().q.conjugate() * o.axis_w).normalized();
  }
  *result = std::move(o);
  return Status::Ok();
}

}  // namespace io_internal
}  // namespace symba
