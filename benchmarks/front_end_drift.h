// A drifting front end made from a real one, for symba-real-bench
// (--drift-yaw, --drift-scale): each keyframe step of the front end, the
// relative motion T_prev,cur = T_wc(prev)^-1 T_wc(cur) between consecutive
// keyframes (in the previous keyframe's camera frame), has its translation
// scaled and is then turned about the camera's y axis in proportion to the
// step's length; the drifted keyframes are chained again from the first:
//
//   step'  = (Rot(y, yaw_per_metre |t|), 0) * (R, scale t)
//   T'(0)  = T(0),   T'(k) = T'(k-1) * step'(k)
//
// with (R, t) the original step and |t| its original length. A frame
// between two keyframes keeps its motion relative to the keyframe before
// it, so the drifted front end has every frame of the original.
#ifndef SYMBA_BENCHMARKS_FRONT_END_DRIFT_H_
#define SYMBA_BENCHMARKS_FRONT_END_DRIFT_H_

#include <vector>

#include "symba/geometry/rigid3.h"

namespace symba::bench {

struct FrontEndDrift {
  double yaw_per_metre = 0.0;  // rad per metre of the original step
  double scale = 1.0;          // of every step's translation
  // No drift: the front end as it is.
  bool IsNone() const { return yaw_per_metre == 0.0 && scale == 1.0; }
};

// The front end `T_wc` (one pose per frame, a keyframe every `stride`
// frames from frame 0; stride >= 1) with `drift` applied to its keyframe steps as above.
std::vector<Rigid3d> DriftFrontEnd(const std::vector<Rigid3d>& T_wc,
                                   int stride,
                                   const FrontEndDrift& drift);

}  // namespace symba::bench

#endif  // SYMBA_BENCHMARKS_FRONT_END_DRIFT_H_
