// Internal to symba import bop: the log header's "bop" key (BopSource,
// symba/io/log_format.h), which records the imported scene and the BOP
// obj_id of every class so that `symba replay --bop-out` can write the
// refined poses back with the detector's ids.
#ifndef SYMBA_SRC_IMPORT_BOP_SOURCE_H_
#define SYMBA_SRC_IMPORT_BOP_SOURCE_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "symba/common/status.h"
#include "symba/io/log_format.h"

namespace symba::import_internal {

// The scene is `scene` when given, else `row_scene` (the rows' one scene);
// without either (no option, no row) there is no source. `obj_ids` are the
// object ids of the rows and of models_info.json, `names` what each is
// called in the log. Two ids of one name are an error ("class names: obj_ids
// 1 and 2 are both named "box"; ..."): a class maps to one BOP obj_id.
Status MakeBopSource(const std::optional<int>& scene,
                     const std::optional<int>& row_scene,
                     const std::vector<int>& obj_ids,
                     const std::map<int, std::string>& names,
                     std::optional<BopSource>* source);

}  // namespace symba::import_internal

#endif  // SYMBA_SRC_IMPORT_BOP_SOURCE_H_
