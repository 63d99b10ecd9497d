// How far each keyframe's pose can be trusted: its marginal covariance in
// the world frame (docs/backend.md "Covariances").
#ifndef SYMBA_BACKEND_KEYFRAME_COVARIANCE_H_
#define SYMBA_BACKEND_KEYFRAME_COVARIANCE_H_

#include "symba/backend/ids.h"
#include "symba/factors/pose_component.h"

namespace symba {

struct KeyframeCovariance {
  KeyframeId id = 0;
  // 6 x 6, [t_wc (world frame, m); w (rad)], w the world-frame rotation
  // vector of R_wc = Exp(w) R_wc_estimate; zero for the first keyframe,
  // which holds the gauge.
  Matrix6d covariance = Matrix6d::Zero();
};

}  // namespace symba

#endif  // SYMBA_BACKEND_KEYFRAME_COVARIANCE_H_
