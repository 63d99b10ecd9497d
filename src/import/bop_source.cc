#include "import/bop_source.h"

#include <algorithm>
#include <utility>

namespace symba::import_internal {

Status MakeBopSource(const std::optional<int>& scene,
                     const std::optional<int>& row_scene,
                     const std::vector<int>& obj_ids,
                     const std::map<int, std::string>& names,
                     std::optional<BopSource>* source) {
  source->reset();
  const std::optional<int> scene_id = scene ? scene : row_scene;
  if (!scene_id) return Status::Ok();
  BopSource result;
  result.scene_id = *scene_id;
  for (int obj_id : obj_ids) {
    const std::string& name = names.at(obj_id);
    const auto [it, inserted] = result.obj_ids.emplace(name, obj_id);
    if (!inserted && it->second != obj_id) {
      return Status::Error(
          "class names: obj_ids " +
          std::to_string(std::min(it->second, obj_id)) + " and " +
          std::to_string(std::max(it->second, obj_id)) + " are both named \"" +
          name + "\"; a class maps to one BOP obj_id");
    }
  }
  *source = std::move(result);
  return Status::Ok();
}

}  // namespace symba::import_internal
