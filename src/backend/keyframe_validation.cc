#include "backend/keyframe_validation.h"

#include <cmath>

#include "symba/backend/backend_options.h"
#include "symba/io/format_double.h"

namespace symba::internal {

Status CheckPose(const Rigid3d& T, const std::string& what) {
  if (!T.q.coeffs().allFinite() || !T.t.allFinite()) {
    return Status::Error(what + ": pose is not finite");
  }
  if (std::abs(T.q.norm() - 1.0) > kUnitTolerance) {
    return Status::Error(what + ": quaternion is not unit (|q| = " +
                         std::to_string(T.q.norm()) + ")");
  }
  if (!(T.t.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
    return Status::Error(what + ": translation beyond 1e9 m (" +
                         FormatDouble(T.t.cwiseAbs().maxCoeff()) + ")");
  }
  return Status::Ok();
}

Status CheckSigma(const std::optional<double>& sigma, const std::string& what) {
  if (sigma && !IsUsableNoiseSigma(*sigma)) {
    return Status::Error(what + " must be in [1e-9, 1e9], got " +
                         FormatDouble(*sigma));
  }
  return Status::Ok();
}

namespace {

Status ValidateOrder(const KeyframeInput& input,
                     const std::optional<PreviousKeyframe>& previous,
                     const std::string& where) {
  if (previous) {
    if (input.id <= previous->id) {
      return Status::Error(where + ": id must be greater than the previous (" +
                           std::to_string(previous->id) + ")");
    }
    if (!(input.timestamp >= previous->timestamp)) {
      return Status::Error(where + ": timestamp must not decrease");
    }
  }
  if (!std::isfinite(input.timestamp)) {
    return Status::Error(where + ": timestamp is not finite");
  }
  return Status::Ok();
}

Status ValidateMotion(const KeyframeInput& input,
                      bool first,
                      const std::string& where) {
  if (first && !input.T_wc) {
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
  return Status::Ok();
}

Status ValidateDetection(const DetectionInput& det, const std::string& what) {
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
    // Weights are relative; their sums must stay finite.
    if (!(w > 0.0 && w <= kMaxHypothesisWeight)) {
      return Status::Error(hyp + ": weight must be positive and at most 1e100");
    }
  }
  return Status::Ok();
}

Status ValidatePoints(const KeyframeInput& input,
                      bool has_intrinsics,
                      const std::string& where) {
  if (!input.points.empty() && !has_intrinsics) {
    return Status::Error(where + ": has points but no camera intrinsics");
  }
  for (const PointObservation& point : input.points) {
    const std::string what = where + ": point " + std::to_string(point.id);
    if (!point.uv.allFinite()) {
      return Status::Error(what + ": uv is not finite");
    }
    if (!(point.uv.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      return Status::Error(what + ": uv beyond 1e9 px (" +
                           FormatDouble(point.uv.cwiseAbs().maxCoeff()) + ")");
    }
    if (point.depth && !(std::isfinite(*point.depth) && *point.depth > 0.0)) {
      return Status::Error(what + ": depth must be positive and finite");
    }
  }
  return Status::Ok();
}

}  // namespace

Status ValidateKeyframe(const KeyframeInput& input,
                        const std::optional<PreviousKeyframe>& previous,
                        bool has_intrinsics) {
  const std::string where = "keyframe " + std::to_string(input.id);
  Status status = ValidateOrder(input, previous, where);
  if (!status.ok()) return status;
  status = ValidateMotion(input, !previous.has_value(), where);
  if (!status.ok()) return status;
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& det = input.detections[d];
    status = ValidateDetection(
        det,
        where + ": detection " + (det.id.empty() ? std::to_string(d) : det.id));
    if (!status.ok()) return status;
  }
  return ValidatePoints(input, has_intrinsics, where);
}

}  // namespace symba::internal
