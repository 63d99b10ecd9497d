#include "symba/evaluation/trajectory_error.h"
#include "symba/io/format_double.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "symba/evaluation/evaluate.h"
#include "symba/geometry/angle.h"

namespace symba {

Status CompareTrajectories(const std::vector<TrajectoryPose>& estimate,
                           const std::string& estimate_name,
                           const std::vector<TrajectoryPose>& reference,
                           const std::string& reference_name,
                           TrajectoryError* error) {
  if (estimate.empty()) return Status::Error(estimate_name + ": no poses");
  double sum = 0.0;
  double max = 0.0;
  for (const TrajectoryPose& pose : estimate) {
    const auto it = std::lower_bound(
        reference.begin(),
        reference.end(),
        pose.timestamp - kTimestampTolerance,
        [](const TrajectoryPose& r, double t) { return r.timestamp < t; });
    if (it == reference.end() ||
        !(std::abs(it->timestamp - pose.timestamp) <= kTimestampTolerance)) {
      return Status::Error(estimate_name + ": pose at timestamp " +
                           FormatDouble(pose.timestamp) + ": no pose of " +
                           reference_name + " at that time");
    }
    const double d = (pose.T_wc.t - it->T_wc.t).norm();
    sum += d * d;
    max = std::max(max, d);
  }
  error->poses = static_cast<int>(estimate.size());
  error->position_rmse = std::sqrt(sum / static_cast<double>(estimate.size()));
  error->max_position_error = max;
  return Status::Ok();
}

namespace {

// Estimated poses and the reference poses matched to them, both with the
// estimate's timestamps (so CompareTrajectories pairs them one to one).
struct MatchedPoses {
  std::vector<TrajectoryPose> estimate;
  std::vector<TrajectoryPose> reference;
};

MatchedPoses MatchByTime(const std::vector<TrajectoryPose>& estimate,
                         const std::vector<TrajectoryPose>& reference,
                         double tolerance) {
  MatchedPoses matched;
  for (const TrajectoryPose& pose : estimate) {
    const TrajectoryPose* nearest =
        NearestPose(reference, pose.timestamp, tolerance);
    if (nearest == nullptr) continue;
    TrajectoryPose at_estimate_time = *nearest;
    at_estimate_time.timestamp = pose.timestamp;
    matched.estimate.push_back(pose);
    matched.reference.push_back(at_estimate_time);
  }
  return matched;
}

Eigen::Matrix3Xd Positions(const std::vector<TrajectoryPose>& poses) {
  Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    positions.col(static_cast<Eigen::Index>(i)) = poses[i].T_wc.t;
  }
  return positions;
}

Status Align(const MatchedPoses& matched,
             TrajectoryAlignment alignment,
             const std::string& estimate_name,
             TrajectoryEvaluation* e) {
  e->T_ref_est = Rigid3d::Identity();
  e->scale = 1.0;
  if (alignment == TrajectoryAlignment::kNone) return Status::Ok();
  if (alignment == TrajectoryAlignment::kFirst) {
    e->T_ref_est = matched.reference.front().T_wc *
                   matched.estimate.front().T_wc.Inverse();
    return Status::Ok();
  }
  if (matched.estimate.size() < 3) {
    return Status::Error(std::string(TrajectoryAlignmentName(alignment)) +
                         " alignment needs at least 3 matched poses, " +
                         estimate_name + " has " +
                         std::to_string(matched.estimate.size()));
  }
  const bool with_scale = alignment == TrajectoryAlignment::kSim3;
  const Eigen::Matrix4d T = Eigen::umeyama(
      Positions(matched.estimate), Positions(matched.reference), with_scale);
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  e->scale = with_scale ? std::cbrt(sR.determinant()) : 1.0;
  if (!T.allFinite() || !(e->scale > 0.0)) {
    return Status::Error(std::string(TrajectoryAlignmentName(alignment)) +
                         " alignment: the matched positions of " +
                         estimate_name +
                         " do not determine a transform (all in one place)");
  }
  e->T_ref_est.q = Eigen::Quaterniond(sR / e->scale).normalized();
  e->T_ref_est.t = T.topRightCorner<3, 1>();
  return Status::Ok();
}

TrajectoryPose Aligned(const TrajectoryEvaluation& e,
                       const TrajectoryPose& pose) {
  TrajectoryPose aligned = pose;
  aligned.T_wc.q = (e.T_ref_est.q * pose.T_wc.q).normalized();
  aligned.T_wc.t = e.scale * (e.T_ref_est.q * pose.T_wc.t) + e.T_ref_est.t;
  return aligned;
}

double RotationRmseDeg(const std::vector<TrajectoryPose>& estimate,
                       const std::vector<TrajectoryPose>& reference) {
  double sum = 0.0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double angle =
        reference[i].T_wc.q.angularDistance(estimate[i].T_wc.q);
    sum += angle * angle;
  }
  return kDegreesPerRadian *
         std::sqrt(sum / static_cast<double>(estimate.size()));
}

void RelativePoseError(const std::vector<TrajectoryPose>& estimate,
                       const std::vector<TrajectoryPose>& reference,
                       TrajectoryEvaluation* e) {
  double sum_t = 0.0;
  double sum_r = 0.0;
  e->rpe_pairs = static_cast<int>(estimate.size()) - 1;
  for (std::size_t i = 0; i + 1 < estimate.size(); ++i) {
    const Rigid3d d_est = estimate[i].T_wc.Inverse() * estimate[i + 1].T_wc;
    const Rigid3d d_ref = reference[i].T_wc.Inverse() * reference[i + 1].T_wc;
    const Rigid3d error = d_ref.Inverse() * d_est;
    sum_t += error.t.squaredNorm();
    const double angle =
        Eigen::Quaterniond::Identity().angularDistance(error.q);
    sum_r += angle * angle;
  }
  if (e->rpe_pairs <= 0) {
    e->rpe_pairs = 0;
    e->rpe_translation_rmse = std::nan("");
    e->rpe_rotation_rmse_deg = std::nan("");
    return;
  }
  e->rpe_translation_rmse = std::sqrt(sum_t / e->rpe_pairs);
  e->rpe_rotation_rmse_deg =
      kDegreesPerRadian * std::sqrt(sum_r / e->rpe_pairs);
}

}  // namespace

const char* TrajectoryAlignmentName(TrajectoryAlignment alignment) {
  switch (alignment) {
    case TrajectoryAlignment::kNone:
      return "none";
    case TrajectoryAlignment::kSe3:
      return "se3";
    case TrajectoryAlignment::kSim3:
      return "sim3";
    case TrajectoryAlignment::kFirst:
      break;
  }
  return "first";
}

bool ParseTrajectoryAlignment(const std::string& name,
                              TrajectoryAlignment* alignment) {
  for (TrajectoryAlignment a : {TrajectoryAlignment::kNone,
                                TrajectoryAlignment::kFirst,
                                TrajectoryAlignment::kSe3,
                                TrajectoryAlignment::kSim3}) {
    if (name == TrajectoryAlignmentName(a)) {
      *alignment = a;
      return true;
    }
  }
  return false;
}

Status EvaluateTrajectory(const std::vector<TrajectoryPose>& estimate,
                          const std::string& estimate_name,
                          const std::vector<TrajectoryPose>& reference,
                          const std::string& reference_name,
                          const TrajectoryEvaluationOptions& options,
                          TrajectoryEvaluation* evaluation) {
  if (!(options.time_tolerance >= 0.0) ||
      !std::isfinite(options.time_tolerance)) {
    return Status::Error(
        "time tolerance: must be finite and not negative, "
        "got " +
        FormatDouble(options.time_tolerance));
  }
  if (estimate.empty()) return Status::Error(estimate_name + ": no poses");
  const MatchedPoses matched =
      MatchByTime(estimate, reference, options.time_tolerance);
  if (matched.estimate.empty()) {
    return Status::Error(estimate_name + ": no pose within " +
                         FormatDouble(options.time_tolerance) +
                         " s of a pose of " + reference_name);
  }
  TrajectoryEvaluation e;
  e.poses = static_cast<int>(estimate.size());
  e.matched = static_cast<int>(matched.estimate.size());
  e.alignment = options.alignment;
  Status status = Align(matched, options.alignment, estimate_name, &e);
  if (!status.ok()) return status;
  std::vector<TrajectoryPose> aligned;
  for (const TrajectoryPose& pose : matched.estimate) {
    aligned.push_back(Aligned(e, pose));
  }
  status = CompareTrajectories(
      aligned, estimate_name, matched.reference, reference_name, &e.ate);
  if (!status.ok()) return status;
  e.rotation_rmse_deg = RotationRmseDeg(aligned, matched.reference);
  RelativePoseError(aligned, matched.reference, &e);
  *evaluation = e;
  return Status::Ok();
}

}  // namespace symba
