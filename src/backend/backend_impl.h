// Backend::Impl: the backend's state and the steps of AddKeyframe and the
// solves. Its member functions are defined by topic:
//   backend.cc      AddKeyframe, detections per method, solves, read-back
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
#include "backend/window_problem.h"
#include "symba/backend/backend.h"
#include "symba/manifolds/axis_manifold.h"

namespace symba {

class Backend::Impl {
 public:
  Impl(const BackendOptions& options,
       const std::optional<PinholeIntrinsics>& intrinsics,
       const std::map<std::string, ClassPrior>& class_priors);

  Status AddKeyframe(const KeyframeInput& input);
  Status Optimize(int first_free, int max_iterations, SolveReport* report);
  int WindowStart() const;

  std::vector<KeyframeEstimate> Keyframes() const;
  std::vector<MapObjectEstimate> Objects() const;

  const BackendOptions options_;
  std::vector<DetectionAssignment> assignments_;
  BackendStatistics statistics_;

 private:
  // Keyframe pose initialisation and camera factors (keyframe_factors.cc).
  Rigid3d InitialPose(const KeyframeInput& input) const;
  void AddCameraFactors(int k, const KeyframeInput& input);
  void AddPointObservations(int k, const KeyframeInput& input);

  // Detections, per method (backend.cc). CategorizeDetections runs before
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

  // The solve's free set and active factors (backend.cc).
  void MarkActive(int first_free,
                  std::vector<char>* keyframe_free,
                  std::vector<char>* active) const;
  int FixKeyframesOutsideWindow(const std::vector<char>& keyframe_free);

  // Map objects (map_objects.cc).
  int CreateObject(const std::string& class_name, SymmetryType type);
  int CreateSymbaObject(const std::string& class_name,
                        const CategorizedDetection& cat,
                        const Rigid3d& T_wc);
  void UpgradeObject(int o, SymmetryType type, const Eigen::Vector3d& a_o);
  int MatchOrAddAngle(int o, const Eigen::Quaterniond& R_wo);
  void AddObservation(int o, internal::ObjectObservation observation);
  void AddObjectFactor(int o, const internal::ObjectObservation& observation);
  void RebuildObjectFactors(int o);
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
  internal::WindowProblem problem_;
};

}  // namespace symba

#endif  // SYMBA_SRC_BACKEND_BACKEND_IMPL_H_
