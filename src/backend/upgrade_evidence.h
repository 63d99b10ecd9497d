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
//     percent);
//   - both rotations recur: with n0 keyframes that saw the object unflipped
//     and n1 agreeing flips, m = min(n0, n1), n = n0 + n1, the odds
//       (1/3)^m (2/3)^(n-m) / (c^m (1-c)^(n-m))
//     of "a symmetric object, each of the two rotations at least a third
//     of the n" against "one rotation, the other a detector's confusion at
//     the rate c = upgrade_confusion_rate" reach upgrade_odds. A young
//     object made from one wrongly turned detection sees every later one as
//     a flip (m = 1), and so does an object the detector turns for a while;
//     neither is a symmetry;
//   - the class flips as a symmetric one does: its asymmetric objects'
//     keyframes with a flip whose own angle fits the order are at
//     least upgrade_min_fraction of all their keyframes (a ghost of a
//     textured can that flips as often as a symmetric one does not make the
//     can symmetric, nor does a drifting camera turn the rest by 30 degrees);
//     and
//   - their mean angle is a plausible symmetry: within
//     upgrade_angle_tolerance of 2 pi j / K for an order K in
//     2..max_upgrade_order (the prior's order only, with a discrete prior).
// Until then the flipped detection joins the object without an edge. When
// the flips instead say the object's own rotation was the confusion
// (FlipsOutvoteTheRotation: more flips than views, and a symmetry rejected
// with the same odds), the object turns to the flips' rotation
// (ObjectMap::Turn): a young object made from one turned detection gets
// the rotation the detector gives it from then on.
#ifndef SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_
#define SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_

#include <map>
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

// The natural log of the odds above: `unflipped` keyframes saw the object
// at its rotation, `flipped` at the flips' one; `confusion_rate` in
// (0, 1/3) (the option allows (0, 0.3)).
double TwoRotationsLogOdds(int unflipped, int flipped, double confusion_rate);

// Whether the object's own rotation is the detector's confusion: odds of
// `odds` for "the flips' rotation is the object's, its own a confusion at
// `confusion_rate`" both against "its own rotation, the flips confusions"
// ((n1 - n0) ln((1 - c) / c)) and against a symmetric object (the negated
// TwoRotationsLogOdds). A symmetric object's views never pass: both of its
// rotations recur.
bool FlipsOutvoteTheRotation(int unflipped,
                             int flipped,
                             double confusion_rate,
                             double odds);

// Keyframes in which the asymmetric objects of one class were detected,
// and those of them with a flip whose angle fits order K (2 pi j / K; its
// first flip in the keyframe), per K: a flip by pi counts for K = 2 and 4.
struct ClassFlipCounts {
  int keyframes = 0;
  std::map<int, int> flip_keyframes_by_order;

  // Whether the flips of order `order` are at least `fraction` of the
  // keyframes.
  bool FlipsAsSymmetric(int order, double fraction) const;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_UPGRADE_EVIDENCE_H_
