// Backend::Impl: the backend's state and the steps of AddKeyframe and the
// solves. Its member functions are defined by topic:
//   backend.cc      AddKeyframe, the solves, read-back
//   window.cc       keyframes leaving the window: marginalisation and the
//                   prior
//   detections.cc   a keyframe's detections, per method
//   keyframe_factors.cc  a keyframe's initial pose, camera motion factor
//                   and point observations
//   map_objects.cc  the object lifecycle: creation, upgrades, observations,
//                   re-anchoring and building object edges
// Association (association.h), detection observations
// (detection_observations.h), input checks (keyframe_validation.h) and the
// persistent Ceres problem (window_problem.h) are units of their own. Not
// installed.
#ifndef SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
#define SYMBA_SRC_BACKEND_BACKEND_IMPL_H_

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include "backend/association.h"
#include "backend/backend_state.h"
#include "backend/detection_noise.h"
#include "backend/marginalization.h"
#include "backend/window_problem.h"
#include "symba/backend/backend.h"
#include "symba/manifolds/axis_manifold.h"

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
  int WindowStart() const;

  std::vector<KeyframeEstimate> Keyframes() const;
  std::vector<MapObjectEstimate> Objects() const;
  std::optional<KeyframeEstimate> Keyframe(KeyframeId id) const;
  std::optional<MapObjectEstimate> Object(ObjectId id) const;
  std::vector<ClassNoiseEstimate> Noise() const;

  const BackendOptions options_;
  std::vector<DetectionAssignment> assignments_;
  BackendStatistics statistics_;

 private:
  // Keyframe pose initialisation and camera factors (keyframe_factors.cc).
  Rigid3d InitialPose(const KeyframeInput& input) const;
  // The same from the front end alone (KeyframeState::T_wc_chain).
  Rigid3d ChainPose(const KeyframeInput& input) const;
  void AddCameraFactors(int k, const KeyframeInput& input);
  void AddPointObservations(int k, const KeyframeInput& input);

  // Detections, per method (detections.cc). CategorizeDetections runs before
  // anything of the keyframe is added, so a failing detection adds nothing.
  const ClassPrior* PriorOf(const std::string& class_name) const;
  Status CategorizeDetections(const KeyframeInput& input);
  void AddDetection(int k,
                    const DetectionInput& detection,
                    const CategorizedDetection* categorized,
                    const std::string& detection_id);
  int AddSingleOrMultiHypothesis(int k,
                                 const DetectionInput& detection,
                                 const Matrix6d& sqrt_info);
  int AddSymba(int k,
               const DetectionInput& detection,
               const CategorizedDetection& cat,
               const Matrix6d& sqrt_info);
  // symba: a flip joins the object without an edge, or upgrades it once
  // the evidence suffices (upgrade_evidence.h). True if it upgraded.
  bool RecordFlip(int o, int k, const internal::SymbaMatch& match);
  // The detection's noise as given or the options' default, and the
  // position noise the association gates it with.
  void SetObservationNoise(const DetectionInput& detection,
                           internal::ObjectObservation* observation) const;
  std::optional<double> GateSigma(const DetectionInput& detection) const;

  // The solve's free set and active factors (backend.cc). A factor is in
  // the map unless it was retired or its object is not confirmed.
  bool InMap(const internal::FactorRecord& record) const;
  // condition: the window keyframes' factors and every factor of what they
  // observe (grows with the run).
  std::vector<int> ConditionedFactors(int first_free) const;
  // marginalize, drop: the window keyframes' factors only.
  std::vector<int> WindowFactors(int first_free) const;
  // batch: every factor in the map.
  std::vector<int> AllFactors() const;
  // Sets the keyframes the problem holds constant or free (free: index >=
  // first_free, not the gauge); returns the free count. O(problem size).
  int SetKeyframeFreedom(int first_free, int gauge);
  Status Solve(const char* what,
               int max_iterations,
               int free_keyframes,
               const std::chrono::steady_clock::time_point& start,
               SolveReport* report);

  // The window (window.cc). Keyframes before marginalized_until_ have left
  // the window: their factors are marginalised into the prior (marginalize)
  // or dropped (drop).
  void LeaveWindow(int k);
  // Frees what keyframe k's `left` factors hold that no window solve needs
  // again: its factor list, and without keep_history the factors' cost
  // functions and their observations' hypotheses.
  void ForgetLeftKeyframe(int k, const std::vector<int>& left);
  // The factors of a point or object (`own`: its blocks) from a keyframe
  // that leaves the window, conditioned on everything else and merged with
  // `share` of their information into its own prior (*prior_factor).
  void MergeIntoOwnPrior(const std::vector<int>& factors,
                         const std::vector<double*>& own,
                         double share,
                         int object,
                         int point,
                         int* prior_factor);
  // Marginalises `terms` (`describe` says which blocks are the entity's) and
  // stores the result as the entity's prior in place of *prior_factor.
  void ReplaceOwnPrior(const std::vector<internal::MarginalizationTerm>& terms,
                       const internal::BlockDescriber& describe,
                       int object,
                       int point,
                       int* prior_factor);
  // Marginalises `blocks` out of object o's prior (their information on
  // its other blocks stays); nothing if the prior has none of them.
  void RemoveFromObjectPrior(int o, const std::vector<double*>& blocks);
  internal::BlockDescription DescribeForPrior(const double* block) const;
  static std::vector<double*> ObjectBlocks(internal::ObjectState& object);

  // Map objects (map_objects.cc).
  int CreateObject(const std::string& class_name, SymmetryType type, int k);
  // A detection of object o in keyframe k, reported as assignment a.
  void NoteDetection(int o, int k, int assignment);
  // Confirms tentative objects with enough keyframes and drops those whose
  // timeout passed (bounded by the tentative objects).
  void UpdateTentativeObjects(int k);
  void DropObject(int o);
  // Widens the view cone (bearing, depth) detections were seen in.
  void NoteViewCone(const Eigen::Vector3d& t_co);
  // Counts the keyframe for every confirmed object in view and drops those
  // detected in too few of their views (min_support).
  void PruneUnsupportedObjects(int k);
  // A detection of object o in keyframe k (its position, and its rotation
  // where it has one) as noise samples of the class, taken at the front
  // end's pose of the keyframe (detection_noise.h).
  void SampleNoise(int o,
                   int k,
                   const Eigen::Vector3d& t_co,
                   const std::optional<Eigen::Quaterniond>& R_co);
  // The association scope of a detection in keyframe k.
  internal::AssociationScope Scope(const DetectionInput& detection,
                                   int k,
                                   const Eigen::Vector3d& t_co) const;
  // Each class's noise after a keyframe; rebuilds the edges of a class whose
  // noise moved by more than noise_update_ratio.
  void UpdateDetectionNoise(const std::vector<std::string>& classes);
  int CreateSymbaObject(const std::string& class_name,
                        const CategorizedDetection& cat,
                        const Rigid3d& T_wc,
                        int k);
  void UpgradeObject(int o,
                     SymmetryType type,
                     const Eigen::Vector3d& a_o,
                     const internal::UpgradeRecord& record);
  // The angle of discrete object o that `observation` (seen from T_wc)
  // constrains: the nearest within gate_angle; else, if `may_fold` (the
  // detection shows one mode) and the class prior gives the order, the
  // nearest modulo 2 pi / order, the observation then turned by that
  // multiple about a_o; else a new angle.
  int MatchOrAddAngle(int o,
                      const Rigid3d& T_wc,
                      bool may_fold,
                      internal::ObjectObservation* observation);
  // The class prior's symmetry order when it applies to object o (discrete
  // prior, order >= 2, axis along the object's a_o), else 0.
  int KnownOrder(int o) const;
  void AddObservation(int o, internal::ObjectObservation observation);
  // The edge of object o's observation i.
  void AddObjectFactor(int o, int i);
  // Rebuilds the edges of the observations still in the window (all under
  // condition); the older ones become stale (ObjectState).
  void RebuildObjectFactors(int o);
  void RebuildObjectFactors(int o, int begin, int end);
  // The batch solve first rebuilds every stale edge.
  void RebuildStaleObjectFactors();
  // The first observation of object o whose keyframe has not left the
  // window for good (0 under condition). O(log observations).
  int FirstLiveObservation(int o) const;
  MapObjectEstimate EstimateOf(const internal::ObjectState& object) const;
  void ReanchorDriftedObjects();
  std::unique_ptr<ceres::CostFunction> BuildObjectEdge(
      internal::KeyframeState* keyframe,
      internal::ObjectState* object,
      const internal::ObjectObservation& observation,
      std::vector<double*>* blocks) const;

  // Registers a factor with the entities it touches (backend.cc).
  int AddFactor(internal::FactorRecord record);

  std::optional<PinholeIntrinsics> intrinsics_;
  std::map<std::string, ClassPrior> class_priors_;
  std::unique_ptr<ceres::LossFunction> object_loss_;
  std::unique_ptr<ceres::LossFunction> point_loss_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
  AxisManifold axis_manifold_;

  std::vector<std::unique_ptr<internal::KeyframeState>> keyframes_;
  internal::ObjectList objects_;
  std::vector<std::unique_ptr<internal::PointState>> points_;
  std::unordered_map<int64_t, int> point_index_;
  int last_frontend_keyframe_ = -1;
  // One categorization per detection of the keyframe being added, reused
  // between keyframes.
  std::vector<CategorizedDetection> categorized_;
  // Real detectors: tentative objects (indices), objects per class, the
  // noise estimator and the noise each class's edges are built with.
  std::vector<int> tentative_;
  double view_cone_cos_ = 1.0;  // cos of the widest detection bearing
  double view_depth_ = 0.0;     // the largest detection distance (m)
  std::map<std::string, std::vector<int>> objects_by_class_;
  internal::DetectionNoiseEstimator noise_;
  std::map<std::string, internal::ClassNoise> applied_noise_;
  internal::WindowProblem problem_;
  int marginalized_until_ = 0;
  internal::MarginalizationOptions marginalization_;
};

}  // namespace symba

#endif  // SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
