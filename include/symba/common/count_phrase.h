// "1 map object", "2 map objects": a count and its noun, for the messages
// of the command-line tools and the Python reprs.
#ifndef SYMBA_COMMON_COUNT_PHRASE_H_
#define SYMBA_COMMON_COUNT_PHRASE_H_

#include <string>

namespace symba {

// The count and `noun`, with an "s" unless the count is one.
inline std::string CountPhrase(long long count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

}  // namespace symba

#endif  // SYMBA_COMMON_COUNT_PHRASE_H_
