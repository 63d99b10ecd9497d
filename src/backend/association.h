// Data association (method notes Sec. 5): which map object a detection
// belongs to, gated on the parameters both can agree on. Pure functions of
// the map objects and the options, so they can be tested on hand-built
// object sets. Not installed.
//
//   SH / MH     6 DoF: position within gate_position and rotation within
//               gate_rotation of any used hypothesis; score d_t / gate_t +
//               d_r / gate_r, lowest wins.
//   symba       position within gate_position, then
//               symmetric object        axis within gate_axis (5 DoF);
//               symmetric detection,
//               asymmetric object       the detection's axis carried by the
//                                       object's pose within gate_axis: the
//                                       object is upgraded;
//               both asymmetric         6 DoF with the nearest inlier
//                                       hypothesis within gate_rotation;
//                                       failing that, a relative rotation
//                                       that is a twist about an axis (the
//                                       prior's within gate_axis, or its own)
//                                       is a flip: evidence that may upgrade
//                                       the object to discrete once repeated
//                                       (upgrade_evidence.h).
//   Only objects of the requested status take part (the backend tries the
//   confirmed map first, then tentative objects). The position gate is
//   gate_position, or, once the detection's noise is known, that noise
//   with the object's (n observations) and the predicted camera's (one
//   motion step, or the steps since the place was last seen: PlaceGrowth,
//   RevisitGates),
//   times gate_sigmas, if that is smaller (PositionGate).
//   angles      a discrete object's angle within gate_angle of the twist
//               the detection shows, else a new angle.
#ifndef SYMBA_SRC_BACKEND_ASSOCIATION_H_
#define SYMBA_SRC_BACKEND_ASSOCIATION_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "backend/backend_state.h"
#include "symba/backend/backend_options.h"
#include "symba/backend/keyframe_input.h"
#include "symba/categorization/categorize.h"

namespace symba::internal {

using ObjectList = std::vector<std::unique_ptr<ObjectState>>;

// Angle between two axes, ignoring their signs, in [0, pi/2].
double AxisDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Which objects an association looks at, and the detection's position
// noise (m) where it is known.
struct AssociationScope {
  ObjectStatus status = ObjectStatus::kConfirmed;
  std::optional<double> sigma_t;
  // The variance the predicted camera pose adds to the detection's world
  // position (m^2): one step of the camera motion noise at its distance.
  double prediction_variance = 0.0;
  // The variance the camera's motion since the place was last seen adds
  // (m^2; PlaceGrowth), if larger than prediction_variance, to the gate of
  // `place_object` only (RevisitGates).
  double place_variance = 0.0;
  const ObjectState* place_object = nullptr;
};

// The scope of a detection in keyframe `kf` seen at t_co (confirmed
// objects): the position noise the gates use, the detection's sigma_t (or
// the default) times its class's claim factor (ObjectEdges::ApplyNoise)
// where it declares a noise, else `estimated_sigma_t`: the
// class's estimate, or the hypotheses' scatter held to the class's white
// part (Backend::Impl::GateSigmaT; the gate wants the scatter itself, not
// the floor of the weighting); and one motion step's variance at the
// object's distance.
AssociationScope DetectionScope(const DetectionInput& detection,
                                const KeyframeState& kf,
                                const Eigen::Vector3d& t_co,
                                const std::optional<double>& estimated_sigma_t,
                                const BackendOptions& options,
                                double claim_factor_t = 1.0);

// The latest keyframe before keyframe k in which an object (any class,
// any status but dropped) within gate_position of t_w was detected: when
// the place the detection lies in was last seen (-1: never). Called before
// keyframe k's detections are added (an object detected in keyframe k
// already counts as not seen before it).
int PlaceLastSeen(const ObjectList& objects,
                  int k,
                  const Eigen::Vector3d& t_w,
                  const BackendOptions& options);

// The camera's uncertainty relative to a place last seen in keyframe j, at
// keyframe k, for a detection at `distance` (docs/backend.md "Real
// detectors", 2): the motion variances of keyframes j + 1 .. k summed, the
// rotation's at that distance, (V_t(k) - V_t(j)) + d^2 (V_r(k) - V_r(j))
// (KeyframeState::summed_motion_variance_*); 0 for j < 0.
double PlaceGrowth(const std::vector<std::unique_ptr<KeyframeState>>& keyframes,
                   int j,
                   int k,
                   double distance);

// One detection of a keyframe as the revisit test (RevisitGates) sees
// it: its class, where the predicted camera puts it, its distance from
// the camera, and its scope (one step's prediction_variance; PlaceGrowth's
// place_variance).
struct RevisitDetection {
  const std::string* class_name = nullptr;
  Eigen::Vector3d t_w = Eigen::Vector3d::Zero();
  double distance = 0.0;
  AssociationScope scope;
};

// What a detection's gate takes for a revisit: the grown variance and the
// one object it applies to (-1: none, one step's gate for every object).
struct RevisitGate {
  double variance = 0.0;  // m^2
  int object = -1;        // index into the objects
};

// Per detection of a keyframe, its RevisitGate (docs/backend.md "Real
// detectors", 2). None where an object of its class lies within one step's
// gate (no revisit), or its place_variance does not exceed one step's.
// Otherwise the nearest of the objects of its class that the grown gate
// reaches and one step's does not (off by Delta = the object's position -
// the detection's) for which either no other object lies within the
// detection's distance from the camera of that object (a place of one
// object), or
// more of the keyframe's other detections near it, moved by Delta, fall
// within one step's gate of an object of their class (other than it) than
// do not (the place seen off by the same shift). A detection of one object
// that the drift carried near another of its class is so kept from it when
// the place's other detections do not move with it.
std::vector<RevisitGate> RevisitGates(
    const ObjectList& objects,
    const std::vector<RevisitDetection>& detections,
    const BackendOptions& options);

// The position gate (m) of `object` for a detection in `scope`:
// min(gate_position, gate_sigmas * sqrt(sigma_t^2 (1 + 1/n) +
// max(prediction_variance, place_variance))) once sigma_t is known (the
// place_variance for scope.place_object only), gate_position before.
double PositionGate(const ObjectState& object,
                    const AssociationScope& scope,
                    const BackendOptions& options);

// SH / MH: the best object of `class_name` within the 6-DoF gates of any
// candidate world pose T_wo, or -1.
int FindSixDofMatch(const ObjectList& objects,
                    const std::string& class_name,
                    const std::vector<Rigid3d>& T_wo_candidates,
                    const AssociationScope& scope,
                    const BackendOptions& options);

struct SymbaMatch {
  int object = -1;
  bool upgrade = false;  // an asymmetric object that must become symmetric
  bool flip = false;     // a twist away from an asymmetric object's pose
  Eigen::Vector3d a_o = Eigen::Vector3d::Zero();  // the axis, if either
  double flip_angle = 0.0;  // the twist about a_o (rad, [0, pi]), if a flip
  // A flip's world rotation: the detection's hypothesis nearest the object.
  Eigen::Quaterniond R_wo_flip = Eigen::Quaterniond::Identity();
};

// symba: the best object for a categorized detection seen from T_wc, or
// object = -1. `prior` may be null.
SymbaMatch FindSymbaMatch(const ObjectList& objects,
                          const Rigid3d& T_wc,
                          const CategorizedDetection& cat,
                          const std::string& class_name,
                          const std::vector<PoseHypothesis>& hyps,
                          const ClassPrior* prior,
                          const AssociationScope& scope,
                          const BackendOptions& options);

// A discrete object's angle whose rotation is within `gate` (rad, twist
// about a_o) of R_wo, or -1.
int FindAngle(const ObjectState& object,
              const Eigen::Quaterniond& R_wo,
              double gate);
// A rotation R_wo of a discrete object of known symmetry order, read modulo
// step = 2 pi / order about a_o: the angle i and multiple m minimising
// |Twist(R_wo_i^T R_wo, a_o) - m step|, when that remainder is within
// `gate` (rad); angle = -1 otherwise. R_wo Rot(a_o, -m step) is then the
// same physical pose seen at angle i.
struct FoldedAngle {
  int angle = -1;
  int multiple = 0;
};
FoldedAngle FoldToAngle(const ObjectState& object,
                        const Eigen::Quaterniond& R_wo,
                        int order,
                        double gate);
// The theta a new angle of `object` showing R_wo gets: theta_0 plus the
// twist from angle 0 (or from the anchor when there is no angle yet).
double NewAngleTheta(const ObjectState& object, const Eigen::Quaterniond& R_wo);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_ASSOCIATION_H_
