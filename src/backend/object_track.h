// Whether a tentative object's detections are the track of one static
// thing (docs/backend.md "Real detectors", 1). A detector that has lost
// the object can keep reporting it: on YCB-Video 0004 DOPE puts the
// cracker box 0.3-1 m off for half the sequence, at a place that wanders
// by 0.05-0.5 m from one keyframe to the next. Such detections can each
// lie within the position gate of the previous one's object (the gate is
// as wide as the class's persistent errors and the front end's stated
// motion noise allow), so the wandering detections would make an object,
// confirmed after confirm_keyframes keyframes like any other.
//
// A step of an object's track is the change |d| of its detection's
// position, where the front end alone puts it (detection_noise.h), between
// two keyframes j < k; its ratio is
//   r = |d| / sqrt(2 sigma_I^2 + G),
// with sigma_I the class's frame-to-frame noise and G the stated motion
// variance of keyframes j + 1 .. k at the later detection's distance
// (PlaceGrowth). For a static object r is of order one; how large exactly
// depends on how well the front end states its noise (a front end that
// states ten times its error makes r small), so it is learned: the class's
// reference R is the median r over the steps of its confirmed objects (the
// last noise_window), and a tentative object is static unless the median r
// of its own steps exceeds track_tolerance R. The medians ignore a few
// outliers on either side.
#ifndef SYMBA_SRC_BACKEND_OBJECT_TRACK_H_
#define SYMBA_SRC_BACKEND_OBJECT_TRACK_H_

#include <deque>
#include <memory>
#include <vector>

#include "backend/backend_state.h"

namespace symba::internal {

// r of one step (see above); the growth is 0 where keyframe `to` is not in
// `keyframes`.
double StepRatio(const TrackStep& step,
                 double sigma_increment,
                 const std::vector<std::unique_ptr<KeyframeState>>& keyframes);

// The median r over `steps` (ObjectState::track), 0 without steps.
double MedianStepRatio(
    const std::deque<TrackStep>& steps,
    double sigma_increment,
    const std::vector<std::unique_ptr<KeyframeState>>& keyframes);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_TRACK_H_
