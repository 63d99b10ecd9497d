// Status: how library functions report a failure to the caller.
//
// symba's library code never prints and never exits; a function that can fail
// on user data (files, options, detections) returns a Status whose message
// says what is wrong, and the command-line tools print it. Programmer errors
// (violated preconditions inside the library) are checked with SYMBA_CHECK
// (symba/common/check.h), which prints the failed condition and aborts.
#ifndef SYMBA_COMMON_STATUS_H_
#define SYMBA_COMMON_STATUS_H_

#include <string>
#include <utility>

namespace symba {

class [[nodiscard]] Status {
 public:
  // A success.
  Status() = default;

  static Status Ok() { return Status(); }
  static Status Error(std::string message) {
    return Status(std::move(message));
  }

  bool ok() const { return !failed_; }
  const std::string& message() const { return message_; }

 private:
  explicit Status(std::string message)
      : failed_(true), message_(std::move(message)) {}

  bool failed_ = false;
  std::string message_;
};

}  // namespace symba

#endif  // SYMBA_COMMON_STATUS_H_
