// Whether a tentative object's detections are the track of one static
// thing (docs/backend.md "Real detectors", 1). A detector that has lost
// the object can keep reporting it: on YCB-Video 0004 DOPE puts the
// cracker box 0.3 to 1.1 m off for half the sequence, at a place that
// wanders by 0.1 to 0.5 m from one keyframe to the next. Such detections
// can each lie within the position gate of the previous ones' object (the
// gate is as wide as the class's persistent errors and the motion noise
// allow), so the wandering detections would make an object, confirmed
// after confirm_keyframes keyframes like any other.
//
// A step of an object's track (TrackStep) is the change |d| of its
// detection's position, where the front end alone puts it
// (detection_noise.h), between two keyframes j < k; its ratio is
//   r = |d| / sqrt(2 sigma_I^2 + G),
// with sigma_I the class's frame-to-frame noise and G the motion variance
// the camera factors apply to keyframes j + 1 .. k (the front end's stated
// noise times its group's factor, motion_claims.h) at the later
// detection's distance (PlaceGrowth). For a static object r is of order
// one; how large exactly depends on how well the front end states its
// noise (a front end that states ten times its error makes r small), so it
// is learned: the class's reference R is the median r over the steps of
// its confirmed objects (the last noise_window), and a tentative object is
// static unless the median r of its own steps exceeds track_tolerance R.
// Steps are kept as |d| and G, and every ratio is taken with the class's
// sigma_I at the time of the test. The medians ignore a few outliers on
// either side.
#ifndef SYMBA_SRC_BACKEND_OBJECT_TRACK_H_
#define SYMBA_SRC_BACKEND_OBJECT_TRACK_H_

#include <vector>

#include "backend/track_step.h"
#include "common/recent_values.h"

namespace symba::internal {

// r of one step (see above): infinite for a change without any spread.
double StepRatio(const TrackStep& step, double sigma_increment);

// The median r over `steps`, 0 without steps.
double MedianStepRatio(const std::vector<TrackStep>& steps,
                       double sigma_increment);

// The last `window` steps of a class's confirmed objects, for the
// reference R.
class TrackReference {
 public:
  explicit TrackReference(int window) : steps_(window) {}
  void Add(const TrackStep& step) { steps_.Add(step); }
  int size() const { return steps_.size(); }
  // The median r of the steps kept; 0 without steps.
  double Ratio(double sigma_increment) const;

 private:
  RecentValues<TrackStep> steps_;
  mutable std::vector<double> scratch_;  // the ratios, reused
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_TRACK_H_
