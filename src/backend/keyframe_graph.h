// The keyframe graph a loop closure optimises (docs/loop-closure.md "The
// keyframe graph"): it outlives the window because it is made, when a loop
// closes, from what every keyframe keeps anyway (its estimated pose and the
// variance its camera motion states, KeyframeState) and the loop closures
// so far. Not installed.
//
//   vertices  every keyframe, at its current estimate T_wc; keyframe 0
//             holds the gauge; every confirmed map object (GraphObject)
//   edges     each keyframe k and the keyframe its camera motion relates
//             it to (MeasuredStep): the motion it was given (the odometry
//             or the front end's relative pose), or, where k - 1 and k are
//             in the window, k - 1 and their estimated relative pose;
//             information diag(I3 / s_t^2, I3 / s_r^2) from the keyframe's
//             motion variance (kUnstatedMotionSigma_* where it states none
//             usable);
//             each loop closure: its T and sigmas;
//             each object and (up to kMaxObjectEdges of) the keyframes that
//             detected it: the detection's representative pose T_co,
//             weighed with the class's detection noise (position; the
//             rotation for an asymmetric object, the axis for a symmetric
//             one of symba)
//
// Outside the window the chain is what the camera motion measured, not
// what the window's solves made of it: where the window was pulled onto
// objects seen again while its oldest keyframes were held, the estimate
// keeps a kink that, taken as a measurement with the motion's weight, no
// closure could spread. The objects' edges carry what the detections said;
// the loop's error is spread along the chain in proportion to the motion
// variances. Inside the window the estimate: the window moves as one.
#ifndef SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_
#define SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_

#include <string>
#include <vector>

#include "backend/factor_graph.h"
#include "backend/graph_noise_calibration.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/pose_graph/optimize_pose_graph.h"
#include "symba/pose_graph/pose_graph_covariance.h"

namespace symba::internal {

// A keyframe without a motion factor is linked to its predecessor this
// loosely (m, rad).
inline constexpr double kUnstatedMotionSigmaT = 1.0;
inline constexpr double kUnstatedMotionSigmaR = 1.0;

// The sigmas (m, rad) of keyframe `kf`'s step from its predecessor: its
// stated motion variance, or kUnstatedMotionSigma_* where it states none
// (or one whose information 1 / variance is not finite and positive).
struct StepSigmas {
  double t = kUnstatedMotionSigmaT;
  double r = kUnstatedMotionSigmaR;
};
StepSigmas StepSigmasOf(const KeyframeState& kf);

// A relative pose between two keyframes (indices): `later`'s pose in
// `earlier`'s frame.
struct LoopConstraint {
  int earlier = -1;
  int later = -1;
  Rigid3d T;
  double sigma_t = 0.0;  // m
  double sigma_r = 0.0;  // rad
};

// A map object in the graph: a vertex at its estimate, linked to the
// keyframes that detected it by what they measured, so that keyframes that
// saw it move together and drifted ones are pulled to it.
struct GraphObject {
  Rigid3d T_wo;  // a symmetric object's rotation is any of its poses
  // Asymmetric: its detections constrain its rotation. Otherwise the
  // rotation rows get the axis' information (HasAxis) or
  // kSymmetricRotationInformation only (they keep the vertex's rotation
  // determined).
  bool rotation = false;
  std::vector<int> keyframes;  // the detecting keyframes (indices)
  // Per detecting keyframe, what it measured: the detection's
  // representative pose T_co (its position; its rotation for an
  // asymmetric object). Empty: the estimated relative pose instead.
  std::vector<Rigid3d> measured;
  double sigma_t = 0.0;  // the class's detection noise (m, rad)
  double sigma_r = 0.0;
  // A symmetric object (rotation = false) whose detections measured its
  // axis: the world axis, per detecting keyframe the axis it measured
  // (camera frame, unit), and their noise (rad). Its edges then constrain
  // the two rotation directions off the axis (the tilt of the keyframes
  // that saw it); the turn about the axis is held only loosely
  // (kAxisTurnInformation). Empty: no axis.
  Eigen::Vector3d axis_w = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> measured_axes;
  double sigma_axis = 0.0;
  // A loaded map's object: where the map has it (a constant vertex; its
  // prior holds it there in the window's solves).
  bool fixed = false;
  // Its class: its edges' noise group for the covariances
  // (graph_noise_calibration.h).
  std::string class_name;
  // Its detections' noise (sigma_t, sigma_r) is what they declared or
  // their hypotheses' scatter, not the class's estimate or the floor for
  // an undeclared detector, which stands for errors that persist beyond
  // what its residuals can show.
  bool noise_stated = false;

  bool HasAxis() const {
    return !rotation && !measured_axes.empty() &&
           measured_axes.size() == keyframes.size() && sigma_axis > 0.0;
  }
};

// The measured relative pose of an axis edge (GraphObject::HasAxis): the
// predicted T_co = T_wc^-1 T_wo with its rotation turned by the least
// rotation that takes the predicted axis R_co a_o (a_o = R_wo^-1 a_w) onto
// the measured a_c, and its position t_co_measured. Its rotation error is
// then zero about the axis and the measured tilt off it.
Rigid3d AxisEdgeMeasurement(const Rigid3d& T_wc,
                            const Rigid3d& T_wo,
                            const Eigen::Vector3d& axis_w,
                            const Eigen::Vector3d& axis_c,
                            const Eigen::Vector3d& t_co_measured);
// `axis_c` must be on `axis_w`'s side (R_wc axis_c . axis_w >= 0), as
// GraphObjects() makes it: the least rotation onto the opposite axis is not
// unique.
// Its rotation information in the object's frame (the edge's error frame):
// information (I - a_o a_o^T) + kAxisTurnInformation a_o a_o^T.
Eigen::Matrix3d AxisInformation(const Eigen::Vector3d& a_o, double information);
// The turn about the axis, which nothing measures, is held to the edge's
// measurement (the estimate's relative turn when the graph is made) with a
// sigma of 1 rad: far looser than a step of camera motion (a long
// featureless chain can add up to as much), and it keeps
// Levenberg-Marquardt's steps well conditioned. With 1e-6 / rad^2 (as a
// symmetric object's rotation without an axis gets) the long scene's
// closures took 3.5 times as many iterations (1868 against 533 over 82
// closures, up to 3.3 s each; keyframe RMSE 0.113 m against 0.122 m).
inline constexpr double kAxisTurnInformation = 1.0;  // 1/rad^2

// At most this many edges per object, spread over its detections, each
// with the information of (detections / edges) detections.
inline constexpr int kMaxObjectEdges = 16;
inline constexpr double kSymmetricRotationInformation = 1e-6;  // 1/rad^2

// Keyframe k's (k >= 1) edge to an earlier keyframe in the graph: with
// k - 1 >= window_begin (both in the window) the estimated relative pose
// T_{k-1,k}; else the camera motion measured, from the keyframe its motion
// factor relates it to (KeyframeState::motion_from: k - 1 for odometry,
// the last keyframe the front end posed otherwise), T_chain(j)^-1
// T_chain(k) (KeyframeState::T_wc_chain).
struct ChainStep {
  int from = -1;  // keyframe index
  Rigid3d T;      // k's pose in from's frame
};
ChainStep MeasuredStep(const KeyframeList& keyframes, int k, int window_begin);

// The graph above for `keyframes` (at least one), the window's first
// keyframe (index; <= 0: all in the window), `loops` and `objects` (vertex
// ids: keyframe indices, then keyframes.size() + object index). With
// `roles`, each edge's role in the covariances' noise calibration
// (graph_noise_calibration.h): a step's group is its stated sigmas (to a
// quarter octave), held where its two keyframes shared at least
// kMinSharedPoints map points, measured unless both are in the window (the
// estimate is its measurement); an object's edges are its class's group,
// held from kMinHeldViews detecting keyframes on where its noise is stated
// (GraphObject::noise_stated); loop closures keep their noise.
PoseGraph MakeKeyframeGraph(const KeyframeList& keyframes,
                            int window_begin,
                            const std::vector<LoopConstraint>& loops,
                            const std::vector<GraphObject>& objects,
                            std::vector<GraphEdgeRole>* roles = nullptr);
// A step is held by others where its two keyframes (k - 1 and k) shared at
// least this many map points: a relative pose from them is overdetermined.
inline constexpr int kMinSharedPoints = 6;
// An object's edges are held by others from this many detecting keyframes
// on: its position is then a mean of many, each detection's residual
// nearly its own error.
inline constexpr int kMinHeldViews = 10;

// Optimises that graph; on success (*keyframe_poses)[k] is keyframe k's
// optimised pose and (*object_poses)[o] object o's. On an error nothing is
// written.
Status OptimizeKeyframeGraph(const KeyframeList& keyframes,
                             int window_begin,
                             const std::vector<LoopConstraint>& loops,
                             const std::vector<GraphObject>& objects,
                             std::vector<Rigid3d>* keyframe_poses,
                             std::vector<Rigid3d>* object_poses,
                             PoseGraphSolveSummary* summary);

// For PoseGraphCovariances on that graph: the objects whose rotation it
// does not measure (no rotation, no axis) have it held.
PoseGraphCovarianceOptions KeyframeGraphCovarianceOptions(
    int num_keyframes, const std::vector<GraphObject>& objects);

// Exactly the identity (an unmoved entity).
inline bool IsIdentity(const Rigid3d& W) {
  return W.t.isZero(0.0) && W.q.vec().isZero(0.0);
}

// The one rigid move that stands for the moves of `keyframes` (indices,
// -1 skipped) at a point p they observed: its rotation the chordal mean of
// theirs, its translation such that it takes p to the mean of W_k p. The
// identity for none.
Rigid3d MeanMove(const std::vector<Rigid3d>& moves,
                 const std::vector<int>& keyframes,
                 const Eigen::Vector3d& p);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_KEYFRAME_GRAPH_H_
