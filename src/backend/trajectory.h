// The backend's keyframes and map points (docs/architecture.md): each new
// keyframe's initial pose (the previous optimised pose moved by the odometry
// or the front end's relative motion) and its pose as the front end alone
// chains it, its camera motion factor, and its point observations
// (reprojection and, with a depth, the point depth factor; a point is
// created from its first observation with a depth). It owns the keyframes
// and points; their factors go into the factor graph. Not installed.
#ifndef SYMBA_SRC_BACKEND_TRAJECTORY_H_
#define SYMBA_SRC_BACKEND_TRAJECTORY_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include "backend/backend_state.h"
#include "backend/detection_noise.h"
#include "backend/factor_graph.h"
#include "backend/motion_claims.h"
#include "symba/backend/backend.h"

namespace symba::internal {

// The motion factors a MotionNoiseReport's medians are over (the last).
inline constexpr int kMotionNoiseWindow = 500;

class Trajectory {
 public:
  // `graph` and `statistics` are the backend's; the graph is not used
  // before the first keyframe is added.
  Trajectory(const BackendOptions& options,
             const std::optional<PinholeIntrinsics>& intrinsics,
             FactorGraph* graph,
             BackendStatistics* statistics);

  const KeyframeList& keyframes() const { return keyframes_; }
  const PointList& points() const { return points_; }
  bool has_intrinsics() const { return intrinsics_.has_value(); }
  // The keyframe with this id, or null (ids are strictly increasing).
  const KeyframeState* Find(int64_t id) const;
  // The index of the keyframe with this id, or -1.
  int IndexOf(int64_t id) const;

  // Adds a validated keyframe with its camera motion factor and point
  // observations; returns its index. With `claims`, the motion factor's
  // stated sigmas are multiplied by their group's factor.
  int Add(const KeyframeInput& input, MotionClaims* claims);
  // The noise stated for the motion factors (MotionNoiseReport; the
  // backend adds the claims).
  MotionNoiseReport MotionNoise() const;

 private:
  Rigid3d InitialPose(const KeyframeInput& input) const;
  // Where the front end alone puts the keyframe (KeyframeState::T_wc_chain).
  Rigid3d ChainPose(const KeyframeInput& input) const;
  void AddCameraFactors(int k,
                        const KeyframeInput& input,
                        MotionClaims* claims);
  void AddPointObservations(int k, const KeyframeInput& input);

  const BackendOptions& options_;
  std::optional<PinholeIntrinsics> intrinsics_;
  FactorGraph* graph_;
  BackendStatistics* statistics_;
  std::unique_ptr<ceres::LossFunction> point_loss_;
  ceres::EigenQuaternionManifold quaternion_manifold_;

  KeyframeList keyframes_;
  PointList points_;
  std::unordered_map<int64_t, int> point_index_;
  int last_frontend_keyframe_ = -1;  // the last keyframe the front end posed
  // The sigmas per step of the motion factors, by source.
  struct StepSigmas {
    explicit StepSigmas(int window) : t(window), r(window) {}
    int steps = 0;
    RobustScale t;
    RobustScale r;
  };
  StepSigmas odometry_sigmas_{kMotionNoiseWindow};
  StepSigmas frontend_sigmas_{kMotionNoiseWindow};
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_TRAJECTORY_H_
