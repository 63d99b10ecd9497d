// BOP files give lengths in millimetres; symba works in metres. Not
// installed.
#ifndef SYMBA_SRC_EXPORT_BOP_UNITS_H_
#define SYMBA_SRC_EXPORT_BOP_UNITS_H_

namespace symba::internal {

inline constexpr double kMillimetresPerMetre = 1000.0;

}  // namespace symba::internal

#endif  // SYMBA_SRC_EXPORT_BOP_UNITS_H_
