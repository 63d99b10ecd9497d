// A top-down (x-y) picture of one replay as a hand-written SVG: the true and
// the estimated keyframe trajectories, the ground-truth objects (hollow
// circles) and the map objects (filled diamonds), each with its symmetry
// drawn in the plane:
//   - a symmetry axis that is not vertical as a line through the object,
//     its half-length proportional to the axis' horizontal component;
//   - discrete angles (and the heading of asymmetric objects) as short ticks
//     along R_wo_i e_o, e_o the unit vector of the object frame
//     perpendicular to the axis closest to object x (object x itself when
//     asymmetric);
//   - continuous objects with a dashed ring;
// and the loop closures, each a line between its two keyframes' estimated
// positions with a ring at the keyframe that closed it.
// A legend and a scale bar; the world's +y points up in the picture.
#ifndef SYMBA_BENCHMARKS_TOP_DOWN_SVG_H_
#define SYMBA_BENCHMARKS_TOP_DOWN_SVG_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/estimates.h"
#include "symba/backend/loop_closure.h"
#include "symba/evaluation/evaluate.h"

namespace symba::bench {

// A loop closure as drawn: the estimated positions (world frame, m) of the
// keyframe that closed it (LoopClosureReport::keyframe) and of the other
// keyframe it was related to.
struct LoopClosureLine {
  Eigen::Vector3d closing = Eigen::Vector3d::Zero();
  Eigen::Vector3d other = Eigen::Vector3d::Zero();
};

// The closed loop closures of `loops` (Backend::LoopClosures()), their
// keyframes looked up by id in `keyframes`; a closure still waiting for a
// solve or left out (its message says why), or one whose keyframes are not
// both in `keyframes`, is not drawn.
std::vector<LoopClosureLine> LoopClosureLines(
    const std::vector<KeyframeEstimate>& keyframes,
    const std::vector<LoopClosureReport>& loops);

// `title` is the first line of the picture; `color` (an SVG colour) is the
// estimate's. A non-empty `front_end` (e.g. a front end's keyframe poses in
// the ground truth's world) is drawn as a grey dotted line. Each of `loops`
// is an orange line with a ring (SVG class "loop-closure"), counted in the
// legend when there are any.
std::string TopDownSvg(const GroundTruth& gt,
                       const ReplayOutputs& result,
                       const std::string& title,
                       const std::string& color,
                       const std::vector<TrajectoryPose>& front_end = {},
                       const std::vector<LoopClosureLine>& loops = {});

}  // namespace symba::bench

#endif  // SYMBA_BENCHMARKS_TOP_DOWN_SVG_H_
