#include "io/json_file.h"

#include <algorithm>
#include <cstddef>

namespace symba::internal {

Status ReadJson(const std::string& path, Json* json) {
  std::string text;
  Status status = ReadText(path, &text);
  if (!status.ok()) return status;
  try {
    *json = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.byte is the 1-based offset of the character where parsing stopped
    // (one past the end at the end of input); count the lines before it.
    const std::size_t before =
        std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    const int line = 1 + static_cast<int>(std::count(
                             text.begin(),
                             text.begin() + static_cast<std::ptrdiff_t>(before),
                             '\n'));
    // nlohmann's message: "[json.exception.parse_error.101] parse error at
    // line L, column C: REASON"; keep REASON.
    std::string reason = e.what();
    const std::size_t column = reason.find("column ");
    const std::size_t colon = column == std::string::npos
                                  ? std::string::npos
                                  : reason.find(": ", column);
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    return Status::Error(At(path, line) + ": invalid JSON: " + reason);
  }
  return Status::Ok();
}

Status ReadObjectsArray(const std::string& path,
                        Json* root,
                        const Json** objects) {
  Status status = ReadJson(path, root);
  if (!status.ok()) return status;
  if (!root->is_object()) {
    return Status::Error(path + ": expected a JSON object at the top level");
  }
  const JsonReader r(path);
  status = r.Member(*root, "top level", "objects", objects);
  if (!status.ok()) return status;
  if (!(*objects)->is_array()) return r.Error("objects", "expected an array");
  return Status::Ok();
}

}  // namespace symba::internal
