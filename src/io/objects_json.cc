#include "symba/io/objects_json.h"

#include <set>
#include <string>
#include <utility>

#include "io/json_tree_reader.h"
#include "io/json_writer.h"
#include "io/noise_json.h"
#include "io/object_record.h"

namespace symba {

using io_internal::JsonPath;
using io_internal::JsonTree;
using io_internal::JsonTreeReader;
using io_internal::JsonWriter;
using io_internal::ObjectsArray;
using io_internal::ReadJsonFile;

std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects) {
  return FormatObjectsJson(objects, {}, std::nullopt);
}

std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects,
                              const std::vector<ClassNoiseEstimate>& noise,
                              const std::optional<MotionNoiseReport>& motion) {
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject().Key("objects").BeginArray();
  for (const MapObjectEstimate& o : objects) {
    io_internal::WriteObjectRecord(o, &json);
  }
  json.EndArray();
  if (motion) {
    io_internal::WriteNoise(noise, &json);
    io_internal::WriteMotionNoise(*motion, &json);
  }
  json.EndObject();
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
    status = io_internal::ReadObjectRecord(r, e, where, &o);
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) {
      return r.Fail(where.Member("id"), "duplicate id " + std::to_string(o.id));
    }
    result->push_back(std::move(o));
  }
  return Status::Ok();
}

}  // namespace symba
