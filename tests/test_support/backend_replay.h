// Feeding keyframes to a Backend as a SLAM system does: each keyframe, then
// a window solve; and the keyframes' error against the truth. Shared by the
// backend tests; failures are gtest failures.
#ifndef SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_
#define SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/backend/backend.h"

namespace symba::testing {

// Creates `backend` and adds every keyframe with a window solve after each.
// Use with ASSERT_NO_FATAL_FAILURE.
inline void ReplayWindowed(
    const std::vector<KeyframeInput>& keyframes,
    const BackendOptions& options,
    const std::optional<PinholeIntrinsics>& intrinsics,
    std::unique_ptr<Backend>* backend,
    const std::map<std::string, ClassPrior>& class_priors = {}) {
  Status status = Backend::Create(options, intrinsics, class_priors, backend);
  ASSERT_TRUE(status.ok()) << status.message();
  for (const KeyframeInput& keyframe : keyframes) {
    status = (*backend)->AddKeyframe(keyframe);
    ASSERT_TRUE(status.ok()) << status.message();
    status = (*backend)->OptimizeWindow();
    ASSERT_TRUE(status.ok()) << status.message();
  }
}

// The keyframe position RMSE (m) of the backend's estimates against
// `truth` (one pose per keyframe, in order; no alignment).
inline double KeyframePositionRmse(const Backend& backend,
                                   const std::vector<Rigid3d>& truth) {
  const std::vector<KeyframeEstimate> estimates = backend.Keyframes();
  double sum = 0.0;
  for (size_t k = 0; k < estimates.size(); ++k) {
    sum += (estimates[k].T_wc.t - truth[k].t).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(estimates.size()));
}

// The same over the estimates whose keyframe id is at least `first`, each
// against truth[id] (ids that index the truth, as the simulator's do); 0
// without such estimates.
inline double KeyframePositionRmseFrom(
    const std::vector<KeyframeEstimate>& estimates,
    const std::vector<Rigid3d>& truth,
    int64_t first) {
  double sum = 0.0;
  size_t n = 0;
  for (const KeyframeEstimate& e : estimates) {
    if (e.id < first) continue;
    sum += (e.T_wc.t - truth[static_cast<size_t>(e.id)].t).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_
