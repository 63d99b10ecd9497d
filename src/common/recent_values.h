// The last `window` values added: a ring once full, in no particular order
// (what a median over a sliding window needs).
#ifndef SYMBA_SRC_COMMON_RECENT_VALUES_H_
#define SYMBA_SRC_COMMON_RECENT_VALUES_H_

#include <cstddef>
#include <vector>

namespace symba::internal {

template <typename T>
class RecentValues {
 public:
  explicit RecentValues(int window) : window_(window) {}
  void Add(const T& value) {
    if (static_cast<int>(values_.size()) < window_) {
      values_.push_back(value);
      return;
    }
    values_[next_] = value;
    next_ = (next_ + 1) % values_.size();
  }
  int size() const { return static_cast<int>(values_.size()); }
  const std::vector<T>& values() const { return values_; }

 private:
  int window_;
  std::vector<T> values_;
  std::size_t next_ = 0;  // the oldest value once full
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_COMMON_RECENT_VALUES_H_
