// The map file (docs/map-format.md): a SavedMap as versioned JSON, its
// writer and its strict reader.
//
//   {"format": "symba-map", "version": 1,
//    "objects": [ one record per object, as in objects.json ],
//    "noise": [{"class": NAME, "sigma_t"?: m, "sigma_r"?: rad,
//               "white_sigma_t"?: m, "white_sigma_r"?: rad,
//               "claim_factor_t"?: >= 1, "claim_factor_r"?: >= 1}]}
//
// Writing what was read gives the same bytes: numbers are written as the
// shortest text that reads back as the same double (covariances rounded to
// 6 significant digits first), and reading keeps them as they are.
#ifndef SYMBA_IO_MAP_FILE_H_
#define SYMBA_IO_MAP_FILE_H_

#include <string>

#include "symba/backend/saved_map.h"
#include "symba/common/status.h"

namespace symba {

inline constexpr int kMapFormatVersion = 1;

std::string FormatMapFile(const SavedMap& map);

// Parses a map file's text; `name` stands for the file in messages
// ("NAME:LINE: invalid JSON ..." or "NAME: where: reason"). On error *map
// is left unchanged.
Status ParseMapFile(const std::string& text,
                    const std::string& name,
                    SavedMap* map);
Status ReadMapFile(const std::string& path, SavedMap* map);

}  // namespace symba

#endif  // SYMBA_IO_MAP_FILE_H_
