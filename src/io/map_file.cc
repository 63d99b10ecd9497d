#include "symba/io/map_file.h"

#include <set>
#include <string>
#include <string_view>
#include <utility>

#include "io/json_tree_reader.h"
#include "io/json_writer.h"
#include "io/object_record.h"
#include "io/text_file.h"

namespace symba {
namespace {

using io_internal::JsonPath;
using io_internal::JsonTree;
using io_internal::JsonTreeReader;
using io_internal::JsonType;
using io_internal::JsonWriter;

constexpr const char* kFormatName = "symba-map";

Status Header(const JsonTreeReader& r, const JsonPath& root) {
  Status status = r.Object(0, root);
  JsonTree::Index member = 0;
  if (status.ok()) status = r.Require(0, root, "format", "", &member);
  if (!status.ok()) return status;
  if (r.Type(member) != JsonType::kString ||
      r.tree().String(member) != kFormatName) {
    return r.Fail(root.Member("format"),
                  std::string("expected \"") + kFormatName + "\", got " +
                      r.Describe(member));
  }
  status = r.Require(0, root, "version", "", &member);
  int64_t version = 0;
  if (status.ok()) status = r.Integer(member, root.Member("version"), &version);
  if (status.ok() && version != kMapFormatVersion) {
    status = r.Fail(root.Member("version"),
                    "version " + r.Describe(member) +
                        " is not supported (this reader reads version " +
                        std::to_string(kMapFormatVersion) + ")");
  }
  return status;
}

Status Objects(const JsonTreeReader& r,
               const JsonPath& root,
               std::vector<MapObjectEstimate>* objects) {
  JsonTree::Index array = 0;
  const JsonPath path = root.Member("objects");
  Status status = r.Require(0, root, "objects", "", &array);
  if (status.ok()) status = r.Array(array, path);
  std::set<int> ids;
  int i = 0;
  for (JsonTree::Index e = status.ok() ? r.tree().node(array).first : 0; e != 0;
       e = r.tree().node(e).next, ++i) {
    const JsonPath where = path.Element(i);
    MapObjectEstimate o;
    status = io_internal::ReadObjectRecord(r, e, where, &o);
    if (status.ok() && (o.id < 0 || o.id >= kMaxMapObjectId)) {
      status = r.Fail(
          where.Member("id"),
          "expected an id in [0, " + std::to_string(kMaxMapObjectId) + ")");
    }
    if (status.ok() && !ids.insert(o.id).second) {
      status =
          r.Fail(where.Member("id"), "duplicate id " + std::to_string(o.id));
    }
    if (!status.ok()) return status;
    objects->push_back(std::move(o));
  }
  return status;
}

// An optional number: positive (a sigma), or at least 1 (a claim factor,
// which multiplies a declared sigma and never lowers it).
enum class AtLeast { kPositive, kOne };

Status OptionalNumber(const JsonTreeReader& r,
                      JsonTree::Index object,
                      const JsonPath& where,
                      const char* key,
                      AtLeast at_least,
                      std::optional<double>* value) {
  const JsonTree::Index member = r.Find(object, key);
  if (member == 0) return Status::Ok();
  double v = 0.0;
  Status status = at_least == AtLeast::kPositive
                      ? r.Positive(member, where.Member(key), &v)
                      : r.Number(member, where.Member(key), &v);
  if (status.ok() && at_least == AtLeast::kOne && !(v >= 1.0)) {
    status = r.Fail(where.Member(key),
                    "must be at least 1, got " + r.Describe(member));
  }
  if (status.ok()) *value = v;
  return status;
}

Status Noise(const JsonTreeReader& r,
             const JsonPath& root,
             std::vector<SavedClassNoise>* noise) {
  JsonTree::Index array = 0;
  const JsonPath path = root.Member("noise");
  Status status = r.Require(0, root, "noise", "", &array);
  if (status.ok()) status = r.Array(array, path);
  std::string previous;
  int i = 0;
  for (JsonTree::Index e = status.ok() ? r.tree().node(array).first : 0; e != 0;
       e = r.tree().node(e).next, ++i) {
    const JsonPath where = path.Element(i);
    SavedClassNoise entry;
    status = r.Object(e, where);
    JsonTree::Index member = 0;
    std::string_view name;
    if (status.ok()) status = r.Require(e, where, "class", "", &member);
    if (status.ok()) status = r.String(member, where.Member("class"), &name);
    if (status.ok() && i > 0 && !(previous < name)) {
      status = r.Fail(where.Member("class"),
                      "classes must be sorted by name, each once");
    }
    entry.class_name = std::string(name);
    const std::pair<const char*, std::optional<double>*> sigmas[] = {
        {"sigma_t", &entry.sigma_t},
        {"sigma_r", &entry.sigma_r},
        {"white_sigma_t", &entry.white_sigma_t},
        {"white_sigma_r", &entry.white_sigma_r}};
    for (const auto& [key, value] : sigmas) {
      if (status.ok()) {
        status = OptionalNumber(r, e, where, key, AtLeast::kPositive, value);
      }
    }
    const std::pair<const char*, std::optional<double>*> factors[] = {
        {"claim_factor_t", &entry.claim_factor_t},
        {"claim_factor_r", &entry.claim_factor_r}};
    for (const auto& [key, value] : factors) {
      if (status.ok()) {
        status = OptionalNumber(r, e, where, key, AtLeast::kOne, value);
      }
    }
    if (!status.ok()) return status;
    previous = entry.class_name;
    noise->push_back(std::move(entry));
  }
  return status;
}

}  // namespace

std::string FormatMapFile(const SavedMap& map) {
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("format", kFormatName)
      .Member("version", kMapFormatVersion);
  json.Key("objects").BeginArray();
  for (const MapObjectEstimate& o : map.objects) {
    io_internal::WriteObjectRecord(o, &json);
  }
  json.EndArray().Key("noise").BeginArray();
  for (const SavedClassNoise& n : map.noise) {
    json.BeginObject().Member("class", n.class_name);
    if (n.sigma_t) json.Member("sigma_t", *n.sigma_t);
    if (n.sigma_r) json.Member("sigma_r", *n.sigma_r);
    if (n.white_sigma_t) json.Member("white_sigma_t", *n.white_sigma_t);
    if (n.white_sigma_r) json.Member("white_sigma_r", *n.white_sigma_r);
    if (n.claim_factor_t) json.Member("claim_factor_t", *n.claim_factor_t);
    if (n.claim_factor_r) json.Member("claim_factor_r", *n.claim_factor_r);
    json.EndObject();
  }
  json.EndArray().EndObject();
  out.push_back('\n');
  return out;
}

Status ParseMapFile(const std::string& text,
                    const std::string& name,
                    SavedMap* map) {
  JsonTree tree;
  Status status = io_internal::ParseJsonText(text, name, &tree);
  if (!status.ok()) return status;
  const JsonTreeReader r(name, 0, tree);
  const JsonPath root;
  SavedMap result;
  status = Header(r, root);
  if (status.ok()) status = Objects(r, root, &result.objects);
  if (status.ok()) status = Noise(r, root, &result.noise);
  if (!status.ok()) return status;
  *map = std::move(result);
  return Status::Ok();
}

Status ReadMapFile(const std::string& path, SavedMap* map) {
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  return ParseMapFile(text, path, map);
}

}  // namespace symba
