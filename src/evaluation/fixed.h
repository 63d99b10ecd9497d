// Numbers in the evaluation's reports: a fixed count of decimals, "n/a" for
// a value that is not finite. Not installed.
#ifndef SYMBA_SRC_EVALUATION_FIXED_H_
#define SYMBA_SRC_EVALUATION_FIXED_H_

#include <cmath>
#include <cstdio>
#include <string>

namespace symba::internal {

inline std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

}  // namespace symba::internal

#endif  // SYMBA_SRC_EVALUATION_FIXED_H_
