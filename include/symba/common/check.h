// SYMBA_CHECK: the check for programmer errors. symba has three tiers of
// errors: compile time (static_assert), programmer errors (SYMBA_CHECK) and
// user data (a Status, symba/common/status.h).
//
//   SYMBA_CHECK(index < size) << "index " << index << " of " << size;
//
// If the condition is false, prints "file:line: Check failed: <condition>"
// followed by the streamed message to stderr and aborts. If it is true,
// nothing after the condition is evaluated. Use it only for violated
// preconditions inside the library, never for user data (files, flags,
// options, detections), which is reported with a Status.
#ifndef SYMBA_COMMON_CHECK_H_
#define SYMBA_COMMON_CHECK_H_

#include <cstdlib>
#include <iostream>
#include <sstream>

namespace symba {
namespace internal {

// Collects the message of a failed check; its destructor prints and aborts.
class CheckFailure {
 public:
  CheckFailure(const char* file, int line, const char* condition) {
    stream_ << file << ":" << line << ": Check failed: " << condition << " ";
  }
  CheckFailure(const CheckFailure&) = delete;
  CheckFailure& operator=(const CheckFailure&) = delete;
  [[noreturn]] ~CheckFailure() {
    std::cerr << stream_.str() << std::endl;
    std::abort();
  }

  std::ostream& stream() { return stream_; }

 private:
  std::ostringstream stream_;
};

// Turns the streamed expression into void so that both branches of the
// conditional in SYMBA_CHECK have the same type.
struct CheckVoidify {
  void operator&(std::ostream&) {}
};

}  // namespace internal
}  // namespace symba

#define SYMBA_CHECK(condition)                                              \
  (condition)                                                               \
      ? (void)0                                                             \
      : ::symba::internal::CheckVoidify() &                                 \
            ::symba::internal::CheckFailure(__FILE__, __LINE__, #condition) \
                .stream()

#endif  // SYMBA_COMMON_CHECK_H_
