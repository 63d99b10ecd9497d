// Input checks of one keyframe, everything the backend verifies before it
// adds anything (docs/backend.md "Input checks"). Not installed.
#ifndef SYMBA_SRC_BACKEND_KEYFRAME_VALIDATION_H_
#define SYMBA_SRC_BACKEND_KEYFRAME_VALIDATION_H_

#include <optional>
#include <string>

#include "symba/backend/keyframe_input.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba::internal {

// Quaternions in the input may be this far from unit norm (as the log
// format); they are normalised.
inline constexpr double kUnitTolerance = 1e-3;

// The last keyframe the backend holds, for the ordering checks.
struct PreviousKeyframe {
  int64_t id = 0;
  double timestamp = 0.0;
};

// A finite pose whose quaternion is unit within kUnitTolerance.
Status CheckPose(const Rigid3d& T, const std::string& what);
// Absent, or in [kMinNoiseSigma, kMaxNoiseSigma].
Status CheckSigma(const std::optional<double>& sigma, const std::string& what);

// Checks `input` against the previous keyframe (none for the first): ids
// increase, time does not go back, the first keyframe has T_wc, later ones
// T_wc or odometry, every pose, sigma, weight and depth is valid, and points
// come with intrinsics. Messages start with "keyframe ID".
Status ValidateKeyframe(const KeyframeInput& input,
                        const std::optional<PreviousKeyframe>& previous,
                        bool has_intrinsics);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_KEYFRAME_VALIDATION_H_
