// When a flip may make an asymmetric map object symmetric (symba only;
// docs/backend.md "Real detectors").
//
// A flip is a detection at the object's position whose rotation differs
// from the object's by more than gate_rotation, by a twist of angle
// |theta| about an axis a_o (the class prior's, or the relative rotation's
// own). One flip is no evidence: real detectors return a wrong rotation
// now and then, and a single noisy one would upgrade a box to a 3-, 5- or
// 10-fold "symmetric" object. The object is upgraded to discrete when
//   - at least `upgrade_evidence` flips from different keyframes agree:
//     axes within gate_axis (sign-free), angles within gate_angle, and they
//     are at least upgrade_min_fraction of the keyframes that detected the
//     object (a real symmetric object seen by a single-pose detector flips
//     in about half of them; a detector's occasional confusion in a few
//     percent); and
//   - their mean angle is a plausible symmetry: within
//     upgrade_angle_tolerance of 2 pi j / K for an order K in
//     2..max_upgrade_order (the prior's order only, with a discrete prior).
// Until then the flipped detection joins the object without an edge.
#ifndef SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_
#define SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_

#include <vector>

#include "backend/backend_state.h"

namespace symba::internal {

// The smallest order K in [2, max_order] such that |angle| is within
// `tolerance` of 2 pi j / K for some j in 1..K-1, or 0 if there is none.
// `angle` in radians, any value (it is wrapped).
int PlausibleOrder(double angle, int max_order, double tolerance);

// True if `angle` is within `tolerance` of 2 pi j / order, j in 1..order-1.
bool FitsOrder(double angle, int order, double tolerance);

// The flips (one per keyframe: the first of each) that agree with `flip`,
// itself included if it is in `flips`, and their mean |angle| (rad).
struct FlipConsensus {
  int count = 0;
  double mean_angle = 0.0;
};
FlipConsensus ConsistentFlips(const std::vector<FlipEvidence>& flips,
                              const FlipEvidence& flip,
                              double gate_axis,
                              double gate_angle);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_
