// The backend's map objects (method notes Sec. 5; docs/architecture.md): it
// owns every object's estimate and lifecycle (created from a first
// detection, tentative until confirmed, dropped when unsupported), the
// upgrades from asymmetric to symmetric, a discrete object's angles and its
// re-anchoring, and the samples of the detector's noise taken from its
// detections. It changes objects only; their edges are ObjectEdges' and the
// caller rebuilds them where a step says the object changed. Not installed.
#ifndef SYMBA_SRC_BACKEND_OBJECT_MAP_H_
#define SYMBA_SRC_BACKEND_OBJECT_MAP_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <ceres/manifold.h>

#include "backend/association.h"
#include "backend/backend_state.h"
#include "backend/claim_pairs.h"
#include "backend/detection_noise.h"
#include "backend/factor_graph.h"
#include "backend/upgrade_evidence.h"
#include "symba/backend/backend.h"
#include "symba/categorization/hypothesis_scatter.h"
#include "symba/manifolds/axis_manifold.h"

namespace symba::internal {

class ObjectMap {
 public:
  // `graph`, `statistics` and `assignments` are the backend's; the graph is
  // not used before the first object is created.
  ObjectMap(const BackendOptions& options,
            const std::map<std::string, ClassPrior>& class_priors,
            FactorGraph* graph,
            BackendStatistics* statistics,
            std::vector<DetectionAssignment>* assignments);

  const ObjectList& objects() const { return objects_; }
  // The class's flip counts (upgrade_evidence.h); empty if it has none.
  ClassFlipCounts ClassFlips(const std::string& class_name) const {
    const auto it = class_flips_.find(class_name);
    return it == class_flips_.end() ? ClassFlipCounts{} : it->second;
  }
  // The objects themselves, for the edges' bookkeeping (ObjectEdges).
  ObjectList& mutable_objects() { return objects_; }
  const ClassPrior* PriorOf(const std::string& class_name) const;
  // The objects of a class, dropped ones included.
  const std::vector<int>& ObjectsOfClass(const std::string& class_name) const;
  const DetectionNoiseEstimator& noise() const { return noise_; }
  // The front end's stated motion noise as the objects test it.
  const MotionClaims& motion_claims() const { return motion_claims_; }
  MotionClaims* mutable_motion_claims() { return &motion_claims_; }

  // A new object of `class_name` at T_wo, first detected in keyframe k;
  // tentative when confirm_keyframes > 1. A symmetric one's axis and anchor
  // are the caller's to set.
  int Create(const std::string& class_name,
             SymmetryType type,
             const Rigid3d& T_wo,
             int k);
  // symba: a new object at the categorized detection's base pose seen from
  // T_wc, with its axis and anchor if symmetric.
  int CreateSymba(const std::string& class_name,
                  const CategorizedDetection& cat,
                  const Rigid3d& T_wc,
                  int k);
  // A detection of object o in keyframe k, reported as assignment a, seen at
  // t_co (its bearing and depth widen the view cone).
  void NoteDetection(int o, int k, int assignment, const Eigen::Vector3d& t_co);
  // Confirms tentative objects with enough keyframes whose track looks
  // static (object_track.h) and drops those whose timeout passed (bounded
  // by the tentative objects).
  void UpdateTentative(int k);
  // Counts keyframe k (camera T_wc) for every confirmed object in view and
  // drops those detected in too few of their views (min_support).
  void PruneUnsupported(int k, const Rigid3d& T_wc);

  // symba: a flip of object o joins it without an edge (kOutlier), upgrades
  // it once the evidence suffices, or turns it to the flip's rotation once
  // the flips say its own rotation was the detector's confusion
  // (upgrade_evidence.h). Upgraded or turned, its edges must then be
  // rebuilt; turned, the flip is a view of it at its rotation.
  enum class FlipOutcome { kOutlier, kUpgraded, kTurned };
  FlipOutcome RecordFlip(int o, int k, const SymbaMatch& match);
  // Object o becomes `type` about a_o (object frame); its edges must then be
  // rebuilt.
  void Upgrade(int o,
               SymmetryType type,
               const Eigen::Vector3d& a_o,
               const UpgradeRecord& record);
  // The angle of discrete object o that `observation` (seen from T_wc)
  // constrains: the nearest within gate_angle; else, if `may_fold` (the
  // detection shows one mode) and the class prior gives the order, the
  // nearest modulo 2 pi / order, the observation then turned by that
  // multiple about a_o; else a new angle.
  int MatchOrAddAngle(int o,
                      const Rigid3d& T_wc,
                      bool may_fold,
                      ObjectObservation* observation);
  // Adds `share` of one detection to angle `angle` of discrete object o
  // (MapObjectEstimate::angle_evidence).
  void AddAngleEvidence(int o, int angle, double share);
  // A discrete object whose axis drifted beyond reanchor_angle from its
  // anchor gets a new anchor; true if so: its edges must then be rebuilt.
  bool ReanchorIfDrifted(int o);

  // A detection of object o in keyframe k (its position, and its rotation
  // where it has one) as noise samples of the class, taken at the front
  // end's pose of the keyframe, T_wc_chain (detection_noise.h).
  void SampleNoise(int o,
                   int k,
                   const Rigid3d& T_wc_chain,
                   const Eigen::Vector3d& t_co,
                   const std::optional<Eigen::Quaterniond>& R_co);

  // A detection of keyframe k that declares its sigma, as a sample of its
  // class's claim scale (claim_pairs.h, ClaimPairs::Add).
  void SampleClaim(int k,
                   const ClaimedDetection& detection,
                   const std::optional<StepVariance>& step) {
    claim_pairs_.Add(k, detection, step, &noise_, &motion_claims_);
  }

  // A detection of `class_name` weighed by its hypotheses' scatter, for
  // the noise report.
  void NoteScatter(const std::string& class_name,
                   const HypothesisScatter& scatter) {
    noise_.AddScatter(class_name, scatter.sigma_t, scatter.sigma_r);
  }

  // Loops found from the objects (docs/loop-closure.md): duplicate object
  // `from` (confirmed, the later-made of two copies of one object) is
  // merged into `into` of the same class and type; the noise samples go on
  // from the copy detected last. `from` is gone (its edges and prior
  // retired, its detections and their assignments now `into`'s); the
  // observations it had are returned, for the caller to add to `into`
  // (their factor -1, a discrete one's angle still `from`'s).
  std::vector<ObjectObservation> MergeInto(int from, int into);
  // Discrete object o's angle nearest to the world rotation R_wo within
  // gate_angle; else, if the class prior gives the order, the nearest
  // modulo 2 pi / order (*multiple = m: R_wo Rot(a_o, -m 2 pi / order) is
  // that angle's pose, the same physical pose); else a new one at R_wo.
  // *multiple is 0 unless folded. It never folds onto an angle in
  // `taken` (a merge's angles of one duplicate stay apart, as a detection
  // showing several modes does not fold).
  int MatchOrAddAngle(int o,
                      const Eigen::Quaterniond& R_wo,
                      const std::vector<int>& taken,
                      int* multiple);
  // Turns `observation`'s rotations as MatchOrAddAngle's fold of
  // `multiple` for discrete object o (a no-op for 0).
  void TurnByFold(int o, int multiple, ObjectObservation* observation) const;
  // How many objects were confirmed so far (never decreases).
  int confirmations() const { return confirmations_; }

  // A confirmed object from a saved map (Backend::LoadMap) with id and
  // index `e.id` (the indices below it that no loaded object takes are
  // dropped placeholders) and the prior of its covariance, if any. Before
  // any other object; e is valid (ValidateSavedMap).
  void Load(const MapObjectEstimate& e);

 private:
  // Whether a tentative object's track looks static (object_track.h):
  // true without estimate_noise, with track_tolerance 0, or before the
  // class has a frame-to-frame noise and a reference ratio.
  bool TrackLooksStatic(const ObjectState& object) const;
  // A step between two detections of `object` (object_track.h): kept on
  // its track while tentative, one of the class's reference steps once
  // confirmed.
  void NoteTrackStep(ObjectState& object, const TrackStep& step);
  void Drop(int o);
  // A new angle of discrete object o at the world rotation R_wo.
  int AddAngle(int o, const Eigen::Quaterniond& R_wo);
  // The class prior's symmetry order when it applies to object o (discrete
  // prior, order >= 2, axis along the object's a_o), else 0.
  int KnownOrder(int o) const;
  // The symmetry order a flip by `angle` shows: `known_order` (a discrete
  // class prior's, 0 if none) if it fits, else the smallest plausible one
  // (upgrade_evidence.h); 0 if none.
  int FlipOrder(double angle, int known_order) const;
  // Turns asymmetric object o to the world rotation R_wo: its earlier views
  // weigh nothing from then on (turned_away: neither rotation nor position,
  // in the window and in a batch over the kept history), its prior is
  // retired, its flips start again from the `left_behind` views at the
  // rotation it leaves (flips by `angle`, also in its class's counts), its
  // rotation noise samples start again.
  void Turn(int o,
            const Eigen::Quaterniond& R_wo,
            int left_behind,
            double angle,
            int known_order);
  // Adds `count` (may be negative) flips by `angle` to the class's counts of
  // every order the angle fits (only `known_order`, a discrete prior's, if
  // not 0).
  void CountClassFlip(const std::string& class_name,
                      double angle,
                      int known_order,
                      int count);
  // The MatchOrAddAngles' one rule for discrete object o seen at R_wo: the
  // angle within gate_angle; else, with order > 0, the one modulo
  // 2 pi / order that is not in `taken` (*multiple its multiple, counted in
  // folded_angles); else a new angle. *multiple is 0 unless folded.
  int MatchFoldOrAddAngle(int o,
                          const Eigen::Quaterniond& R_wo,
                          int order,
                          const std::vector<int>& taken,
                          int* multiple);

  const BackendOptions& options_;
  std::map<std::string, ClassPrior> class_priors_;
  FactorGraph* graph_;
  BackendStatistics* statistics_;
  std::vector<DetectionAssignment>* assignments_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
  AxisManifold axis_manifold_;

  ObjectList objects_;
  std::map<std::string, std::vector<int>> objects_by_class_;
  std::map<std::string, ClassFlipCounts> class_flips_;  // upgrade evidence
  std::vector<int> tentative_;                          // indices
  int confirmations_ = 0;
  double view_cone_cos_ = 1.0;  // cos of the widest detection bearing
  double view_depth_ = 0.0;     // the largest detection distance (m)
  DetectionNoiseEstimator noise_;
  MotionClaims motion_claims_;
  ClaimPairs claim_pairs_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_MAP_H_
