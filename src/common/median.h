// The median of a set of values, and the medians of the chi distributions
// that turn a median error into a sigma: |e| of isotropic Gaussian noise of
// sigma per axis has median kChi3Median sigma in 3 dimensions and
// kChi2Median sigma in 2.
#ifndef SYMBA_SRC_COMMON_MEDIAN_H_
#define SYMBA_SRC_COMMON_MEDIAN_H_

#include <algorithm>
#include <vector>

namespace symba::internal {

inline constexpr double kChi3Median = 1.5381722;
inline constexpr double kChi2Median = 1.1774100;  // sqrt(2 ln 2)
inline constexpr double kChi1Median = 0.6744898;  // of |x|, x ~ N(0, 1)

// The median of `values` (the mean of the middle two for an even count);
// reorders them. `values` must not be empty.
inline double MedianInPlace(std::vector<double>* values) {
  const size_t middle = values->size() / 2;
  std::nth_element(values->begin(), values->begin() + middle, values->end());
  double median = (*values)[middle];
  if (values->size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(values->begin(),
                                               values->begin() + middle));
  }
  return median;
}

}  // namespace symba::internal

#endif  // SYMBA_SRC_COMMON_MEDIAN_H_
