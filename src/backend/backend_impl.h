// Backend::Impl: the backend's state and the steps of AddKeyframe and the
// solves. Its member functions are defined by topic:
//   backend.cc      AddKeyframe, the solves, read-back
//   detections.cc   a keyframe's detections, per method
//   keyframe_factors.cc  a keyframe's initial pose, camera motion factor
//                   and point observations
//   map_objects.cc  the object lifecycle: creation, upgrades, observations,
//                   re-anchoring and building object edges
// The factors, the window and the solves are the factor graph's
// (factor_graph.h). Association (association.h), detection observations
// (detection_observations.h) and input checks (keyframe_validation.h) are
// units of their own (docs/architecture.md). Not installed.
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
#include "backend/factor_graph.h"
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

  // The end of a solve: re-anchoring, statistics and the report.
  Status Finish(const char* what,
                const internal::SolveOutcome& outcome,
                const std::chrono::steady_clock::time_point& start,
                SolveReport* report);

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
  MapObjectEstimate EstimateOf(const internal::ObjectState& object) const;
  void ReanchorDriftedObjects();
  std::unique_ptr<ceres::CostFunction> BuildObjectEdge(
      internal::KeyframeState* keyframe,
      internal::ObjectState* object,
      const internal::ObjectObservation& observation,
      std::vector<double*>* blocks) const;

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
  // After the keyframes, objects and points it refers to.
  internal::FactorGraph graph_;
};

}  // namespace symba

#endif  // SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
