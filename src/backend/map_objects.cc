// Backend::Impl: the object lifecycle (method notes Sec. 5). A map object is
// created from its first detection, may be upgraded from asymmetric to
// discrete or continuous when a detection shows its symmetry, gains one
// observation (and one edge) per detection mode, and a discrete object is
// re-anchored when its axis drifts far from its anchor. Every observation
// is kept, so an object's edges can be rebuilt when its type or anchor
// changes.
#include <algorithm>
#include <cmath>
#include <utility>

#include "backend/backend_impl.h"
#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/continuous_object_edge.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/geometry/swing_twist.h"

namespace symba {

using internal::FactorRecord;
using internal::KeyframeState;
using internal::ObjectObservation;
using internal::ObjectState;

int Backend::Impl::CreateObject(const std::string& class_name,
                                SymmetryType type) {
  auto object = std::make_unique<ObjectState>();
  object->id = static_cast<int>(objects_.size());
  object->class_name = class_name;
  object->type = type;
  objects_.push_back(std::move(object));
  ObjectState& created = *objects_.back();
  problem_.SetManifold(created.q, &quaternion_manifold_);
  problem_.SetManifold(created.a_w, &axis_manifold_);
  ++statistics_.objects;
  return created.id;
}

int Backend::Impl::CreateSymbaObject(const std::string& class_name,
                                     const CategorizedDetection& cat,
                                     const Rigid3d& T_wc) {
  const int o = CreateObject(class_name, cat.type);
  ObjectState& object = *objects_[o];
  const Rigid3d T_wo_base = T_wc * cat.T_co_base;
  internal::WritePose(T_wo_base, object.q, object.t);
  if (cat.type != SymmetryType::kAsymmetric) {
    object.a_o = cat.axis_o.normalized();
    object.anchor = SymmetryAnchor::FromObjectRotation(T_wo_base.q, object.a_o);
    Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  }
  return o;
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

int Backend::Impl::MatchOrAddAngle(int o, const Eigen::Quaterniond& R_wo) {
  ObjectState& object = *objects_[o];
  const int angle = internal::FindAngle(object, R_wo, options_.gate_angle);
  if (angle >= 0) return angle;
  object.thetas.push_back(
      std::make_unique<double>(internal::NewAngleTheta(object, R_wo)));
  return static_cast<int>(object.thetas.size()) - 1;
}

void Backend::Impl::AddObservation(int o, ObjectObservation observation) {
  ObjectState& object = *objects_[o];
  object.observations.push_back(std::move(observation));
  AddObjectFactor(o, object.observations.back());
}

void Backend::Impl::AddObjectFactor(int o,
                                    const ObjectObservation& observation) {
  FactorRecord record;
  record.cost = BuildObjectEdge(keyframes_[observation.keyframe].get(),
                                objects_[o].get(),
                                observation,
                                &record.blocks);
  record.loss = object_loss_.get();
  record.keyframe = observation.keyframe;
  record.object = o;
  AddFactor(std::move(record));
}

void Backend::Impl::RebuildObjectFactors(int o) {
  ObjectState& object = *objects_[o];
  for (int f : object.factors) problem_.Retire(f);
  object.factors.clear();
  for (const ObjectObservation& observation : object.observations) {
    AddObjectFactor(o, observation);
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

// The edge of one observation for the object's current type (method notes
// Eq. 14-20): asymmetric 6 DoF on (T_wc, T_wo); discrete on (T_wc, t_wo,
// a_w, theta_i); continuous (or a continuous view of a discrete object) on
// (T_wc, t_wo, a_w) with the measured axis signed like the map axis.
std::unique_ptr<ceres::CostFunction> Backend::Impl::BuildObjectEdge(
    KeyframeState* kf,
    ObjectState* object,
    const ObjectObservation& observation,
    std::vector<double*>* blocks) const {
  if (object->type == SymmetryType::kAsymmetric) {
    std::unique_ptr<AsymmetricObjectEdge> edge;
    Status status = CreateAsymmetricObjectEdge(
        observation.components, options_.mixture, &edge);
    *blocks = {kf->q, kf->t, object->q, object->t};
    return status.ok() ? std::move(edge) : nullptr;
  }
  if (object->type == SymmetryType::kDiscrete && observation.angle >= 0) {
    std::unique_ptr<DiscreteObjectEdge> edge;
    Status status = CreateDiscreteObjectEdge(
        observation.components, object->anchor, options_.mixture, &edge);
    *blocks = {kf->q,
               kf->t,
               object->t,
               object->a_w,
               object->thetas[observation.angle].get()};
    return status.ok() ? std::move(edge) : nullptr;
  }
  std::vector<TranslationComponent> translations;
  for (const PoseComponent& c : observation.components) {
    translations.push_back(
        {c.T_co.t, c.sqrt_info.topLeftCorner<3, 3>(), c.weight});
  }
  AxisMeasurement axis;
  axis.a_c = observation.axis_c.norm() > 0.0
                 ? observation.axis_c.normalized()
                 : Eigen::Vector3d(observation.T_co_best.q * object->a_o);
  if ((kf->T_wc().q * axis.a_c).dot(object->axis_w()) < 0.0) {
    axis.a_c = -axis.a_c;
  }
  axis.sqrt_info = Eigen::Matrix2d::Identity() / options_.axis_sigma;
  axis.gamma = options_.gamma;
  std::unique_ptr<ContinuousObjectEdge> edge;
  Status status =
      CreateContinuousObjectEdge(translations, axis, options_.mixture, &edge);
  *blocks = {kf->q, kf->t, object->t, object->a_w};
  return status.ok() ? std::move(edge) : nullptr;
}

}  // namespace symba
