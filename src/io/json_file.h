// Internal to the readers of symba's JSON files (objects.json,
// gt_objects.json): parsing a whole file with "FILE:LINE: invalid JSON"
// errors, and reading members with "FILE: where: reason" errors. Not
// installed.
#ifndef SYMBA_SRC_IO_JSON_FILE_H_
#define SYMBA_SRC_IO_JSON_FILE_H_

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "io/text_file.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba::internal {

using Json = nlohmann::json;

// Quaternions and axes whose norm is within this of 1 are normalised; others
// are errors (as in the log format).
inline constexpr double kUnitTolerance = 1e-3;

// Normalises `q` if its norm is within kUnitTolerance of 1.
inline bool NormaliseQuaternion(Eigen::Quaterniond* q) {
  const double norm = q->norm();
  if (!(std::abs(norm - 1.0) <= kUnitTolerance)) return false;
  q->normalize();
  return true;
}

// Parses the whole file `path` into *json; a syntax error reads
// "PATH:LINE: invalid JSON: REASON".
Status ReadJson(const std::string& path, Json* json);

// Reads JSON members with "FILE: where: reason" errors.
class JsonReader {
 public:
  explicit JsonReader(std::string path) : path_(std::move(path)) {}

  Status Error(const std::string& where, const std::string& reason) const {
    return Status::Error(path_ + ": " + where + ": " + reason);
  }

  // `object[key]`, which must exist.
  Status Member(const Json& object,
                const std::string& where,
                const char* key,
                const Json** member) const {
    const auto it = object.find(key);
    if (it == object.end()) {
      return Status::Error(path_ + ": " + where + ": missing " + Quoted(key));
    }
    *member = &*it;
    return Status::Ok();
  }

  Status Object(const Json& json, const std::string& where) const {
    if (!json.is_object()) return Error(where, "expected a JSON object");
    return Status::Ok();
  }

  Status Int(const Json& object,
             const std::string& where,
             const char* key,
             int* value) const {
    const Json* member = nullptr;
    Status status = Member(object, where, key, &member);
    if (!status.ok()) return status;
    if (!member->is_number_integer() ||
        member->get<int64_t>() < std::numeric_limits<int>::min() ||
        (member->is_number_unsigned()
             ? member->get<uint64_t>() >
                   static_cast<uint64_t>(std::numeric_limits<int>::max())
             : member->get<int64_t>() > std::numeric_limits<int>::max())) {
      return Error(Sub(where, key), "expected an integer");
    }
    *value = member->get<int>();
    return Status::Ok();
  }

  Status String(const Json& object,
                const std::string& where,
                const char* key,
                std::string* value) const {
    const Json* member = nullptr;
    Status status = Member(object, where, key, &member);
    if (!status.ok()) return status;
    if (!member->is_string())
      return Error(Sub(where, key), "expected a string");
    *value = member->get<std::string>();
    return Status::Ok();
  }

  Status Symmetry(const Json& object,
                  const std::string& where,
                  SymmetryType* type) const {
    std::string name;
    Status status = String(object, where, "symmetry", &name);
    if (!status.ok()) return status;
    const std::optional<SymmetryType> parsed = ParseSymmetryType(name);
    if (!parsed) {
      return Error(Sub(where, "symmetry"),
                   Quoted(name) + " is not asymmetric, discrete or continuous");
    }
    *type = *parsed;
    return Status::Ok();
  }

  // What every entry of an "objects" array starts with: a JSON object with
  // an integer "id", a string "class" and a "symmetry".
  Status ObjectIdentity(const Json& json,
                        const std::string& where,
                        int* id,
                        std::string* class_name,
                        SymmetryType* symmetry) const {
    Status status = Object(json, where);
    if (status.ok()) status = Int(json, where, "id", id);
    if (status.ok()) status = String(json, where, "class", class_name);
    if (status.ok()) status = Symmetry(json, where, symmetry);
    return status;
  }

  // An array of exactly `n` finite numbers.
  Status Numbers(const Json& json,
                 const std::string& where,
                 int n,
                 double* values) const {
    if (!json.is_array() || static_cast<int>(json.size()) != n) {
      return Error(where,
                   "expected an array of " + std::to_string(n) + " numbers");
    }
    for (int i = 0; i < n; ++i) {
      if (!json[i].is_number() || !std::isfinite(json[i].get<double>())) {
        return Error(
            where,
            "expected an array of " + std::to_string(n) + " finite numbers");
      }
      values[i] = json[i].get<double>();
    }
    return Status::Ok();
  }

  Status Vector(const Json& object,
                const std::string& where,
                const char* key,
                Eigen::Vector3d* v) const {
    const Json* member = nullptr;
    Status status = Member(object, where, key, &member);
    if (!status.ok()) return status;
    double values[3];
    status = Numbers(*member, Sub(where, key), 3, values);
    if (!status.ok()) return status;
    *v = Eigen::Vector3d(values[0], values[1], values[2]);
    return Status::Ok();
  }

  // A unit 3-vector (normalised when within kUnitTolerance of unit length).
  Status UnitVector(const Json& object,
                    const std::string& where,
                    const char* key,
                    Eigen::Vector3d* v) const {
    Status status = Vector(object, where, key, v);
    if (!status.ok()) return status;
    if (!(std::abs(v->norm() - 1.0) <= kUnitTolerance)) {
      return Error(Sub(where, key), "norm " + Approx(v->norm()) + " is not 1");
    }
    v->normalize();
    return Status::Ok();
  }

  // {"t": [x, y, z], "q": [qx, qy, qz, qw]}.
  Status Pose(const Json& json, const std::string& where, Rigid3d* T) const {
    Status status = Object(json, where);
    if (!status.ok()) return status;
    status = Vector(json, where, "t", &T->t);
    if (!status.ok()) return status;
    const Json* q_json = nullptr;
    status = Member(json, where, "q", &q_json);
    if (!status.ok()) return status;
    double q[4];
    status = Numbers(*q_json, Sub(where, "q"), 4, q);
    if (!status.ok()) return status;
    T->q = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    if (!NormaliseQuaternion(&T->q)) {
      return Error(Sub(where, "q"),
                   "quaternion norm " + Approx(T->q.norm()) + " is not 1");
    }
    return Status::Ok();
  }

  static std::string Sub(const std::string& where, const char* key) {
    return where.empty() ? std::string(key) : where + "." + key;
  }
  static std::string Index(const std::string& where, std::size_t i) {
    return where + "[" + std::to_string(i) + "]";
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Reads `path` as a JSON object and finds its top-level "objects" array.
Status ReadObjectsArray(const std::string& path,
                        Json* root,
                        const Json** objects);

}  // namespace symba::internal

#endif  // SYMBA_SRC_IO_JSON_FILE_H_
