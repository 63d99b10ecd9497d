// libFuzzer target for the map file reader (scripts/fuzz 600
// map_file_fuzzer builds and runs it).
//
// For every input, taken as a map file:
//   1. ParseMapFile either fails with a message naming the file, leaving
//      the map it was given unchanged, or returns a map whose objects have
//      unique ids >= 0, one pose per angle and finite numbers, and noise
//      entries whose sigmas are positive and claim factors at least 1.
//   2. Whatever it accepted writes, reads back and writes again as the same
//      bytes (docs/map-format.md).
// A violated check aborts, which libFuzzer reports as a crash.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <string>

#include "symba/io/map_file.h"

namespace symba {
namespace {

void Check(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "map_file_fuzzer: check failed: %s\n", what);
    std::abort();
  }
}

void CheckAccepted(const SavedMap& map) {
  std::set<int> ids;
  for (const MapObjectEstimate& o : map.objects) {
    Check(o.id >= 0 && ids.insert(o.id).second, "unique ids >= 0");
    const size_t poses =
        o.symmetry == SymmetryType::kDiscrete ? o.angles.size() : 1;
    Check(o.poses.size() == poses && poses > 0, "one pose per angle");
    Check(o.t_wo.allFinite(), "finite position");
  }
  for (const SavedClassNoise& n : map.noise) {
    for (const std::optional<double>& sigma :
         {n.sigma_t, n.sigma_r, n.white_sigma_t, n.white_sigma_r}) {
      Check(!sigma || (std::isfinite(*sigma) && *sigma > 0.0),
            "positive finite sigmas");
    }
    for (const std::optional<double>& factor :
         {n.claim_factor_t, n.claim_factor_r}) {
      Check(!factor || (std::isfinite(*factor) && *factor >= 1.0),
            "claim factors at least 1");
    }
  }
}

}  // namespace
}  // namespace symba

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using symba::Check;
  const std::string text(reinterpret_cast<const char*>(data), size);
  symba::SavedMap map;
  map.noise = {{"sentinel", 1.0, std::nullopt}};
  const symba::Status status = symba::ParseMapFile(text, "fuzz.json", &map);
  if (!status.ok()) {
    Check(status.message().rfind("fuzz.json", 0) == 0, "message names file");
    Check(map.objects.empty() && map.noise.size() == 1 &&
              map.noise[0].class_name == "sentinel",
          "a refused file leaves the map unchanged");
    return 0;
  }
  symba::CheckAccepted(map);
  const std::string written = symba::FormatMapFile(map);
  symba::SavedMap again;
  Check(symba::ParseMapFile(written, "fuzz.json", &again).ok(),
        "what was written reads back");
  Check(symba::FormatMapFile(again) == written, "byte-identical rewrite");
  return 0;
}
