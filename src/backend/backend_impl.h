// Backend::Impl: the orchestrator behind the Backend facade. AddKeyframe
// is the recipe of one keyframe (docs/architecture.md): validate and
// categorise, add the keyframe (Trajectory), associate each detection and
// add its observations (ObjectMap, ObjectEdges), then the lifecycle and the
// noise updates; the solves are the factor graph's (FactorGraph). Its
// member functions are defined in
//   backend.cc      AddKeyframe, the solves, read-back
//   detections.cc   a keyframe's detections, per method
//   loop_closure.cc loop closures, the past moved with them
//   object_loops.cc loops found from the objects, duplicates merged
//   saved_map.cc    SaveMap, LoadMap
// Association (association.h), detection observations
// (detection_observations.h) and input checks (keyframe_validation.h) are
// units of their own. Not installed.
#ifndef SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
#define SYMBA_SRC_BACKEND_BACKEND_IMPL_H_

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "backend/backend_state.h"
#include "backend/factor_graph.h"
#include "backend/keyframe_graph.h"
#include "backend/object_edges.h"
#include "backend/object_map.h"
#include "backend/trajectory.h"
#include "symba/backend/backend.h"
#include "symba/categorization/hypothesis_scatter.h"

namespace symba {

class Backend::Impl {
 public:
  Impl(const BackendOptions& options,
       const std::optional<PinholeIntrinsics>& intrinsics,
       const std::map<std::string, ClassPrior>& class_priors);

  Status AddKeyframe(const KeyframeInput& input,
                     std::vector<DetectionAssignment>* assignments);
  Status OptimizeWindow(SolveReport* report);
  Status OptimizeBatch(SolveReport* report);
  // A loop closure (loop_closure.cc, docs/loop-closure.md).
  Status AddLoopClosure(KeyframeId keyframe,
                        const LoopClosureInput& closure,
                        LoopClosureReport* report);

  std::vector<KeyframeEstimate> Keyframes() const;
  std::vector<MapObjectEstimate> Objects() const;
  std::optional<KeyframeEstimate> Keyframe(KeyframeId id) const;
  std::optional<MapObjectEstimate> Object(ObjectId id) const;
  std::vector<ClassNoiseEstimate> Noise() const;
  // What the edges of the class's confirmed objects weigh its detections
  // with now (ClassNoiseEstimate::weights).
  ClassNoiseEstimate::Weights EdgeWeights(const std::string& class_name) const;
  MotionNoiseReport MotionNoise() const {
    MotionNoiseReport report = trajectory_.MotionNoise();
    report.claims = map_.motion_claims().Report();
    return report;
  }
  // The closed loops' reports and the waiting ones'.
  std::vector<LoopClosureReport> LoopClosures() const;
  Status ObjectCovariances(std::vector<MapObjectCovariance>* covariances);
  std::vector<CovarianceNoiseGroup> CovarianceNoise() const {
    return covariance_noise_;
  }
  Status KeyframeCovariances(
      const std::vector<KeyframeId>& ids,
      std::vector<KeyframeCovariance>* covariances) const;
  // A map that lasts (saved_map.cc, docs/map-format.md).
  Status SaveMap(SavedMap* map);
  Status LoadMap(const SavedMap& map);
  // Weighs the classes' detections as a saved map's run last did
  // (SavedClassNoise), before the first keyframe; nothing without
  // estimate_noise (the options' weights stand).
  void RestoreNoise(const std::vector<SavedClassNoise>& noise);

  const BackendOptions options_;
  // As created (a relocalisation's search is created alike).
  const std::optional<PinholeIntrinsics> intrinsics_;
  const std::map<std::string, ClassPrior> class_priors_;
  std::vector<DetectionAssignment> assignments_;
  BackendStatistics statistics_;
  std::vector<LoopClosureReport> loop_closures_;

 private:
  // Detections, per method (detections.cc). CategorizeDetections runs before
  // anything of the keyframe is added, so a failing detection adds nothing.
  Status CategorizeDetections(const KeyframeInput& input);
  // Per detection of keyframe k, what its position gate takes for the
  // camera's motion since its place was last seen (internal::RevisitGates)
  // and whether that place was last seen before the window.
  struct Revisit {
    internal::RevisitGate gate;
    bool before_window = false;
  };
  std::vector<Revisit> Revisits(int k, const KeyframeInput& input) const;
  void AddDetection(int k,
                    const DetectionInput& detection,
                    const CategorizedDetection* categorized,
                    const std::optional<HypothesisScatter>& scatter,
                    const std::string& detection_id,
                    const Revisit& revisit);
  // The grown gate into the detection's association scope.
  void ApplyRevisit(const Revisit& revisit,
                    internal::AssociationScope* scope) const;
  // Sets revisit_pending_ where the detection went to the object its grown
  // gate reached, in a place last seen before the window.
  void NoteRevisit(const Revisit& revisit, int object);
  // What a declared sigma_t of the class is multiplied by (1: the claims
  // hold; ObjectEdges::ApplyNoise).
  double ClaimFactorT(const std::string& class_name) const;
  // A detection that declares its sigma, or is weighed by its hypotheses'
  // scatter, as a test of the claim and of the front end's step
  // (claim_pairs.h).
  void SampleClaim(int k,
                   const DetectionInput& detection,
                   const CategorizedDetection* categorized,
                   const std::optional<HypothesisScatter>& scatter);
  int AddSingleOrMultiHypothesis(
      int k,
      const DetectionInput& detection,
      const std::optional<HypothesisScatter>& scatter,
      const Matrix6d& sqrt_info,
      const Revisit& revisit);
  int AddSymba(int k,
               const DetectionInput& detection,
               const CategorizedDetection& cat,
               const std::optional<HypothesisScatter>& scatter,
               const Matrix6d& sqrt_info,
               const Revisit& revisit);
  // The position noise the association gate takes for a detection of
  // `class_name` without sigmas: its scatter held to the class's white
  // part, or the class's estimate (nullopt: gate_position alone).
  std::optional<double> GateSigmaT(
      const std::string& class_name,
      const std::optional<HypothesisScatter>& scatter) const;
  std::optional<double> GateSigmaT(
      const std::string& class_name,
      const std::optional<double>& scatter_sigma_t) const;
  // Each class's noise after a keyframe; rebuilds the edges of a class whose
  // noise moved by more than noise_update_ratio.
  void UpdateDetectionNoise(const KeyframeInput& input);

  // The end of a solve: re-anchoring, statistics and the report.
  Status Finish(const char* what,
                const internal::SolveOutcome& outcome,
                const std::chrono::steady_clock::time_point& start,
                SolveReport* report);
  // Discrete objects whose axis drifted far from their anchor get a new
  // one and their edges rebuilt.
  void ReanchorDriftedObjects();
  MapObjectEstimate EstimateOf(const internal::ObjectState& object) const;
  // Loop closures (loop_closure.cc). `closure` of keyframe index k, checked
  // already; `prefix` starts the error messages.
  Status CheckLoopClosure(int k,
                          const LoopClosureInput& closure,
                          const std::string& prefix) const;
  LoopClosureReport CloseLoop(int k, const LoopClosureInput& closure);
  // The report of a closure of keyframe k that waits for a solve.
  LoopClosureReport WaitingReport(int k, const LoopClosureInput& closure) const;
  // The keyframes' loop closures waiting for their window solve.
  void ClosePendingLoops();
  // The keyframe graph optimised, every keyframe, object, point and prior
  // moved with it (the part of a loop closure after its constraint), unless
  // it would move keyframe k by less than `min_correction_m`.
  void MovePastByGraph(int k,
                       double min_correction_m,
                       LoopClosureReport* report);
  // After a window solve whose keyframe revisited a place last seen before
  // the window (revisit_pending_): the keyframe graph moves the past as a
  // loop closure would, without a constraint (the objects' edges close it),
  // where it moves the newest keyframe by at least one motion step's
  // translation noise. Whether it moved anything.
  bool MovePastForRevisit();
  // Loops found from the objects (object_loops.cc): after a window solve
  // that follows an object's confirmation, a loop closed where the recent
  // objects match earlier ones (CloseLoopFromObjects), then the duplicates
  // that lie on earlier objects merged (MergeRevisitedDuplicates); true if
  // either changed the map.
  bool DetectObjectLoop();
  // After a solve whose closures or revisit moved the past (past_moved_):
  // every pair of copies of one object the move brought together, wherever
  // the camera is now, merged (MergeRevisitedDuplicates over every object);
  // true if one was.
  bool MergeDuplicatesTheMoveJoined();
  bool CloseLoopFromObjects();
  // Each confirmed object first detected recently or detected by the
  // newest keyframe (with `every_object`, each confirmed object) that has
  // one copy (OneCopyOf) whose one copy it is, is merged with it (the
  // later-made into the earlier-made); returns how many. The pairs of a
  // class are compared by distance first (gate_position), so a pass costs
  // the squares of the classes' object counts in distance tests.
  int MergeRevisitedDuplicates(bool every_object = false);
  // The one other confirmed object of object o's class and type that it
  // is by the association gates (SameObject) and no keyframe detected
  // together with it, not both of a loaded map; -1 if none or several.
  int OneCopyOf(int o) const;
  // Whether a and b are one object by the association gates: positions
  // within gate_sigmas of their uncertainty (PositionSigma) and
  // gate_position, and rotation (gate_rotation), axis (gate_axis) or one
  // pair of angles (gate_angle) as their type has.
  bool SameObject(const internal::ObjectState& a,
                  const internal::ObjectState& b) const;
  // Object o's position noise from its detections (m): their sigma_t as
  // the association takes it, over sqrt(keyframes that detected it).
  double PositionSigma(const internal::ObjectState& o) const;
  struct LoopCandidates {
    std::vector<MapObjectEstimate> recent;  // first detected recently
    // Last detected before them, or a loaded map's not detected yet.
    std::vector<MapObjectEstimate> earlier;
  };
  LoopCandidates ObjectLoopCandidates() const;
  // The last keyframe (index) that detected a loaded map's object; -1 if
  // none did.
  int LastKeyframeOnLoadedObjects() const;
  // Whether `correction` (T_wc <- correction T_wc) of keyframe `later` is
  // within loop_drift_factor times the drift the camera motion could have
  // made since keyframe `earlier` (and the matcher's gates).
  bool WithinPossibleDrift(int earlier,
                           int later,
                           const Rigid3d& correction) const;
  // Duplicate `from` merged into `into` (ObjectMap::MergeInto), its
  // observations added to `into` with its angles; false (nothing done) if
  // their symmetry types differ.
  bool MergeDuplicate(int from, int into);
  // The confirmed objects as the keyframe graph holds them (by index; the
  // others without keyframes).
  std::vector<internal::GraphObject> GraphObjects() const;
  // The keyframe graph as it stands (MakeKeyframeGraph of every keyframe,
  // the window's first, the loops and *objects = GraphObjects()), for its
  // covariances, with the options to compute them with: the objects whose
  // rotation it does not measure held, and with calibrate_covariances each
  // edge's noise as its group's residuals show it (CalibrateGraphNoise;
  // the groups kept for CovarianceNoise()).
  PoseGraph CurrentKeyframeGraph(std::vector<internal::GraphObject>* objects,
                                 PoseGraphCovarianceOptions* options) const;
  // Each object's rigid move: with the window if only the window saw it
  // (keyframes from window_begin on), else to its optimised vertex, or by
  // the mean move of its detectors if it is not in the graph; identity for
  // one never detected or dropped.
  std::vector<Rigid3d> ObjectMoves(
      const std::vector<Rigid3d>& moves,
      const std::vector<internal::GraphObject>& objects,
      const std::vector<Rigid3d>& object_poses,
      int window_begin) const;
  // Every keyframe k moved by moves[k] (T_wc <- moves[k] T_wc), object o by
  // object_moves[o], each point with the window (seen from it) or by the
  // mean move of its first and last observer, and every prior with them.
  void MovePast(const std::vector<Rigid3d>& moves,
                const std::vector<Rigid3d>& object_moves,
                int window_begin);

  // The parts, each constructed after those it refers to; the trajectory
  // and the object map only keep the graph's address until it exists.
  internal::Trajectory trajectory_;
  internal::ObjectMap map_;
  internal::FactorGraph graph_;
  internal::ObjectEdges edges_;
  bool map_loaded_ = false;  // LoadMap succeeded (once per backend)
  std::vector<internal::LoopConstraint> loops_;
  std::vector<std::pair<int, LoopClosureInput>> pending_loops_;
  // A detection of the newest keyframe was associated through a gate grown
  // since its place was last seen before the window (NoteRevisit).
  bool revisit_pending_ = false;
  // MovePastByGraph moved the past (a closure, the host's between solves
  // included, or a revisit) since MergeDuplicatesTheMoveJoined last looked.
  bool past_moved_ = false;
  // Keyframes before this index have been through a solve: a closure of a
  // later one waits for the next (its pose is a prediction until then).
  int solved_keyframes_ = 0;
  // ObjectMap::confirmations() when DetectObjectLoop last looked.
  int confirmations_checked_ = 0;
  // Duplicates a loop from the objects recognised but could not merge
  // (their type differs): never matched again.
  std::set<int> unmerged_duplicates_;
  // One categorization per detection of the keyframe being added, reused
  // between keyframes.
  std::vector<CategorizedDetection> categorized_;
  // The hypotheses' scatter of each detection of the keyframe being added
  // that is weighed by it (internal::UsableScatter).
  std::vector<std::optional<HypothesisScatter>> scatters_;
  // The noise groups the last covariances from the keyframe graph were
  // computed with (CurrentKeyframeGraph); empty before any.
  mutable std::vector<CovarianceNoiseGroup> covariance_noise_;
};

}  // namespace symba

#endif  // SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
