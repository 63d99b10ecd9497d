// One pose hypothesis of a detected object: T_co (object in the camera frame)
// with an optional positive weight (a detector's confidence). A detection
// carries N of them (the paper uses N = 30).
#ifndef SYMBA_DETECTION_POSE_HYPOTHESIS_H_
#define SYMBA_DETECTION_POSE_HYPOTHESIS_H_

#include "symba/geometry/rigid3.h"

namespace symba {

struct PoseHypothesis {
  Rigid3d T_co;
  double weight = 1.0;  // positive; relative weights matter, not their sum
};

}  // namespace symba

#endif  // SYMBA_DETECTION_POSE_HYPOTHESIS_H_
