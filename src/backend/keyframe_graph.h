// The keyframe graph a loop closure optimises (docs/loop-closure.md "The
// keyframe graph"): it outlives the window because it is made, when a loop
// closes, from what every keyframe keeps anyway (its estimated pose and the
// variance its camera motion states, KeyframeState) and the loop closures
// so far. Not installed.
//
//   vertices  every keyframe, at its current estimate T_wc; keyframe 0
//             holds the gauge
//   edges     consecutive keyframes k-1, k: their estimated relative pose
//             T_{k-1,k}, information diag(I3 / s_t^2, I3 / s_r^2) from the
//             keyframe's motion variance (kUnstatedMotionSigma_* where it
//             has no motion factor: the first of a front end's gap);
//             each loop closure: its T and sigmas
//
// The estimated relative poses carry what the window's solves made of the
// objects and points; the loop's error is spread along the chain in
// proportion to the motion variances.
#ifndef SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_
#define SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_

#include <vector>

#include "backend/factor_graph.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/pose_graph/optimize_pose_graph.h"

namespace symba::internal {

// A keyframe without a motion factor is linked to its predecessor this
// loosely (m, rad).
inline constexpr double kUnstatedMotionSigmaT = 1.0;
inline constexpr double kUnstatedMotionSigmaR = 1.0;

// A relative pose between two keyframes (indices): `later`'s pose in
// `earlier`'s frame.
struct LoopConstraint {
  int earlier = -1;
  int later = -1;
  Rigid3d T;
  double sigma_t = 0.0;  // m
  double sigma_r = 0.0;  // rad
};

// The graph above for `keyframes` (at least one) and `loops`.
PoseGraph MakeKeyframeGraph(const KeyframeList& keyframes,
                            const std::vector<LoopConstraint>& loops);

// Optimises that graph; on success (*corrected)[k] is keyframe k's
// optimised pose. On an error *corrected is untouched.
Status OptimizeKeyframeGraph(const KeyframeList& keyframes,
                             const std::vector<LoopConstraint>& loops,
                             std::vector<Rigid3d>* corrected,
                             PoseGraphSolveSummary* summary);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_
