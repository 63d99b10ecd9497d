// Feeding keyframes to a Backend as a SLAM system does: each keyframe, then
// a window solve. Shared by the backend tests; failures are gtest failures.
#ifndef SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_
#define SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_

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
inline void ReplayWindowed(const std::vector<KeyframeInput>& keyframes,
                           const BackendOptions& options,
                           const std::optional<PinholeIntrinsics>& intrinsics,
                           std::unique_ptr<Backend>* backend) {
  Status status = Backend::Create(options, intrinsics, {}, backend);
  ASSERT_TRUE(status.ok()) << status.message();
  for (const KeyframeInput& keyframe : keyframes) {
    status = (*backend)->AddKeyframe(keyframe);
    ASSERT_TRUE(status.ok()) << status.message();
    status = (*backend)->OptimizeWindow();
    ASSERT_TRUE(status.ok()) << status.message();
  }
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_BACKEND_REPLAY_H_
