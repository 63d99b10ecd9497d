#include "backend/association.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/swing_twist.h"

namespace symba::internal {

double AxisDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

AssociationScope DetectionScope(const DetectionInput& detection,
                                const KeyframeState& kf,
                                const Eigen::Vector3d& t_co,
                                const std::optional<double>& estimated_sigma_t,
                                const BackendOptions& options,
                                double claim_factor_t) {
  AssociationScope scope;
  scope.sigma_t = detection.sigma_t || detection.sigma_r
                      ? detection.sigma_t.value_or(options.hypothesis_sigma_t) *
                            claim_factor_t
                      : estimated_sigma_t;
  scope.prediction_variance =
      kf.motion_variance_t + t_co.squaredNorm() * kf.motion_variance_r;
  return scope;
}

int PlaceLastSeen(const ObjectList& objects,
                  int k,
                  const Eigen::Vector3d& t_w,
                  const BackendOptions& options) {
  int seen = -1;
  for (const auto& object : objects) {
    if (object->status == ObjectStatus::kDropped) continue;
    const int last = object->last_keyframe;
    if (last < k && last > seen &&
        (object->position() - t_w).norm() <= options.gate_position) {
      seen = last;
    }
  }
  return seen;
}

double PlaceGrowth(const std::vector<std::unique_ptr<KeyframeState>>& keyframes,
                   int j,
                   int k,
                   double distance) {
  if (j < 0) return 0.0;
  const KeyframeState& now = *keyframes[k];
  const KeyframeState& then = *keyframes[j];
  return (now.summed_motion_variance_t - then.summed_motion_variance_t) +
         distance * distance *
             (now.summed_motion_variance_r - then.summed_motion_variance_r);
}

namespace {

AssociationScope OneStep(AssociationScope scope) {
  scope.place_variance = 0.0;
  scope.place_object = nullptr;
  return scope;
}

// No object but `o` within `radius` of it.
bool AloneWithin(const ObjectList& objects, size_t o, double radius) {
  for (size_t other = 0; other < objects.size(); ++other) {
    if (other == o || objects[other]->status == ObjectStatus::kDropped) {
      continue;
    }
    if ((objects[other]->position() - objects[o]->position()).norm() <=
        radius) {
      return false;
    }
  }
  return true;
}

// Whether `shift` explains the keyframe's other detections near object
// `o` (within `radius` of it once moved): more of them, moved by it, lie
// within one step's gate of an object of their class (other than `o`)
// than do not, and at least one does.
bool ShiftExplainsThePlace(const ObjectList& objects,
                           const std::vector<RevisitDetection>& detections,
                           size_t i,
                           size_t o,
                           const Eigen::Vector3d& shift,
                           double radius,
                           const BackendOptions& options) {
  int explained = 0;
  int unexplained = 0;
  for (size_t j = 0; j < detections.size(); ++j) {
    const RevisitDetection& other = detections[j];
    const Eigen::Vector3d moved = other.t_w + shift;
    if (j == i || (moved - objects[o]->position()).norm() > radius) continue;
    const AssociationScope scope = OneStep(other.scope);
    bool found = false;
    for (size_t p = 0; p < objects.size() && !found; ++p) {
      const ObjectState& object = *objects[p];
      found = p != o && object.status != ObjectStatus::kDropped &&
              object.class_name == *other.class_name &&
              (object.position() - moved).norm() <=
                  PositionGate(object, scope, options);
    }
    ++(found ? explained : unexplained);
  }
  return explained > 0 && explained > unexplained;
}

}  // namespace

std::vector<RevisitGate> RevisitGates(
    const ObjectList& objects,
    const std::vector<RevisitDetection>& detections,
    const BackendOptions& options) {
  std::vector<RevisitGate> gates(detections.size());
  for (size_t i = 0; i < detections.size(); ++i) {
    const RevisitDetection& detection = detections[i];
    if (detection.scope.place_variance <= detection.scope.prediction_variance) {
      continue;
    }
    const AssociationScope one_step = OneStep(detection.scope);
    AssociationScope grown = detection.scope;
    int nearest = -1;
    double nearest_distance = std::numeric_limits<double>::infinity();
    bool within_one_step = false;
    for (size_t o = 0; o < objects.size() && !within_one_step; ++o) {
      const ObjectState& object = *objects[o];
      if (object.status == ObjectStatus::kDropped ||
          object.class_name != *detection.class_name) {
        continue;
      }
      const Eigen::Vector3d shift = object.position() - detection.t_w;
      const double d = shift.norm();
      within_one_step = d <= PositionGate(object, one_step, options);
      grown.place_object = &object;
      if (within_one_step || d >= nearest_distance ||
          d > PositionGate(object, grown, options)) {
        continue;
      }
      if (AloneWithin(objects, o, detection.distance) ||
          ShiftExplainsThePlace(
              objects, detections, i, o, shift, detection.distance, options)) {
        nearest = static_cast<int>(o);
        nearest_distance = d;
      }
    }
    if (!within_one_step && nearest >= 0) {
      gates[i] = RevisitGate{detection.scope.place_variance, nearest};
    }
  }
  return gates;
}

double PositionGate(const ObjectState& object,
                    const AssociationScope& scope,
                    const BackendOptions& options) {
  if (!scope.sigma_t || options.gate_sigmas <= 0.0) {
    return options.gate_position;
  }
  const double n = std::max<size_t>(1, object.observations.size());
  const double prediction =
      &object == scope.place_object
          ? std::max(scope.prediction_variance, scope.place_variance)
          : scope.prediction_variance;
  const double variance =
      *scope.sigma_t * *scope.sigma_t * (1.0 + 1.0 / n) + prediction;
  return std::min(options.gate_position,
                  options.gate_sigmas * std::sqrt(variance));
}

int FindSixDofMatch(const ObjectList& objects,
                    const std::string& class_name,
                    const std::vector<Rigid3d>& T_wo_candidates,
                    const AssociationScope& scope,
                    const BackendOptions& options) {
  int best = -1;
  double best_score = std::numeric_limits<double>::infinity();
  for (size_t o = 0; o < objects.size(); ++o) {
    const ObjectState& object = *objects[o];
    if (object.class_name != class_name || object.status != scope.status) {
      continue;
    }
    const double gate_t = PositionGate(object, scope, options);
    const Eigen::Quaterniond R_wo = object.Rotation(-1);
    for (const Rigid3d& T_wo : T_wo_candidates) {
      const double d_t = (T_wo.t - object.position()).norm();
      const double d_r = T_wo.q.angularDistance(R_wo);
      if (d_t > gate_t || d_r > options.gate_rotation) {
        continue;
      }
      const double score =
          d_t / options.gate_position + d_r / options.gate_rotation;
      if (score < best_score) {
        best_score = score;
        best = static_cast<int>(o);
      }
    }
  }
  return best;
}

namespace {

// Both asymmetric: the 6-DoF rotation distance to the nearest inlier
// hypothesis (the base pose without inliers), and that hypothesis' world
// rotation.
double NearestRotation(const Eigen::Quaterniond& R_wo,
                       const Rigid3d& T_wc,
                       const CategorizedDetection& cat,
                       const std::vector<PoseHypothesis>& hyps,
                       Eigen::Quaterniond* nearest) {
  const Eigen::Quaterniond R_wo_det = T_wc.q * cat.T_co_base.q;
  double d_r = std::numeric_limits<double>::infinity();
  *nearest = R_wo_det;
  for (int j : cat.inliers) {
    const Eigen::Quaterniond R = T_wc.q * hyps[j].T_co.q.normalized();
    const double d = R.angularDistance(R_wo);
    if (d < d_r) {
      d_r = d;
      *nearest = R;
    }
  }
  if (cat.inliers.empty()) d_r = R_wo_det.angularDistance(R_wo);
  return d_r;
}

// 6 DoF failed: the relative rotation may still be a twist about an axis
// (the prior's, within gate_axis, or its own), making the object discrete.
// False if it cannot.
bool UpgradeAxis(const Eigen::Quaterniond& R_wo,
                 const Eigen::Quaterniond& nearest,
                 const ClassPrior* prior,
                 const BackendOptions& options,
                 Eigen::Vector3d* a_o) {
  if (prior && prior->symmetry == SymmetryType::kAsymmetric) return false;
  const Eigen::Quaterniond R_rel = R_wo.conjugate() * nearest;
  *a_o = LogSO3(R_rel).normalized();
  if (prior && prior->axis_o.norm() > 0.0) {
    *a_o = prior->axis_o.normalized();
    const SwingTwist<double> st = DecomposeSwingTwist(R_rel, *a_o);
    if (2.0 * std::asin(std::min(1.0, st.swing.vec().norm())) >
        options.gate_axis) {
      return false;
    }
  }
  return true;
}

}  // namespace

SymbaMatch FindSymbaMatch(const ObjectList& objects,
                          const Rigid3d& T_wc,
                          const CategorizedDetection& cat,
                          const std::string& class_name,
                          const std::vector<PoseHypothesis>& hyps,
                          const ClassPrior* prior,
                          const AssociationScope& scope,
                          const BackendOptions& options) {
  const bool det_symmetric = cat.type != SymmetryType::kAsymmetric;
  const Eigen::Vector3d t_w = T_wc * cat.t_co;
  const Eigen::Quaterniond R_wo_det = T_wc.q * cat.T_co_base.q;

  SymbaMatch best;
  double best_score = std::numeric_limits<double>::infinity();
  for (size_t o = 0; o < objects.size(); ++o) {
    const ObjectState& object = *objects[o];
    if (object.class_name != class_name || object.status != scope.status) {
      continue;
    }
    const double d_t = (t_w - object.position()).norm();
    if (d_t > PositionGate(object, scope, options)) continue;
    const bool obj_symmetric = object.type != SymmetryType::kAsymmetric;
    SymbaMatch candidate;
    candidate.object = static_cast<int>(o);
    double d_angle = 0.0;
    double gate = options.gate_axis;
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
      Eigen::Quaterniond nearest;
      const double d_r = NearestRotation(R_wo, T_wc, cat, hyps, &nearest);
      gate = options.gate_rotation;
      d_angle = d_r;
      if (d_r > options.gate_rotation) {
        if (!UpgradeAxis(R_wo, nearest, prior, options, &candidate.a_o)) {
          continue;
        }
        candidate.flip = true;
        candidate.R_wo_flip = nearest;
        candidate.flip_angle = std::abs(TwistAngle(
            Eigen::Quaterniond(R_wo.conjugate() * nearest), candidate.a_o));
        d_angle = options.gate_axis;  // ranks after any 6-DoF match
        gate = options.gate_axis;
      }
    }
    if (d_angle > gate) continue;
    const double score = d_t / options.gate_position + d_angle / gate;
    if (score < best_score) {
      best_score = score;
      best = candidate;
    }
  }
  return best;
}

int FindAngle(const ObjectState& object,
              const Eigen::Quaterniond& R_wo,
              double gate) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < object.thetas.size(); ++i) {
    const Eigen::Quaterniond R_wo_i = object.Rotation(static_cast<int>(i));
    const double delta =
        std::abs(TwistAngle(Eigen::Quaterniond(R_wo_i.conjugate() * R_wo),
                            Eigen::Vector3d(object.a_o)));
    if (delta < best_distance) {
      best_distance = delta;
      best = static_cast<int>(i);
    }
  }
  return best >= 0 && best_distance <= gate ? best : -1;
}

FoldedAngle FoldToAngle(const ObjectState& object,
                        const Eigen::Quaterniond& R_wo,
                        int order,
                        double gate) {
  const double step = kTwoPi / order;
  FoldedAngle best;
  double best_remainder = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < object.thetas.size(); ++i) {
    const Eigen::Quaterniond R_wo_i = object.Rotation(static_cast<int>(i));
    const double delta =
        TwistAngle(Eigen::Quaterniond(R_wo_i.conjugate() * R_wo),
                   Eigen::Vector3d(object.a_o));
    const int multiple = static_cast<int>(std::lround(delta / step));
    const double remainder = std::abs(delta - multiple * step);
    if (remainder < best_remainder) {
      best_remainder = remainder;
      best.angle = static_cast<int>(i);
      best.multiple = multiple;
    }
  }
  return best_remainder <= gate ? best : FoldedAngle();
}

double NewAngleTheta(const ObjectState& object,
                     const Eigen::Quaterniond& R_wo) {
  const double theta_0 = object.thetas.empty() ? 0.0 : *object.thetas[0];
  const Eigen::Quaterniond R_wo_0 =
      SymmetricObjectRotation(object.anchor, object.axis_w(), theta_0);
  return WrapToPi(theta_0 +
                  TwistAngle(Eigen::Quaterniond(R_wo_0.conjugate() * R_wo),
                             Eigen::Vector3d(object.a_o)));
}

}  // namespace symba::internal
