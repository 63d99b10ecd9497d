// Backend: the object-SLAM estimation backend a SLAM system embeds
// (docs/backend.md). Keyed by ids (symba/backend/ids.h), never by pointers.
//
//   AddKeyframe      initialise the keyframe's pose from the previous
//                    optimised pose and the front end's relative motion (or
//                    odometry), add its camera factors and point
//                    observations, categorise each detection, warp it into
//                    the world, associate it with a map object or create one,
//                    and add its object edges (method notes Sec. 2-5).
//                    Returns the keyframe's assignments.
//   OptimizeWindow   the last K = window_size keyframes and everything they
//                    observe are free; older keyframes are marginalised into
//                    priors, held constant or dropped, as
//                    options().window_policy says (backend_options.h;
//                    docs/backend.md "The window" is where it is explained).
//   OptimizeBatch    everything free but the first keyframe, every factor
//                    ever added (never the priors); needs
//                    options().keep_history once keyframes left the window.
//   Keyframe / Object          one estimate by id (cheap: for every frame)
//   Keyframes / Objects / Assignments   every estimate (O(run))
//   SaveMap / LoadMap          a map that lasts (docs/map-format.md)
//
// The Ceres problem persists: a window solve adds the factors that became
// active and removes those that left the window; nothing is rebuilt per
// keyframe. The three methods (symba, mh, sh) share all of this code and
// differ only in how a detection is turned into edges and associated.
// Not thread-safe: call from one thread (Ceres may use several inside).
#ifndef SYMBA_BACKEND_BACKEND_H_
#define SYMBA_BACKEND_BACKEND_H_

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "symba/backend/backend_options.h"
#include "symba/backend/covariance_noise.h"
#include "symba/backend/estimates.h"
#include "symba/backend/keyframe_covariance.h"
#include "symba/backend/keyframe_input.h"
#include "symba/backend/loop_closure.h"
#include "symba/backend/relocalization.h"
#include "symba/backend/saved_map.h"
#include "symba/categorization/categorize.h"
#include "symba/common/status.h"
#include "symba/geometry/pinhole_intrinsics.h"

namespace symba {

namespace internal {
class Relocalizer;
}  // namespace internal

// Statistics of one solve.
struct SolveReport {
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
  bool converged = false;
  int free_keyframes = 0;
  int residual_blocks = 0;  // including the prior
  int parameter_blocks = 0;
  int prior_size = 0;  // the prior's tangent size (0: none)
};

// Counters over the backend's life.
struct BackendStatistics {
  int keyframes = 0;
  int detections = 0;
  int objects = 0;  // confirmed map objects
  int points = 0;
  int object_upgrades = 0;  // asymmetric map objects that became symmetric
  // asymmetric map objects turned to the rotation their later detections
  // agree on (their first was a detector's confusion)
  int objects_turned = 0;
  int objects_dropped = 0;    // tentative objects never confirmed
  int rotation_outliers = 0;  // symba: flips that did not (yet) upgrade or turn
  // symba: discrete observations read modulo 2 pi / order (class prior)
  int folded_angles = 0;
  int marginalized_keyframes = 0;   // keyframes that left the window
  int ambiguous_edges_dropped = 0;  // mixtures not frozen into the prior
  int solves = 0;
  double solve_seconds = 0.0;
  int solve_iterations = 0;
  // observations of a map point behind the camera's initial pose, left out
  int point_observations_behind = 0;
  int loop_closures = 0;  // given by the host or found from the objects
  int loop_closures_moved_past = 0;  // ... that moved the past
  double loop_closure_seconds = 0.0;
  int object_loop_closures = 0;  // closed loops symba found from the objects
  int objects_merged = 0;        // duplicates merged into the objects they are
  // places revisited a little off (associated again through a gate grown
  // since they were last seen before the window) whose keyframe graph then
  // moved the past, as a loop closure does but without one
  int revisits_moved_past = 0;
};

class Backend {
 public:
  // `intrinsics` is needed only if keyframes carry point observations;
  // `class_priors` (may be empty) refine categorisation per class name.
  static Status Create(const BackendOptions& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       const std::map<std::string, ClassPrior>& class_priors,
                       std::unique_ptr<Backend>* backend);
  ~Backend();
  Backend(const Backend&) = delete;
  Backend& operator=(const Backend&) = delete;

  // Validates the keyframe first: on an error nothing is added. On success
  // `assignments` (if not null) holds one entry per detection of the
  // keyframe, in input order (an object -1: the detection was refused).
  Status AddKeyframe(const KeyframeInput& keyframe,
                     std::vector<DetectionAssignment>* assignments = nullptr);
  // A relative pose between two keyframes the host system knows (its own
  // loop closure; docs/loop-closure.md): `closure.T` is `keyframe`'s pose
  // in `closure.keyframe`'s frame. Both must be known and different. If the
  // other keyframe has left the window, the keyframe graph (every
  // keyframe, linked by its estimated motion) is optimised with every loop
  // closure so far and the past moves with it: keyframes, objects, points
  // and the priors marginalisation left. The constraint then stays in the
  // window's solves. A KeyframeInput's loop_closures are added this way
  // right after the keyframe. On an error nothing changes.
  Status AddLoopClosure(KeyframeId keyframe,
                        const LoopClosureInput& closure,
                        LoopClosureReport* report = nullptr);
  Status OptimizeWindow(SolveReport* report = nullptr);
  Status OptimizeBatch(SolveReport* report = nullptr);

  // The keyframe's current estimate (O(log keyframes)); nullopt for an
  // unknown id.
  std::optional<KeyframeEstimate> Keyframe(KeyframeId id) const;
  // A confirmed map object's current estimate (O(its angles)); nullopt for
  // an unknown, tentative or dropped object.
  std::optional<MapObjectEstimate> Object(ObjectId id) const;
  std::vector<KeyframeEstimate> Keyframes() const;
  std::vector<MapObjectEstimate> Objects() const;
  const std::vector<DetectionAssignment>& Assignments() const;
  // Every loop closure so far: those closed, in the order they were
  // closed, then those still waiting for a solve (waiting true, message
  // "waits for the next solve").
  std::vector<LoopClosureReport> LoopClosures() const;
  BackendStatistics Statistics() const;
  // Per class with detections, sorted by name: the detection noise
  // estimated so far and what the class's detections without a sigma are
  // weighed with (empty without estimate_noise).
  std::vector<ClassNoiseEstimate> Noise() const;
  // The noise the front end stated for the camera's motion factors, and
  // the objects' test of it: the factor each group of steps stated alike
  // was weighed with.
  MotionNoiseReport MotionNoise() const;
  // Every confirmed map object's covariance at the current estimate
  // (docs/backend.md "Covariances"): from the last solve, or for an object
  // outside it from its marginalised observations; an object neither
  // covers (no solve yet, or outside the window without a prior) is left
  // out. Costs a factorisation of the last solve's problem, which it first
  // syncs with the edges rebuilt since (so a call between solves may change
  // the next solve's result at round-off level). Fails if that problem is
  // rank deficient.
  Status ObjectCovariances(std::vector<MapObjectCovariance>* covariances);
  // The noise each group of the keyframe graph's edges was taken to have by
  // the last ObjectCovariances or KeyframeCovariances that used the graph
  // (docs/backend.md "Covariances"; BackendOptions::calibrate_covariances);
  // empty before any.
  std::vector<CovarianceNoiseGroup> CovarianceNoise() const;
  // The keyframes `ids`' covariances (in that order), each its marginal in
  // the keyframe graph (docs/backend.md "Covariances": every keyframe, the
  // camera motion, the loop closures and the objects' detections; no map
  // points), keyframe 0 the gauge. Costs a factorisation of that graph and
  // a solve per requested keyframe; changes nothing. Fails (nothing
  // written) for an unknown id or a graph that cannot be factored.
  Status KeyframeCovariances(
      const std::vector<KeyframeId>& ids,
      std::vector<KeyframeCovariance>* covariances) const;
  // The map as it stands (docs/map-format.md): the confirmed objects with
  // their covariances (without any where ObjectCovariances fails) and each
  // class's detection noise. Costs what ObjectCovariances costs.
  Status SaveMap(SavedMap* map);
  // Starts the run from a saved map, before the first keyframe: its
  // objects become confirmed map objects with their ids, each keeping its
  // covariance as a prior, and its classes' noise weighs their detections
  // until the run's own estimate moves away from it. Without `relocalize`
  // keyframes must then be given in the map's frame. With it their frame is
  // unknown (docs/relocalization.md): the run is estimated in its own frame
  // until the objects it mapped match the map's after a window solve, then
  // its keyframes are estimated again in the map's frame and associated
  // with the loaded objects. Until then Keyframe(s), Statistics and Noise
  // describe the search in the run's own frame, Objects the loaded map,
  // Assignments nothing (AddKeyframe's are pending: object -1).
  // Fails, changing nothing, after a keyframe or a successful LoadMap, or
  // on an invalid map (ids, numbers, poses) or options.
  Status LoadMap(
      const SavedMap& map,
      const std::optional<RelocalizationOptions>& relocalize = std::nullopt);
  // Where relocalisation stands; nullopt unless LoadMap was asked for it.
  std::optional<RelocalizationReport> Relocalization() const;
  // Ends a search that has not matched (as max_keyframes would): the run
  // goes on in its own frame without the map. Nothing otherwise. A run
  // whose keyframes end while searching calls it to give results in one
  // frame (symba replay does).
  void GiveUpRelocalization();
  const BackendOptions& options() const;

 private:
  class Impl;
  explicit Backend(std::unique_ptr<Impl> impl);
  bool Searching() const;
  // What keyframes are estimated in: the relocalisation's search until it
  // matched, this backend's own state otherwise.
  const Impl& Run() const;
  Impl& Run();
  Status FinishRelocalization(SolveReport* report);
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<internal::Relocalizer> relocalizer_;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_BACKEND_H_
