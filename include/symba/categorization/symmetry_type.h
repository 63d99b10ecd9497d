// The three symmetry types of the paper (Sec. III-A) and their names on disk.
//
//   kAsymmetric  all hypotheses agree on one pose: 6 DoF are observable.
//   kDiscrete    the hypotheses form a few compact groups that differ by
//                rotations about one axis: position, axis and one angle per
//                group are observable.
//   kContinuous  the hypotheses spread around one axis: only position and
//                axis are observable.
//
// The names ("asymmetric", "discrete", "continuous") are the ones the log
// format uses for class priors and for outputs (docs/categorization.md).
#ifndef SYMBA_CATEGORIZATION_SYMMETRY_TYPE_H_
#define SYMBA_CATEGORIZATION_SYMMETRY_TYPE_H_

#include <optional>
#include <string_view>

namespace symba {

enum class SymmetryType { kAsymmetric, kDiscrete, kContinuous };

// "asymmetric", "discrete" or "continuous".
inline const char* ToString(SymmetryType type) {
  switch (type) {
    case SymmetryType::kAsymmetric:
      return "asymmetric";
    case SymmetryType::kDiscrete:
      return "discrete";
    case SymmetryType::kContinuous:
      return "continuous";
  }
  return "unknown";
}

// The type named by `name` (exact, lower case), or nullopt.
inline std::optional<SymmetryType> ParseSymmetryType(std::string_view name) {
  if (name == "asymmetric") return SymmetryType::kAsymmetric;
  if (name == "discrete") return SymmetryType::kDiscrete;
  if (name == "continuous") return SymmetryType::kContinuous;
  return std::nullopt;
}

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_SYMMETRY_TYPE_H_
