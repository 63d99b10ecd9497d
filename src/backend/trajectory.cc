// The backend's keyframes and map points (trajectory.h).
#include "backend/trajectory.h"

#include <algorithm>
#include <utility>

#include "symba/factors/point_depth_factor.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/factors/reprojection_factor.h"

namespace symba::internal {

Trajectory::Trajectory(const BackendOptions& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       FactorGraph* graph,
                       BackendStatistics* statistics)
    : options_(options),
      intrinsics_(intrinsics),
      graph_(graph),
      statistics_(statistics),
      point_loss_(
          std::make_unique<ceres::HuberLoss>(options.point_loss_scale)) {}

const KeyframeState* Trajectory::Find(int64_t id) const {
  const int k = IndexOf(id);
  return k < 0 ? nullptr : keyframes_[k].get();
}

int Trajectory::IndexOf(int64_t id) const {
  const auto it =
      std::lower_bound(keyframes_.begin(),
                       keyframes_.end(),
                       id,
                       [](const std::unique_ptr<KeyframeState>& kf,
                          int64_t value) { return kf->id < value; });
  if (it == keyframes_.end() || (*it)->id != id) return -1;
  return static_cast<int>(it - keyframes_.begin());
}

int Trajectory::Add(const KeyframeInput& input, MotionClaims* claims) {
  auto kf = std::make_unique<KeyframeState>();
  kf->id = input.id;
  kf->timestamp = input.timestamp;
  WritePose(InitialPose(input), kf->q, kf->t);
  kf->T_wc_chain = ChainPose(input);
  if (input.T_wc) kf->T_wc_frontend = Normalized(*input.T_wc);
  const int k = static_cast<int>(keyframes_.size());
  keyframes_.push_back(std::move(kf));
  graph_->SetManifold(keyframes_[k]->q, &quaternion_manifold_);
  ++statistics_->keyframes;
  AddCameraFactors(k, input, claims);
  if (input.T_wc) last_frontend_keyframe_ = k;
  AddPointObservations(k, input);
  return k;
}

Rigid3d Trajectory::InitialPose(const KeyframeInput& input) const {
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

Rigid3d Trajectory::ChainPose(const KeyframeInput& input) const {
  if (keyframes_.empty()) return Normalized(*input.T_wc);
  if (input.odometry) {
    return Normalized(keyframes_.back()->T_wc_chain *
                      Normalized(input.odometry->T_prev_cur));
  }
  if (last_frontend_keyframe_ >= 0) {
    const KeyframeState& anchor = *keyframes_[last_frontend_keyframe_];
    return Normalized(anchor.T_wc_chain * anchor.T_wc_frontend->Inverse() *
                      Normalized(*input.T_wc));
  }
  return Normalized(*input.T_wc);
}

MotionNoiseReport Trajectory::MotionNoise() const {
  MotionNoiseReport report;
  report.odometry_steps = odometry_sigmas_.steps;
  report.frontend_steps = frontend_sigmas_.steps;
  if (odometry_sigmas_.steps > 0) {
    report.odometry_sigma_t = odometry_sigmas_.t.Median();
    report.odometry_sigma_r = odometry_sigmas_.r.Median();
  }
  if (frontend_sigmas_.steps > 0) {
    report.frontend_sigma_t = frontend_sigmas_.t.Median();
    report.frontend_sigma_r = frontend_sigmas_.r.Median();
  }
  return report;
}

void Trajectory::AddCameraFactors(int k,
                                  const KeyframeInput& input,
                                  MotionClaims* claims) {
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
  if (k > 0) {  // a keyframe without a motion factor adds nothing
    kf.summed_motion_variance_t = keyframes_[k - 1]->summed_motion_variance_t;
    kf.summed_motion_variance_r = keyframes_[k - 1]->summed_motion_variance_r;
  }
  if (other < 0) return;
  const double stated_t = 1.0 / sqrt_info(0, 0);
  const double stated_r = 1.0 / sqrt_info(3, 3);
  const double scale =
      claims != nullptr ? claims->Factor(stated_t, stated_r) : 1.0;
  const double sigma_t = scale * stated_t;
  const double sigma_r = scale * stated_r;
  if (scale != 1.0) sqrt_info /= scale;
  kf.stated_motion_sigma_t = stated_t;
  kf.stated_motion_sigma_r = stated_r;
  StepSigmas& sigmas =
      other == k - 1 && input.odometry ? odometry_sigmas_ : frontend_sigmas_;
  ++sigmas.steps;
  sigmas.t.Add(stated_t);
  sigmas.r.Add(stated_r);
  kf.motion_variance_t = sigma_t * sigma_t;
  kf.motion_variance_r = sigma_r * sigma_r;
  kf.motion_from = other;
  KeyframeState& prev = *keyframes_[other];
  // Keyframe after keyframe (a front-end pose's step from an earlier
  // keyframe counts from the previous one: an over-estimate, never below).
  kf.summed_motion_variance_t += kf.motion_variance_t;
  kf.summed_motion_variance_r += kf.motion_variance_r;
  FactorRecord record;
  record.cost.reset(RelativePoseFactor::Create(T_other_cur, sqrt_info));
  record.blocks = {prev.q, prev.t, kf.q, kf.t};
  record.keyframe = k;
  record.keyframe2 = other;
  graph_->Add(std::move(record));
}

void Trajectory::AddPointObservations(int k, const KeyframeInput& input) {
  KeyframeState& kf = *keyframes_[k];
  const Eigen::Matrix2d sqrt_info =
      Eigen::Matrix2d::Identity() / options_.point_sigma_px;
  const Rigid3d T_cw = kf.T_wc().Inverse();
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
      ++statistics_->points;
    }
    // A point behind the camera's initial pose cannot be projected: a solve
    // could not start from it (a point moved by a loop closure, a front end
    // that jumped). The observation is left out.
    const Eigen::Vector3d p_c =
        T_cw * Eigen::Map<const Eigen::Vector3d>(points_[it->second]->p);
    if (p_c.z() <= ReprojectionFactor::kMinDepth) {
      ++statistics_->point_observations_behind;
      continue;
    }
    PointState& point = *points_[it->second];
    if (k > 0 && point.last_keyframe == k - 1) ++kf.points_shared_with_previous;
    if (point.first_keyframe < 0) point.first_keyframe = k;
    point.last_keyframe = k;
    FactorRecord record;
    record.cost.reset(
        ReprojectionFactor::Create(*intrinsics_, obs.uv, sqrt_info));
    record.loss = point_loss_.get();
    record.blocks = {kf.q, kf.t, points_[it->second]->p};
    record.keyframe = k;
    record.point = it->second;
    graph_->Add(std::move(record));
    if (obs.depth && options_.point_depth_sigma_relative > 0.0) {
      FactorRecord depth;
      depth.cost.reset(PointDepthFactor::Create(
          *obs.depth, options_.point_depth_sigma_relative * *obs.depth));
      depth.loss = point_loss_.get();
      depth.blocks = {kf.q, kf.t, points_[it->second]->p};
      depth.keyframe = k;
      depth.point = it->second;
      graph_->Add(std::move(depth));
    }
  }
}

}  // namespace symba::internal
