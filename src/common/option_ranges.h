// The ranges the option tables use most (symba/common/option_field.h has the
// general ones). Not installed.
#ifndef SYMBA_SRC_COMMON_OPTION_RANGES_H_
#define SYMBA_SRC_COMMON_OPTION_RANGES_H_

#include "symba/common/option_table.h"
#include "symba/geometry/angle.h"

namespace symba {

inline OptionRange Positive() { return Above(0.0); }
inline OptionRange NonNegative() { return AtLeast(0.0); }
inline OptionRange Fraction() { return Between(0.0, 1.0); }
inline OptionRange AngleBelowPi() { return AboveBelow(0.0, kPi); }
inline OptionRange AngleBelowHalfPi() { return AboveBelow(0.0, kPi / 2); }

// translation_gate: positive, infinity disables the gate.
inline OptionRange PositiveOrInfinity() {
  OptionRange range = Positive();
  range.allow_infinity = true;
  return range;
}

}  // namespace symba

#endif  // SYMBA_SRC_COMMON_OPTION_RANGES_H_
