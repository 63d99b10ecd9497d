// The backend's internal state: keyframes, map objects, map points and the
// factors between them, all addressed by index into stable containers. Not
// installed; see symba/backend/backend.h for the public API.
#ifndef SYMBA_SRC_BACKEND_BACKEND_STATE_H_
#define SYMBA_SRC_BACKEND_BACKEND_STATE_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "backend/track_step.h"
#include "symba/backend/estimates.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"

namespace symba::internal {

inline Rigid3d ReadPose(const double* q, const double* t) {
  return Rigid3d(Eigen::Map<const Eigen::Quaterniond>(q),
                 Eigen::Map<const Eigen::Vector3d>(t));
}

// T with its quaternion normalised.
inline Rigid3d Normalized(Rigid3d T) {
  T.q.normalize();
  return T;
}

inline void WritePose(const Rigid3d& T, double* q, double* t) {
  Eigen::Map<Eigen::Quaterniond> q_map(q);
  Eigen::Map<Eigen::Vector3d> t_map(t);
  q_map = T.q.normalized();
  t_map = T.t;
}

struct KeyframeState {
  int64_t id = 0;
  double timestamp = 0.0;
  double q[4] = {0, 0, 0, 1};  // q_wc, Eigen order
  double t[3] = {0, 0, 0};     // t_wc
  std::optional<Rigid3d> T_wc_frontend;
  // Where the front end alone puts this keyframe: the first pose chained
  // with every odometry or front-end relative motion, never optimised (the
  // detection noise is measured against it, detection_noise.h).
  Rigid3d T_wc_chain;
  // The variance one step of the camera motion factor adds to the
  // predicted pose (m^2, rad^2; 0 without a motion factor).
  double motion_variance_t = 0.0;
  double motion_variance_r = 0.0;
  // The sigmas the front end stated for that step (m, rad; 0 without a
  // motion factor); motion_variance_* is their square times the square of
  // the factor the objects found they must be multiplied by
  // (motion_claims.h), 1 unless they contradict the statement.
  double stated_motion_sigma_t = 0.0;
  double stated_motion_sigma_r = 0.0;
  // The keyframe (index) its camera motion factor relates it to: the
  // previous one (odometry), or the last the front end posed (-1: none).
  int motion_from = -1;
  // The motion variances of every keyframe since the first summed (m^2,
  // rad^2): what the camera's uncertainty grows by between two keyframes,
  // as the motion factors state it.
  double summed_motion_variance_t = 0.0;
  double summed_motion_variance_r = 0.0;
  // Map points observed in this keyframe and the one before it (their
  // relative pose is then held by more than the camera motion).
  int points_shared_with_previous = 0;
  // Every factor touching this keyframe while it is in the window (freed
  // when it leaves).
  std::vector<int> factors;

  Rigid3d T_wc() const { return ReadPose(q, t); }
};

// One detection's contribution to one object edge, kept so the edge can be
// rebuilt when its object changes type or is re-anchored.
struct ObjectObservation {
  int keyframe = -1;  // keyframe index
  // The detection's noise as given (claimed = true), its hypotheses'
  // scatter (from_scatter) or the options' default;
  // the edge is built with the effective noise (detection_noise.h).
  double sigma_t = 0.0;  // m
  double sigma_r = 0.0;  // rad
  bool claimed_t = false;
  bool claimed_r = false;
  // sigma_t, sigma_r are the detection's hypotheses' scatter
  // (BackendOptions::scatter_min_hypotheses).
  bool from_scatter = false;
  // This edge's hypotheses (freed when its keyframe leaves the window,
  // unless BackendOptions::keep_history).
  std::vector<PoseComponent> components;
  Rigid3d T_co_best;  // representative hypothesis
  Eigen::Vector3d axis_c = Eigen::Vector3d::Zero();  // measured axis, if any
  // A view of an object from before the object was turned to the rotation
  // its later views agree on (ObjectMap::RecordFlip): neither its rotation
  // nor its position carries information (kUninformativeSigma,
  // object_edges.h); the detector that turned it had its pose wrong.
  bool turned_away = false;
  int angle = -1;   // discrete: the angle it constrains; -1: no angle
  int factor = -1;  // its edge's factor index
  // The sigmas its edge was last built with (ObjectEdges::AddFactor): m,
  // and rad where the edge weighs the rotation with it (an asymmetric
  // view, a discrete angle's); 0: no edge built (yet, or a merged copy's
  // view whose edge left with the copy's prior), a turned-away view (it
  // weighs nothing), or no rotation weighed so.
  double edge_sigma_t = 0.0;
  double edge_sigma_r = 0.0;
};

// A tentative object's edges stay out of the solves until enough
// detections confirmed it; a dropped one is gone for good (its factors are
// retired, its detections rejected).
enum class ObjectStatus { kTentative, kConfirmed, kDropped };

// A detection whose rotation contradicts an asymmetric object at its
// position by a twist about an axis (symba's upgrade evidence).
struct FlipEvidence {
  int keyframe = -1;                              // keyframe index
  Eigen::Vector3d a_o = Eigen::Vector3d::Zero();  // twist axis, object frame
  double angle = 0.0;                             // twist angle (rad)
};

// What made an asymmetric object symmetric, for the report.
struct UpgradeRecord {
  int keyframe = -1;  // keyframe index of the upgrade
  SymmetryType type = SymmetryType::kDiscrete;
  int evidence = 0;    // consistent detections (flips, or 1 symmetric one)
  int order = 0;       // the plausible order the flips' angle implies (0: none)
  double angle = 0.0;  // the flips' mean twist angle (rad)
};

// An object's detections where the front end alone puts them (its chain of
// keyframe poses; detection_noise.h): running sums for the mean position
// and rotation, and the last one, for the class's noise samples.
struct ChainSamples {
  Eigen::Vector3d position_sum = Eigen::Vector3d::Zero();
  Eigen::Vector4d rotation_sum = Eigen::Vector4d::Zero();
  int count = 0;
  int rotation_count = 0;
  int last_keyframe = -1;
  Eigen::Vector3d last_position = Eigen::Vector3d::Zero();
  std::optional<Eigen::Quaterniond> last_rotation;
};

struct ObjectState {
  int id = 0;
  ObjectStatus status = ObjectStatus::kConfirmed;
  int created_keyframe = -1;  // keyframe index
  int last_keyframe = -1;     // keyframe index of its last detection
  int keyframes_seen = 0;     // distinct keyframes with a detection of it
  int keyframes_in_view = 0;  // keyframes since confirmation it was in view
  int keyframes_seen_in_view = 0;  // ... and was detected in
  std::vector<int> assignments;    // indices into the backend's assignments
  std::vector<FlipEvidence> flips;
  int flip_keyframes = 0;     // keyframes among `flips` (each once)
  int flips_left_behind = 0;  // views at the rotation a turn left (flips now)
  std::optional<UpgradeRecord> upgrade;
  // The upgrade a loaded object had in the run that saved it (reported as
  // it was; `upgrade` is this run's).
  std::optional<MapObjectEstimate::Upgrade> loaded_upgrade;
  int loaded_detections = 0;  // the saved map's observations of it
  ChainSamples chain;
  // While tentative: the steps between its detections' front-end positions
  // (the last kMaxTrackSteps; object_track.h). Freed at confirmation.
  std::vector<TrackStep> track;
  std::string class_name;
  SymmetryType type = SymmetryType::kAsymmetric;
  double q[4] = {0, 0, 0, 1};                     // q_wo (asymmetric)
  double t[3] = {0, 0, 0};                        // t_wo (every type)
  double a_w[3] = {0, 0, 1};                      // world axis (symmetric)
  Eigen::Vector3d a_o = Eigen::Vector3d::Zero();  // object-frame axis
  SymmetryAnchor anchor;
  std::vector<std::unique_ptr<double>> thetas;  // stable addresses
  // Discrete: per angle, the detections' evidence for it (each detection
  // shares one unit among the angles its modes went to, by the modes'
  // hypothesis weights; MapObjectEstimate::angle_evidence).
  std::vector<double> angle_evidence;
  // In keyframe order. Edges of observations before stale_observations
  // were built for an older type, anchor or noise: under the marginalize
  // and drop policies a rebuild touches the window's observations only,
  // and the batch solve rebuilds the rest first (observations before
  // upgrade_observations then constrain angle 0, as at the upgrade).
  std::vector<ObjectObservation> observations;
  int stale_observations = 0;
  int upgrade_observations = 0;
  // Its observations from keyframes that left the window, as a prior on
  // its blocks (the factor's index; -1: none).
  int prior_factor = -1;
  int detections = 0;

  Eigen::Vector3d position() const {
    return Eigen::Map<const Eigen::Vector3d>(t);
  }
  Eigen::Vector3d axis_w() const {
    return Eigen::Map<const Eigen::Vector3d>(a_w);
  }
  // The world rotation of angle i (discrete) or of the pose (asymmetric).
  Eigen::Quaterniond Rotation(int angle) const {
    if (type == SymmetryType::kAsymmetric) {
      return Eigen::Map<const Eigen::Quaterniond>(q);
    }
    const double theta = angle >= 0 ? *thetas[angle] : 0.0;
    return SymmetricObjectRotation(anchor, axis_w(), theta);
  }
};

// Confirmed and detected: a map object the loop matching, the duplicate
// merges and the keyframe graph take.
inline bool IsMapped(const ObjectState& o) {
  return o.status == ObjectStatus::kConfirmed && !o.observations.empty();
}

// A loaded map's object (ObjectMap::Load creates it at no keyframe), or a
// duplicate merged into one; dropped ones too.
inline bool IsLoaded(const ObjectState& o) { return o.created_keyframe < 0; }

// A loaded map's object that no detection of this run has gone to yet: it
// is where the map has it, in the map's frame.
inline bool IsLoadedUnseen(const ObjectState& o) {
  return IsLoaded(o) && o.status == ObjectStatus::kConfirmed &&
         o.observations.empty() && o.last_keyframe < 0;
}

struct PointState {
  int64_t id = 0;
  double p[3] = {0, 0, 0};   // p_w
  std::vector<int> factors;  // condition policy only: its observations
  // marginalize: its observations from keyframes that left the window, as
  // one prior on p_w (the factor's index; -1: none).
  int prior_factor = -1;
  // The first and the last keyframe that observed it (-1: none).
  int first_keyframe = -1;
  int last_keyframe = -1;
};

// A factor and where it sits. The record owns its cost function; the
// problem borrows it while the factor is active.
struct FactorRecord {
  std::unique_ptr<ceres::CostFunction> cost;
  const ceres::LossFunction* loss = nullptr;
  std::vector<double*> blocks;
  int keyframe = -1;   // keyframe index
  int keyframe2 = -1;  // the other keyframe of an odometry factor
  int object = -1;
  int observation = -1;  // index into the object's observations
  int point = -1;
  ceres::ResidualBlockId residual = nullptr;  // non-null while in the problem
  bool retired = false;                       // replaced by a rebuilt factor
  // Its information went into the marginalisation prior (or was dropped
  // with its keyframe): only the batch solve uses it again.
  bool marginalized = false;
  // A point's marginalisation prior: a summary of other factors, never in
  // the batch solve.
  bool summary = false;
  int sync_stamp = 0;  // WindowProblem::Sync's bookkeeping
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_BACKEND_STATE_H_
