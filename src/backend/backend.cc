#include "symba/backend/backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include <ceres/ceres.h>

#include "backend/backend_state.h"
#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/continuous_object_edge.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/factors/point_depth_factor.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/factors/reprojection_factor.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/swing_twist.h"
#include "symba/manifolds/axis_manifold.h"

namespace symba {

using internal::FactorRecord;
using internal::KeyframeState;
using internal::ObjectObservation;
using internal::ObjectState;
using internal::PointState;

namespace {

constexpr double kUnitTolerance = 1e-3;  // as the log format

// Angle between two axes, ignoring their signs, in [0, pi/2].
double AxisDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

Status CheckPose(const Rigid3d& T, const std::string& what) {
  if (!T.q.coeffs().allFinite() || !T.t.allFinite()) {
    return Status::Error(what + ": pose is not finite");
  }
  if (std::abs(T.q.norm() - 1.0) > kUnitTolerance) {
    return Status::Error(what + ": quaternion is not unit (|q| = " +
                         std::to_string(T.q.norm()) + ")");
  }
  return Status::Ok();
}

Status CheckSigma(const std::optional<double>& sigma, const std::string& what) {
  if (sigma && !(std::isfinite(*sigma) && *sigma > 0.0)) {
    return Status::Error(what + " must be positive and finite");
  }
  return Status::Ok();
}

Rigid3d Normalized(Rigid3d T) {
  T.q.normalize();
  return T;
}

// A detection's hypotheses as edge components, for the given indices.
std::vector<PoseComponent> Components(const std::vector<PoseHypothesis>& hyps,
                                      const std::vector<int>& indices,
                                      const Matrix6d& sqrt_info) {
  std::vector<PoseComponent> components;
  components.reserve(indices.size());
  for (int j : indices) {
    components.push_back({Normalized(hyps[j].T_co), sqrt_info, hyps[j].weight});
  }
  return components;
}

// One mode's hypotheses merged into one component at `T_co` (the mode's
// mean from the categorization), weighted by their total weight.
std::vector<PoseComponent> MergedComponent(
    const std::vector<PoseHypothesis>& hyps,
    const std::vector<int>& members,
    const Rigid3d& T_co,
    const Matrix6d& sqrt_info) {
  double weight = 0.0;
  for (int j : members) weight += hyps[j].weight;
  return {{Normalized(T_co), sqrt_info, weight}};
}

int HighestWeight(const std::vector<PoseHypothesis>& hyps,
                  const std::vector<int>& indices) {
  int best = indices.front();
  for (int j : indices) {
    if (hyps[j].weight > hyps[best].weight) best = j;
  }
  return best;
}

std::vector<int> AllIndices(size_t n) {
  std::vector<int> indices(n);
  for (size_t j = 0; j < n; ++j) indices[j] = static_cast<int>(j);
  return indices;
}

std::unique_ptr<ceres::LossFunction> MakeLoss(LossType type, double scale) {
  switch (type) {
    case LossType::kNone:
      return nullptr;
    case LossType::kHuber:
      return std::make_unique<ceres::HuberLoss>(scale);
    case LossType::kCauchy:
      return std::make_unique<ceres::CauchyLoss>(scale);
  }
  return nullptr;
}

}  // namespace

class Backend::Impl {
 public:
  Impl(const BackendOptions& options,
       const std::optional<PinholeIntrinsics>& intrinsics,
       const std::map<std::string, ClassPrior>& class_priors)
      : options_(options),
        intrinsics_(intrinsics),
        class_priors_(class_priors),
        object_loss_(MakeLoss(options.object_loss, options.object_loss_scale)),
        point_loss_(
            std::make_unique<ceres::HuberLoss>(options.point_loss_scale)),
        problem_(ProblemOptions()) {}

  Status AddKeyframe(const KeyframeInput& input);
  Status Optimize(int first_free, int max_iterations, SolveReport* report);
  int WindowStart() const {
    return std::max(0,
                    static_cast<int>(keyframes_.size()) - options_.window_size);
  }

  std::vector<KeyframeEstimate> Keyframes() const;
  std::vector<MapObjectEstimate> Objects() const;

  const BackendOptions options_;
  std::vector<DetectionAssignment> assignments_;
  BackendStatistics statistics_;

 private:
  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options options;
    options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.enable_fast_removal = true;
    return options;
  }

  // Input checks (everything before anything is added).
  Status ValidateKeyframe(const KeyframeInput& input) const;

  // Keyframe pose initialisation and camera factors.
  Rigid3d InitialPose(const KeyframeInput& input) const;
  void AddCameraFactors(int k, const KeyframeInput& input);
  void AddPointObservations(int k, const KeyframeInput& input);

  // Detections, per method.
  Status AddDetection(int k,
                      const DetectionInput& detection,
                      const std::string& detection_id);
  int AddSingleOrMultiHypothesis(int k,
                                 const DetectionInput& detection,
                                 const Matrix6d& sqrt_info);
  Status AddSymba(int k,
                  const DetectionInput& detection,
                  const Matrix6d& sqrt_info,
                  int* object,
                  SymmetryType* type);

  // Association.
  int FindSixDofMatch(const std::string& class_name,
                      const std::vector<Rigid3d>& T_wo_candidates) const;
  struct SymbaMatch {
    int object = -1;
    bool upgrade = false;  // an asymmetric object that must become symmetric
    Eigen::Vector3d a_o = Eigen::Vector3d::Zero();  // its axis, if so
  };
  SymbaMatch FindSymbaMatch(const Rigid3d& T_wc,
                            const CategorizedDetection& detection,
                            const std::string& class_name,
                            const std::vector<PoseHypothesis>& hyps) const;
  int MatchOrAddAngle(ObjectState* object, const Eigen::Quaterniond& R_wo);

  // Map objects.
  int CreateObject(const std::string& class_name, SymmetryType type);
  void UpgradeObject(int o, SymmetryType type, const Eigen::Vector3d& a_o);
  void AddObservation(int o, ObjectObservation observation);
  void RebuildObjectFactors(int o);
  void ReanchorDriftedObjects();
  std::unique_ptr<ceres::CostFunction> BuildObjectEdge(
      const ObjectState& object,
      const ObjectObservation& observation,
      std::vector<double*>* blocks);

  // Factors and the persistent problem.
  int AddFactor(FactorRecord record);
  void RetireFactor(int f);
  void EnsureBlock(double* block, int size);

  std::optional<PinholeIntrinsics> intrinsics_;
  std::map<std::string, ClassPrior> class_priors_;
  std::unique_ptr<ceres::LossFunction> object_loss_;
  std::unique_ptr<ceres::LossFunction> point_loss_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
  AxisManifold axis_manifold_;

  std::vector<std::unique_ptr<KeyframeState>> keyframes_;
  std::vector<std::unique_ptr<ObjectState>> objects_;
  std::vector<std::unique_ptr<PointState>> points_;
  std::unordered_map<int64_t, int> point_index_;
  std::vector<FactorRecord> factors_;
  std::unordered_map<const double*, const ceres::Manifold*> manifolds_;
  int last_frontend_keyframe_ = -1;
  CategorizedDetection categorized_;  // reused between detections
  ceres::Problem problem_;
};

// ---------------------------------------------------------------------------
// Input checks.

Status Backend::Impl::ValidateKeyframe(const KeyframeInput& input) const {
  const std::string where = "keyframe " + std::to_string(input.id);
  if (!keyframes_.empty()) {
    const KeyframeState& last = *keyframes_.back();
    if (input.id <= last.id) {
      return Status::Error(where + ": id must be greater than the previous (" +
                           std::to_string(last.id) + ")");
    }
    if (!(input.timestamp >= last.timestamp)) {
      return Status::Error(where + ": timestamp must not decrease");
    }
  }
  if (!std::isfinite(input.timestamp)) {
    return Status::Error(where + ": timestamp is not finite");
  }
  if (keyframes_.empty() && !input.T_wc) {
    return Status::Error(where + ": the first keyframe needs T_wc");
  }
  if (!input.T_wc && !input.odometry) {
    return Status::Error(where + ": needs T_wc or odometry");
  }
  if (input.T_wc) {
    Status status = CheckPose(*input.T_wc, where + ": T_wc");
    if (!status.ok()) return status;
  }
  if (input.odometry) {
    Status status = CheckPose(input.odometry->T_prev_cur, where + ": odometry");
    if (!status.ok()) return status;
    status = CheckSigma(input.odometry->sigma_t, where + ": odometry sigma_t");
    if (!status.ok()) return status;
    status = CheckSigma(input.odometry->sigma_r, where + ": odometry sigma_r");
    if (!status.ok()) return status;
  }
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& det = input.detections[d];
    const std::string what =
        where + ": detection " + (det.id.empty() ? std::to_string(d) : det.id);
    if (det.class_name.empty()) return Status::Error(what + ": class is empty");
    if (det.hypotheses.empty()) {
      return Status::Error(what + ": has no hypotheses");
    }
    Status status = CheckSigma(det.sigma_t, what + ": sigma_t");
    if (!status.ok()) return status;
    status = CheckSigma(det.sigma_r, what + ": sigma_r");
    if (!status.ok()) return status;
    for (size_t j = 0; j < det.hypotheses.size(); ++j) {
      const std::string hyp = what + ": hypothesis " + std::to_string(j);
      status = CheckPose(det.hypotheses[j].T_co, hyp);
      if (!status.ok()) return status;
      const double w = det.hypotheses[j].weight;
      if (!(std::isfinite(w) && w > 0.0)) {
        return Status::Error(hyp + ": weight must be positive and finite");
      }
    }
  }
  if (!input.points.empty() && !intrinsics_) {
    return Status::Error(where + ": has points but no camera intrinsics");
  }
  for (const PointObservation& point : input.points) {
    const std::string what = where + ": point " + std::to_string(point.id);
    if (!point.uv.allFinite())
      return Status::Error(what + ": uv is not finite");
    if (point.depth && !(std::isfinite(*point.depth) && *point.depth > 0.0)) {
      return Status::Error(what + ": depth must be positive and finite");
    }
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Keyframes.

Rigid3d Backend::Impl::InitialPose(const KeyframeInput& input) const {
  if (keyframes_.empty()) return Normalized(*input.T_wc);
  const Rigid3d T_w_prev = keyframes_.back()->T_wc();
  if (input.odometry) {
    return Normalized(T_w_prev * Normalized(input.odometry->T_prev_cur));
  }
  // The front end's relative motion since the last keyframe it posed,
  // applied to that keyframe's optimised pose.
  if (last_frontend_keyframe_ >= 0) {
    const KeyframeState& anchor = *keyframes_[last_frontend_keyframe_];
    const Rigid3d motion =
        anchor.T_wc_frontend->Inverse() * Normalized(*input.T_wc);
    return Normalized(anchor.T_wc() * motion);
  }
  return Normalized(*input.T_wc);
}

void Backend::Impl::AddCameraFactors(int k, const KeyframeInput& input) {
  KeyframeState& kf = *keyframes_[k];
  int other = -1;
  Rigid3d T_other_cur;
  Matrix6d sqrt_info;
  if (input.odometry && k > 0) {
    other = k - 1;
    T_other_cur = Normalized(input.odometry->T_prev_cur);
    sqrt_info =
        IsotropicPoseSqrtInfo(input.odometry->sigma_t, input.odometry->sigma_r);
  } else if (input.T_wc && last_frontend_keyframe_ >= 0) {
    other = last_frontend_keyframe_;
    T_other_cur =
        keyframes_[other]->T_wc_frontend->Inverse() * Normalized(*input.T_wc);
    sqrt_info = IsotropicPoseSqrtInfo(options_.frontend_sigma_t,
                                      options_.frontend_sigma_r);
  }
  if (other < 0) return;
  KeyframeState& prev = *keyframes_[other];
  FactorRecord record;
  record.cost.reset(RelativePoseFactor::Create(T_other_cur, sqrt_info));
  record.blocks = {prev.q, prev.t, kf.q, kf.t};
  record.keyframe = k;
  record.keyframe2 = other;
  AddFactor(std::move(record));
}

void Backend::Impl::AddPointObservations(int k, const KeyframeInput& input) {
  KeyframeState& kf = *keyframes_[k];
  const Eigen::Matrix2d sqrt_info =
      Eigen::Matrix2d::Identity() / options_.point_sigma_px;
  for (const PointObservation& obs : input.points) {
    auto it = point_index_.find(obs.id);
    if (it == point_index_.end()) {
      if (!obs.depth) continue;  // a point is created from a depth
      auto point = std::make_unique<PointState>();
      point->id = obs.id;
      const Eigen::Vector3d p_c(
          (obs.uv.x() - intrinsics_->cx) / intrinsics_->fx * *obs.depth,
          (obs.uv.y() - intrinsics_->cy) / intrinsics_->fy * *obs.depth,
          *obs.depth);
      Eigen::Map<Eigen::Vector3d> p_w(point->p);
      p_w = kf.T_wc() * p_c;
      it = point_index_.emplace(obs.id, static_cast<int>(points_.size())).first;
      points_.push_back(std::move(point));
      ++statistics_.points;
    }
    FactorRecord record;
    record.cost.reset(
        ReprojectionFactor::Create(*intrinsics_, obs.uv, sqrt_info));
    record.loss = point_loss_.get();
    record.blocks = {kf.q, kf.t, points_[it->second]->p};
    record.keyframe = k;
    record.point = it->second;
    AddFactor(std::move(record));
    if (obs.depth && options_.point_depth_sigma_relative > 0.0) {
      FactorRecord depth;
      depth.cost.reset(PointDepthFactor::Create(
          *obs.depth, options_.point_depth_sigma_relative * *obs.depth));
      depth.loss = point_loss_.get();
      depth.blocks = {kf.q, kf.t, points_[it->second]->p};
      depth.keyframe = k;
      depth.point = it->second;
      AddFactor(std::move(depth));
    }
  }
}

Status Backend::Impl::AddKeyframe(const KeyframeInput& input) {
  Status status = ValidateKeyframe(input);
  if (!status.ok()) return status;

  auto kf = std::make_unique<KeyframeState>();
  kf->id = input.id;
  kf->timestamp = input.timestamp;
  internal::WritePose(InitialPose(input), kf->q, kf->t);
  if (input.T_wc) kf->T_wc_frontend = Normalized(*input.T_wc);
  const int k = static_cast<int>(keyframes_.size());
  keyframes_.push_back(std::move(kf));
  manifolds_[keyframes_[k]->q] = &quaternion_manifold_;
  ++statistics_.keyframes;

  AddCameraFactors(k, input);
  if (input.T_wc) last_frontend_keyframe_ = k;
  AddPointObservations(k, input);
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& det = input.detections[d];
    const std::string id =
        det.id.empty() ? std::to_string(input.id) + "/" + std::to_string(d)
                       : det.id;
    status = AddDetection(k, det, id);
    if (!status.ok()) {
      return Status::Error("keyframe " + std::to_string(input.id) +
                           ": detection " + id + ": " + status.message());
    }
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Detections.

Status Backend::Impl::AddDetection(int k,
                                   const DetectionInput& detection,
                                   const std::string& detection_id) {
  const Matrix6d sqrt_info = IsotropicPoseSqrtInfo(
      detection.sigma_t.value_or(options_.hypothesis_sigma_t),
      detection.sigma_r.value_or(options_.hypothesis_sigma_r));
  int object = -1;
  SymmetryType type = SymmetryType::kAsymmetric;
  if (options_.method == Method::kSymba) {
    Status status = AddSymba(k, detection, sqrt_info, &object, &type);
    if (!status.ok()) return status;
  } else {
    object = AddSingleOrMultiHypothesis(k, detection, sqrt_info);
  }
  ++objects_[object]->detections;
  ++statistics_.detections;
  assignments_.push_back(
      {keyframes_[k]->id, detection_id, objects_[object]->id, type});
  return Status::Ok();
}

int Backend::Impl::AddSingleOrMultiHypothesis(int k,
                                              const DetectionInput& detection,
                                              const Matrix6d& sqrt_info) {
  const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
  const int best = HighestWeight(hyps, AllIndices(hyps.size()));
  const std::vector<int> used = options_.method == Method::kSingleHypothesis
                                    ? std::vector<int>{best}
                                    : AllIndices(hyps.size());
  const Rigid3d T_wc = keyframes_[k]->T_wc();
  std::vector<Rigid3d> T_wo_candidates;
  for (int j : used) T_wo_candidates.push_back(T_wc * Normalized(hyps[j].T_co));
  int o = FindSixDofMatch(detection.class_name, T_wo_candidates);
  if (o < 0) {
    o = CreateObject(detection.class_name, SymmetryType::kAsymmetric);
    internal::WritePose(
        T_wc * Normalized(hyps[best].T_co), objects_[o]->q, objects_[o]->t);
  }
  ObjectObservation observation;
  observation.keyframe = k;
  observation.components = Components(hyps, used, sqrt_info);
  observation.T_co_best = Normalized(hyps[best].T_co);
  AddObservation(o, std::move(observation));
  return o;
}

Status Backend::Impl::AddSymba(int k,
                               const DetectionInput& detection,
                               const Matrix6d& sqrt_info,
                               int* object_index,
                               SymmetryType* type) {
  const auto prior_it = class_priors_.find(detection.class_name);
  const ClassPrior* prior =
      prior_it == class_priors_.end() ? nullptr : &prior_it->second;
  Status status = Categorize(
      detection.hypotheses, options_.categorization, prior, &categorized_);
  if (!status.ok()) return status;
  const CategorizedDetection& cat = categorized_;
  const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
  *type = cat.type;
  const Rigid3d T_wc = keyframes_[k]->T_wc();
  const std::vector<int>& inliers =
      cat.inliers.empty() ? std::vector<int>{cat.reference} : cat.inliers;

  SymbaMatch match = FindSymbaMatch(T_wc, cat, detection.class_name, hyps);
  int o = match.object;
  if (o < 0) {
    o = CreateObject(detection.class_name, cat.type);
    ObjectState& object = *objects_[o];
    const Rigid3d T_wo_base = T_wc * cat.T_co_base;
    internal::WritePose(T_wo_base, object.q, object.t);
    if (cat.type != SymmetryType::kAsymmetric) {
      object.a_o = cat.axis_o.normalized();
      object.anchor =
          SymmetryAnchor::FromObjectRotation(T_wo_base.q, object.a_o);
      Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
    }
  } else if (match.upgrade) {
    UpgradeObject(o,
                  cat.type == SymmetryType::kContinuous
                      ? SymmetryType::kContinuous
                      : SymmetryType::kDiscrete,
                  match.a_o);
  }
  ObjectState& object = *objects_[o];

  // Edges: one per discrete angle the detection shows, else one.
  ObjectObservation base;
  base.keyframe = k;
  if (cat.type != SymmetryType::kAsymmetric) base.axis_c = cat.axis_c;
  if (object.type == SymmetryType::kDiscrete &&
      cat.type != SymmetryType::kContinuous) {
    // Each group is one mode: its members and their mean pose.
    std::vector<std::pair<std::vector<int>, Rigid3d>> groups;
    if (cat.type == SymmetryType::kDiscrete) {
      for (const AngleCluster& cluster : cat.clusters) {
        const Eigen::Quaterniond R_cluster =
            cat.T_co_base.q *
            Eigen::Quaterniond(Eigen::AngleAxisd(cluster.theta, cat.axis_o));
        groups.emplace_back(cluster.members, Rigid3d(R_cluster, cat.t_co));
      }
    } else {
      groups.emplace_back(inliers, cat.T_co_base);
    }
    for (const auto& [members, T_co_mode] : groups) {
      if (members.empty()) continue;
      ObjectObservation observation = base;
      observation.T_co_best =
          options_.merge_modes
              ? Normalized(T_co_mode)
              : Normalized(hyps[HighestWeight(hyps, members)].T_co);
      observation.components =
          options_.merge_modes
              ? MergedComponent(hyps, members, T_co_mode, sqrt_info)
              : Components(hyps, members, sqrt_info);
      observation.angle =
          MatchOrAddAngle(&object, (T_wc * observation.T_co_best).q);
      AddObservation(o, std::move(observation));
    }
  } else {
    base.T_co_best = cat.type == SymmetryType::kAsymmetric
                         ? cat.T_co_base
                         : Normalized(hyps[HighestWeight(hyps, inliers)].T_co);
    // A continuous edge uses only the components' positions, so merging
    // them at T_co_base (position t_co) is right for both types.
    base.components =
        options_.merge_modes
            ? MergedComponent(hyps, inliers, cat.T_co_base, sqrt_info)
            : Components(hyps, inliers, sqrt_info);
    AddObservation(o, std::move(base));
  }
  *object_index = o;
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Association.

int Backend::Impl::FindSixDofMatch(
    const std::string& class_name,
    const std::vector<Rigid3d>& T_wo_candidates) const {
  int best = -1;
  double best_score = std::numeric_limits<double>::infinity();
  for (size_t o = 0; o < objects_.size(); ++o) {
    const ObjectState& object = *objects_[o];
    if (object.class_name != class_name) continue;
    const Eigen::Quaterniond R_wo = object.Rotation(-1);
    for (const Rigid3d& T_wo : T_wo_candidates) {
      const double d_t = (T_wo.t - object.position()).norm();
      const double d_r = T_wo.q.angularDistance(R_wo);
      if (d_t > options_.gate_position || d_r > options_.gate_rotation)
        continue;
      const double score =
          d_t / options_.gate_position + d_r / options_.gate_rotation;
      if (score < best_score) {
        best_score = score;
        best = static_cast<int>(o);
      }
    }
  }
  return best;
}

Backend::Impl::SymbaMatch Backend::Impl::FindSymbaMatch(
    const Rigid3d& T_wc,
    const CategorizedDetection& cat,
    const std::string& class_name,
    const std::vector<PoseHypothesis>& hyps) const {
  const bool det_symmetric = cat.type != SymmetryType::kAsymmetric;
  const Eigen::Vector3d t_w = T_wc * cat.t_co;
  const Eigen::Quaterniond R_wo_det = T_wc.q * cat.T_co_base.q;
  const auto prior_it = class_priors_.find(class_name);
  const ClassPrior* prior =
      prior_it == class_priors_.end() ? nullptr : &prior_it->second;

  SymbaMatch best;
  double best_score = std::numeric_limits<double>::infinity();
  for (size_t o = 0; o < objects_.size(); ++o) {
    const ObjectState& object = *objects_[o];
    if (object.class_name != class_name) continue;
    const double d_t = (t_w - object.position()).norm();
    if (d_t > options_.gate_position) continue;
    const bool obj_symmetric = object.type != SymmetryType::kAsymmetric;
    SymbaMatch candidate;
    candidate.object = static_cast<int>(o);
    double d_angle = 0.0;
    double gate = options_.gate_axis;
    if (obj_symmetric) {
      // 5 DoF: position and axis. An asymmetric detection's axis is the
      // object's axis carried by the detection's pose.
      const Eigen::Vector3d axis_det =
          det_symmetric ? Eigen::Vector3d(T_wc.q * cat.axis_c)
                        : Eigen::Vector3d(R_wo_det * object.a_o);
      d_angle = AxisDistance(axis_det, object.axis_w());
    } else if (det_symmetric) {
      // 5 DoF against an asymmetric object: the detection's object-frame
      // axis carried by the object's pose must match the detection's axis.
      const Eigen::Quaterniond R_wo = object.Rotation(-1);
      d_angle = AxisDistance(R_wo * cat.axis_o, T_wc.q * cat.axis_c);
      candidate.upgrade = true;
      candidate.a_o = cat.axis_o.normalized();
    } else {
      // Both asymmetric: 6 DoF with the nearest surviving hypothesis.
      const Eigen::Quaterniond R_wo = object.Rotation(-1);
      double d_r = std::numeric_limits<double>::infinity();
      Eigen::Quaterniond nearest = R_wo_det;
      for (int j : cat.inliers) {
        const Eigen::Quaterniond R = T_wc.q * hyps[j].T_co.q.normalized();
        const double d = R.angularDistance(R_wo);
        if (d < d_r) {
          d_r = d;
          nearest = R;
        }
      }
      if (cat.inliers.empty()) d_r = R_wo_det.angularDistance(R_wo);
      gate = options_.gate_rotation;
      d_angle = d_r;
      if (d_r > options_.gate_rotation) {
        // 6 DoF fails; 5 DoF holds if the relative rotation is a twist about
        // an axis (the prior's, or its own): the object becomes discrete.
        if (prior && prior->symmetry == SymmetryType::kAsymmetric) continue;
        const Eigen::Quaterniond R_rel = R_wo.conjugate() * nearest;
        Eigen::Vector3d a_o = LogSO3(R_rel).normalized();
        if (prior && prior->axis_o.norm() > 0.0) {
          a_o = prior->axis_o.normalized();
          const SwingTwist<double> st = DecomposeSwingTwist(R_rel, a_o);
          if (2.0 * std::asin(std::min(1.0, st.swing.vec().norm())) >
              options_.gate_axis) {
            continue;
          }
        }
        candidate.upgrade = true;
        candidate.a_o = a_o;
        d_angle = options_.gate_axis;  // ranks after any 6-DoF match
        gate = options_.gate_axis;
      }
    }
    if (d_angle > gate) continue;
    const double score = d_t / options_.gate_position + d_angle / gate;
    if (score < best_score) {
      best_score = score;
      best = candidate;
    }
  }
  return best;
}

int Backend::Impl::MatchOrAddAngle(ObjectState* object,
                                   const Eigen::Quaterniond& R_wo) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < object->thetas.size(); ++i) {
    const Eigen::Quaterniond R_wo_i = object->Rotation(static_cast<int>(i));
    const double delta =
        std::abs(TwistAngle(Eigen::Quaterniond(R_wo_i.conjugate() * R_wo),
                            Eigen::Vector3d(object->a_o)));
    if (delta < best_distance) {
      best_distance = delta;
      best = static_cast<int>(i);
    }
  }
  if (best >= 0 && best_distance <= options_.gate_angle) return best;
  // A new angle: theta_0 plus the twist from angle 0 (or from the anchor).
  const double theta_0 = object->thetas.empty() ? 0.0 : *object->thetas[0];
  const Eigen::Quaterniond R_wo_0 =
      SymmetricObjectRotation(object->anchor, object->axis_w(), theta_0);
  const double theta = WrapToPi(
      theta_0 + TwistAngle(Eigen::Quaterniond(R_wo_0.conjugate() * R_wo),
                           Eigen::Vector3d(object->a_o)));
  object->thetas.push_back(std::make_unique<double>(theta));
  return static_cast<int>(object->thetas.size()) - 1;
}

// ---------------------------------------------------------------------------
// Map objects.

int Backend::Impl::CreateObject(const std::string& class_name,
                                SymmetryType type) {
  auto object = std::make_unique<ObjectState>();
  object->id = static_cast<int>(objects_.size());
  object->class_name = class_name;
  object->type = type;
  objects_.push_back(std::move(object));
  ObjectState& created = *objects_.back();
  manifolds_[created.q] = &quaternion_manifold_;
  manifolds_[created.a_w] = &axis_manifold_;
  ++statistics_.objects;
  return created.id;
}

void Backend::Impl::UpgradeObject(int o,
                                  SymmetryType type,
                                  const Eigen::Vector3d& a_o) {
  ObjectState& object = *objects_[o];
  const Eigen::Quaterniond R_wo = object.Rotation(-1);
  object.type = type;
  object.a_o = a_o.normalized();
  object.anchor = SymmetryAnchor::FromObjectRotation(R_wo, object.a_o);
  Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  if (type == SymmetryType::kDiscrete) {
    // The asymmetric pose is angle 0; every past observation constrains it.
    object.thetas.push_back(std::make_unique<double>(0.0));
    for (ObjectObservation& observation : object.observations) {
      observation.angle = 0;
    }
  }
  ++statistics_.object_upgrades;
  RebuildObjectFactors(o);
}

void Backend::Impl::AddObservation(int o, ObjectObservation observation) {
  ObjectState& object = *objects_[o];
  object.observations.push_back(std::move(observation));
  std::vector<double*> blocks;
  FactorRecord record;
  record.cost = BuildObjectEdge(object, object.observations.back(), &blocks);
  record.blocks = std::move(blocks);
  record.loss = object_loss_.get();
  record.keyframe = object.observations.back().keyframe;
  record.object = o;
  AddFactor(std::move(record));
}

void Backend::Impl::RebuildObjectFactors(int o) {
  ObjectState& object = *objects_[o];
  const std::vector<int> old = object.factors;
  for (int f : old) RetireFactor(f);
  object.factors.clear();
  for (const ObjectObservation& observation : object.observations) {
    std::vector<double*> blocks;
    FactorRecord record;
    record.cost = BuildObjectEdge(object, observation, &blocks);
    record.blocks = std::move(blocks);
    record.loss = object_loss_.get();
    record.keyframe = observation.keyframe;
    record.object = o;
    AddFactor(std::move(record));
  }
}

void Backend::Impl::ReanchorDriftedObjects() {
  for (size_t o = 0; o < objects_.size(); ++o) {
    ObjectState& object = *objects_[o];
    if (object.type != SymmetryType::kDiscrete) continue;
    const Eigen::Vector3d a_w = object.axis_w();
    if (std::acos(std::min(1.0, a_w.dot(object.anchor.a_w0))) <=
        options_.reanchor_angle) {
      continue;
    }
    // R_wo_i is unchanged: Swing(a_w -> a_w) = I absorbs the old swing.
    object.anchor.q_base =
        (MinimalRotation(object.anchor.a_w0, a_w) * object.anchor.q_base)
            .normalized();
    object.anchor.a_w0 = object.anchor.q_base * object.anchor.a_o;
    Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
    RebuildObjectFactors(static_cast<int>(o));
  }
}

std::unique_ptr<ceres::CostFunction> Backend::Impl::BuildObjectEdge(
    const ObjectState& object,
    const ObjectObservation& observation,
    std::vector<double*>* blocks) {
  KeyframeState& kf = *keyframes_[observation.keyframe];
  ObjectState& mutable_object = *objects_[object.id];
  if (object.type == SymmetryType::kAsymmetric) {
    std::unique_ptr<AsymmetricObjectEdge> edge;
    Status status = CreateAsymmetricObjectEdge(
        observation.components, options_.mixture, &edge);
    *blocks = {kf.q, kf.t, mutable_object.q, mutable_object.t};
    return status.ok() ? std::move(edge) : nullptr;
  }
  if (object.type == SymmetryType::kDiscrete && observation.angle >= 0) {
    std::unique_ptr<DiscreteObjectEdge> edge;
    Status status = CreateDiscreteObjectEdge(
        observation.components, object.anchor, options_.mixture, &edge);
    *blocks = {kf.q,
               kf.t,
               mutable_object.t,
               mutable_object.a_w,
               mutable_object.thetas[observation.angle].get()};
    return status.ok() ? std::move(edge) : nullptr;
  }
  // Continuous (or a continuous view of a discrete object): translations
  // plus the axis, its sign aligned with the map axis.
  std::vector<TranslationComponent> translations;
  for (const PoseComponent& c : observation.components) {
    translations.push_back(
        {c.T_co.t, c.sqrt_info.topLeftCorner<3, 3>(), c.weight});
  }
  AxisMeasurement axis;
  axis.a_c = observation.axis_c.norm() > 0.0
                 ? observation.axis_c.normalized()
                 : Eigen::Vector3d(observation.T_co_best.q * object.a_o);
  if ((kf.T_wc().q * axis.a_c).dot(object.axis_w()) < 0.0) axis.a_c = -axis.a_c;
  axis.sqrt_info = Eigen::Matrix2d::Identity() / options_.axis_sigma;
  axis.gamma = options_.gamma;
  std::unique_ptr<ContinuousObjectEdge> edge;
  Status status =
      CreateContinuousObjectEdge(translations, axis, options_.mixture, &edge);
  *blocks = {kf.q, kf.t, mutable_object.t, mutable_object.a_w};
  return status.ok() ? std::move(edge) : nullptr;
}

// ---------------------------------------------------------------------------
// Factors and the persistent problem.

int Backend::Impl::AddFactor(FactorRecord record) {
  const int f = static_cast<int>(factors_.size());
  if (!record.cost) return -1;  // unreachable: inputs were validated
  keyframes_[record.keyframe]->factors.push_back(f);
  if (record.keyframe2 >= 0) keyframes_[record.keyframe2]->factors.push_back(f);
  if (record.object >= 0) objects_[record.object]->factors.push_back(f);
  if (record.point >= 0) points_[record.point]->factors.push_back(f);
  factors_.push_back(std::move(record));
  return f;
}

void Backend::Impl::RetireFactor(int f) {
  FactorRecord& record = factors_[f];
  if (record.residual != nullptr) {
    problem_.RemoveResidualBlock(record.residual);
    record.residual = nullptr;
  }
  record.retired = true;
}

void Backend::Impl::EnsureBlock(double* block, int size) {
  if (problem_.HasParameterBlock(block)) return;
  const auto it = manifolds_.find(block);
  problem_.AddParameterBlock(block,
                             size,
                             it == manifolds_.end()
                                 ? nullptr
                                 : const_cast<ceres::Manifold*>(it->second));
}

Status Backend::Impl::Optimize(int first_free,
                               int max_iterations,
                               SolveReport* report) {
  const int n = static_cast<int>(keyframes_.size());
  if (n == 0) return Status::Error("no keyframes to optimise");
  const auto start = std::chrono::steady_clock::now();

  // The free set: window keyframes (not the gauge) and all they observe.
  std::vector<char> keyframe_free(n, 0);
  std::vector<char> object_free(objects_.size(), 0);
  std::vector<char> point_free(points_.size(), 0);
  for (int k = first_free; k < n; ++k) {
    keyframe_free[k] = k > 0;
    for (int f : keyframes_[k]->factors) {
      const FactorRecord& record = factors_[f];
      if (record.retired) continue;
      if (record.object >= 0) object_free[record.object] = 1;
      if (record.point >= 0) point_free[record.point] = 1;
    }
  }
  std::vector<char> active(factors_.size(), 0);
  auto mark = [&](const std::vector<int>& list) {
    for (int f : list) active[f] = !factors_[f].retired;
  };
  for (int k = first_free; k < n; ++k) mark(keyframes_[k]->factors);
  for (size_t o = 0; o < objects_.size(); ++o) {
    if (object_free[o]) mark(objects_[o]->factors);
  }
  for (size_t p = 0; p < points_.size(); ++p) {
    if (point_free[p]) mark(points_[p]->factors);
  }

  // Remove what left the window, then parameter blocks nothing uses.
  std::vector<double*> released;
  for (size_t f = 0; f < factors_.size(); ++f) {
    FactorRecord& record = factors_[f];
    if (record.residual == nullptr || active[f]) continue;
    problem_.RemoveResidualBlock(record.residual);
    record.residual = nullptr;
    released.insert(released.end(), record.blocks.begin(), record.blocks.end());
  }
  std::vector<ceres::ResidualBlockId> users;
  for (double* block : released) {
    if (!problem_.HasParameterBlock(block)) continue;
    problem_.GetResidualBlocksForParameterBlock(block, &users);
    if (users.empty()) problem_.RemoveParameterBlock(block);
  }
  // Add what entered it.
  for (size_t f = 0; f < factors_.size(); ++f) {
    FactorRecord& record = factors_[f];
    if (!active[f] || record.residual != nullptr) continue;
    const std::vector<int32_t>& sizes = record.cost->parameter_block_sizes();
    for (size_t b = 0; b < record.blocks.size(); ++b) {
      EnsureBlock(record.blocks[b], sizes[b]);
    }
    record.residual =
        problem_.AddResidualBlock(record.cost.get(),
                                  const_cast<ceres::LossFunction*>(record.loss),
                                  record.blocks);
  }
  // Keyframes outside the window (and the gauge) are constant.
  int free_keyframes = 0;
  for (int k = 0; k < n; ++k) {
    KeyframeState& kf = *keyframes_[k];
    if (!problem_.HasParameterBlock(kf.q)) continue;
    if (keyframe_free[k]) {
      problem_.SetParameterBlockVariable(kf.q);
      problem_.SetParameterBlockVariable(kf.t);
      ++free_keyframes;
    } else {
      problem_.SetParameterBlockConstant(kf.q);
      problem_.SetParameterBlockConstant(kf.t);
    }
  }

  ceres::Solver::Summary summary;
  if (problem_.NumResidualBlocks() > 0) {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = max_iterations;
    solver_options.num_threads = options_.num_threads;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solve(solver_options, &problem_, &summary);
  }
  ReanchorDriftedObjects();

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ++statistics_.solves;
  statistics_.solve_seconds += seconds;
  statistics_.solve_iterations += static_cast<int>(summary.iterations.size());
  if (report != nullptr) {
    report->iterations = static_cast<int>(summary.iterations.size());
    report->initial_cost = summary.initial_cost;
    report->final_cost = summary.final_cost;
    report->seconds = seconds;
    report->converged = summary.termination_type == ceres::CONVERGENCE;
    report->free_keyframes = free_keyframes;
    report->residual_blocks = problem_.NumResidualBlocks();
  }
  if (problem_.NumResidualBlocks() > 0 && !summary.IsSolutionUsable()) {
    return Status::Error("the solver failed: " + summary.message);
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Read-back.

std::vector<KeyframeEstimate> Backend::Impl::Keyframes() const {
  std::vector<KeyframeEstimate> estimates;
  estimates.reserve(keyframes_.size());
  for (const auto& kf : keyframes_) {
    estimates.push_back({kf->id, kf->timestamp, kf->T_wc()});
  }
  return estimates;
}

std::vector<MapObjectEstimate> Backend::Impl::Objects() const {
  std::vector<MapObjectEstimate> estimates;
  for (const auto& object : objects_) {
    MapObjectEstimate e;
    e.id = object->id;
    e.class_name = object->class_name;
    e.symmetry = object->type;
    e.t_wo = object->position();
    e.observations = object->detections;
    if (object->type == SymmetryType::kAsymmetric) {
      e.poses.push_back(Rigid3d(object->Rotation(-1), e.t_wo));
    } else {
      e.axis_w = object->axis_w().normalized();
      e.axis_o = object->a_o;
      if (object->type == SymmetryType::kDiscrete) {
        for (size_t i = 0; i < object->thetas.size(); ++i) {
          e.angles.push_back(*object->thetas[i]);
          e.poses.push_back(
              Rigid3d(object->Rotation(static_cast<int>(i)), e.t_wo));
        }
      } else {
        e.poses.push_back(Rigid3d(
            SymmetricObjectRotation(object->anchor, object->axis_w(), 0.0),
            e.t_wo));
      }
    }
    estimates.push_back(std::move(e));
  }
  return estimates;
}

// ---------------------------------------------------------------------------
// Backend.

Status Backend::Create(const BackendOptions& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       const std::map<std::string, ClassPrior>& class_priors,
                       std::unique_ptr<Backend>* backend) {
  Status status = options.Validate();
  if (!status.ok()) return status;
  if (intrinsics) {
    const PinholeIntrinsics& k = *intrinsics;
    if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0.0 &&
          k.fy > 0.0 && std::isfinite(k.cx) && std::isfinite(k.cy))) {
      return Status::Error(
          "camera intrinsics: fx, fy must be positive, all finite");
    }
  }
  // Categorize's own checks on every prior (a one-hypothesis detection
  // always passes the rest): a bad prior must fail here, not in AddKeyframe
  // after the keyframe was added.
  for (const auto& [class_name, prior] : class_priors) {
    CategorizedDetection scratch;
    status = Categorize(
        {PoseHypothesis{}}, options.categorization, &prior, &scratch);
    if (!status.ok()) {
      return Status::Error("class prior \"" + class_name +
                           "\": " + status.message());
    }
  }
  backend->reset(
      new Backend(std::make_unique<Impl>(options, intrinsics, class_priors)));
  return Status::Ok();
}

Backend::Backend(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Backend::~Backend() = default;

Status Backend::AddKeyframe(const KeyframeInput& keyframe) {
  return impl_->AddKeyframe(keyframe);
}

Status Backend::OptimizeWindow(SolveReport* report) {
  return impl_->Optimize(
      impl_->WindowStart(), impl_->options_.max_iterations, report);
}

Status Backend::OptimizeBatch(SolveReport* report) {
  return impl_->Optimize(0, impl_->options_.batch_max_iterations, report);
}

std::vector<KeyframeEstimate> Backend::Keyframes() const {
  return impl_->Keyframes();
}

std::vector<MapObjectEstimate> Backend::Objects() const {
  return impl_->Objects();
}

const std::vector<DetectionAssignment>& Backend::Assignments() const {
  return impl_->assignments_;
}

BackendStatistics Backend::Statistics() const { return impl_->statistics_; }

const BackendOptions& Backend::options() const { return impl_->options_; }

}  // namespace symba
