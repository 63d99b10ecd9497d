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
#include "backend/upgrade_evidence.h"
#include "symba/common/check.h"
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
                                SymmetryType type,
                                int k) {
  auto object = std::make_unique<ObjectState>();
  object->id = static_cast<int>(objects_.size());
  object->class_name = class_name;
  object->type = type;
  object->created_keyframe = k;
  objects_.push_back(std::move(object));
  ObjectState& created = *objects_.back();
  graph_.SetManifold(created.q, &quaternion_manifold_);
  graph_.SetManifold(created.a_w, &axis_manifold_);
  objects_by_class_[class_name].push_back(created.id);
  if (options_.confirm_keyframes > 1) {
    created.status = internal::ObjectStatus::kTentative;
    tentative_.push_back(created.id);
  } else {
    ++statistics_.objects;
  }
  return created.id;
}

void Backend::Impl::NoteDetection(int o, int k, int assignment) {
  ObjectState& object = *objects_[o];
  object.assignments.push_back(assignment);
  if (object.last_keyframe != k) {
    object.last_keyframe = k;
    ++object.keyframes_seen;
  }
}

void Backend::Impl::UpdateTentativeObjects(int k) {
  size_t kept = 0;
  for (int o : tentative_) {
    ObjectState& object = *objects_[o];
    if (object.keyframes_seen >= options_.confirm_keyframes) {
      object.status = internal::ObjectStatus::kConfirmed;
      ++statistics_.objects;
    } else if (k - object.last_keyframe >= options_.tentative_timeout) {
      DropObject(o);
    } else {
      tentative_[kept++] = o;
    }
  }
  tentative_.resize(kept);
}

void Backend::Impl::NoteViewCone(const Eigen::Vector3d& t_co) {
  const double distance = t_co.norm();
  if (!(distance > 0.0)) return;
  view_cone_cos_ = std::min(view_cone_cos_, t_co.z() / distance);
  view_depth_ = std::max(view_depth_, distance);
}

void Backend::Impl::PruneUnsupportedObjects(int k) {
  const Rigid3d T_cw = keyframes_[k]->T_wc().Inverse();
  for (size_t o = 0; o < objects_.size(); ++o) {
    ObjectState& object = *objects_[o];
    if (object.status != internal::ObjectStatus::kConfirmed) continue;
    const Eigen::Vector3d p_c = T_cw * object.position();
    const double distance = p_c.norm();
    const bool detected = object.last_keyframe == k;
    const bool in_view =
        detected || (distance > 0.0 && distance <= view_depth_ &&
                     p_c.z() >= view_cone_cos_ * distance);
    if (!in_view) continue;
    ++object.keyframes_in_view;
    if (detected) ++object.keyframes_seen_in_view;
    if (object.keyframes_in_view >= options_.min_support_views &&
        object.keyframes_seen_in_view <
            options_.min_support * object.keyframes_in_view) {
      DropObject(static_cast<int>(o));
      --statistics_.objects;
    }
  }
}

void Backend::Impl::DropObject(int o) {
  ObjectState& object = *objects_[o];
  object.status = internal::ObjectStatus::kDropped;
  for (ObjectObservation& observation : object.observations) {
    if (observation.factor >= 0) graph_.Retire(observation.factor);
    observation.factor = -1;
  }
  if (object.prior_factor >= 0) graph_.Retire(object.prior_factor);
  object.prior_factor = -1;
  for (int a : object.assignments) assignments_[a].object = -1;
  ++statistics_.objects_dropped;
}

int Backend::Impl::CreateSymbaObject(const std::string& class_name,
                                     const CategorizedDetection& cat,
                                     const Rigid3d& T_wc,
                                     int k) {
  const int o = CreateObject(class_name, cat.type, k);
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

bool Backend::Impl::RecordFlip(int o,
                               int k,
                               const internal::SymbaMatch& match) {
  ObjectState& object = *objects_[o];
  internal::FlipEvidence flip;
  flip.keyframe = k;
  flip.a_o = match.a_o;
  flip.angle = match.flip_angle;
  object.flips.push_back(flip);
  const internal::FlipConsensus consensus = internal::ConsistentFlips(
      object.flips, flip, options_.gate_axis, options_.gate_angle);
  const ClassPrior* prior = PriorOf(object.class_name);
  int order = 0;
  if (prior && prior->symmetry == SymmetryType::kDiscrete) {
    if (internal::FitsOrder(consensus.mean_angle,
                            prior->order,
                            options_.upgrade_angle_tolerance)) {
      order = prior->order;
    }
  } else {
    order = internal::PlausibleOrder(consensus.mean_angle,
                                     options_.max_upgrade_order,
                                     options_.upgrade_angle_tolerance);
  }
  // keyframes_seen counts this keyframe only after the detection.
  const int seen = object.keyframes_seen + (object.last_keyframe == k ? 0 : 1);
  if (consensus.count < options_.upgrade_evidence ||
      consensus.count < options_.upgrade_min_fraction * seen || order == 0) {
    ++statistics_.rotation_outliers;
    return false;
  }
  internal::UpgradeRecord record;
  record.keyframe = k;
  record.evidence = consensus.count;
  record.order = order;
  record.angle = consensus.mean_angle;
  UpgradeObject(o, SymmetryType::kDiscrete, match.a_o, record);
  return true;
}

void Backend::Impl::UpgradeObject(int o,
                                  SymmetryType type,
                                  const Eigen::Vector3d& a_o,
                                  const internal::UpgradeRecord& record) {
  ObjectState& object = *objects_[o];
  object.upgrade = record;
  object.upgrade->type = type;
  object.flips.clear();
  // The prior's rotation of the asymmetric object has no counterpart in
  // the symmetric parameters: it is marginalised out of the prior, whose
  // information on the position stays (docs/backend.md "The window").
  graph_.RemoveFromObjectPrior(o, {object.q});
  const Eigen::Quaterniond R_wo = object.Rotation(-1);
  object.type = type;
  object.a_o = a_o.normalized();
  object.anchor = SymmetryAnchor::FromObjectRotation(R_wo, object.a_o);
  Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  if (type == SymmetryType::kDiscrete) {
    // The asymmetric pose is angle 0; every past observation constrains it.
    object.thetas.push_back(std::make_unique<double>(0.0));
    object.upgrade_observations = static_cast<int>(object.observations.size());
    for (size_t i = graph_.FirstLiveObservation(object);
         i < object.observations.size();
         ++i) {
      object.observations[i].angle = 0;
    }
  }
  ++statistics_.object_upgrades;
  RebuildObjectFactors(o);
}

int Backend::Impl::KnownOrder(int o) const {
  const ObjectState& object = *objects_[o];
  const ClassPrior* prior = PriorOf(object.class_name);
  if (prior == nullptr || prior->symmetry != SymmetryType::kDiscrete ||
      prior->order < 2 || !(prior->axis_o.norm() > 0.0)) {
    return 0;
  }
  const double alignment =
      std::abs(prior->axis_o.normalized().dot(Eigen::Vector3d(object.a_o)));
  return alignment >= std::cos(options_.gate_axis) ? prior->order : 0;
}

// Folding: only a detection that shows one mode folds (the modes of one
// detection showing several open the angles between them, tied by its
// edges). R_wo' = R_wo Rot(a_o, -m step) is the same physical pose (a
// symmetry of the class), so every component is turned alike in the object
// frame, T_co' = T_co (Rot(a_o, -m step), 0); positions and the measured
// axis R_co a_o are unchanged.
int Backend::Impl::MatchOrAddAngle(int o,
                                   const Rigid3d& T_wc,
                                   bool may_fold,
                                   internal::ObjectObservation* observation) {
  ObjectState& object = *objects_[o];
  const Eigen::Quaterniond R_wo = (T_wc * observation->T_co_best).q;
  const int angle = internal::FindAngle(object, R_wo, options_.gate_angle);
  if (angle >= 0) return angle;
  const int order = may_fold ? KnownOrder(o) : 0;
  if (order > 0) {
    const internal::FoldedAngle folded =
        internal::FoldToAngle(object, R_wo, order, options_.gate_angle);
    if (folded.angle >= 0) {
      const Eigen::Quaterniond turn(Eigen::AngleAxisd(
          -folded.multiple * kTwoPi / order, Eigen::Vector3d(object.a_o)));
      observation->T_co_best.q = (observation->T_co_best.q * turn).normalized();
      for (PoseComponent& component : observation->components) {
        component.T_co.q = (component.T_co.q * turn).normalized();
      }
      ++statistics_.folded_angles;
      return folded.angle;
    }
  }
  object.thetas.push_back(
      std::make_unique<double>(internal::NewAngleTheta(object, R_wo)));
  return static_cast<int>(object.thetas.size()) - 1;
}

void Backend::Impl::AddObservation(int o, ObjectObservation observation) {
  ObjectState& object = *objects_[o];
  object.observations.push_back(std::move(observation));
  AddObjectFactor(o, static_cast<int>(object.observations.size()) - 1);
}

void Backend::Impl::AddObjectFactor(int o, int i) {
  const ObjectObservation& observation = objects_[o]->observations[i];
  FactorRecord record;
  record.cost = BuildObjectEdge(keyframes_[observation.keyframe].get(),
                                objects_[o].get(),
                                observation,
                                &record.blocks);
  record.loss = object_loss_.get();
  record.keyframe = observation.keyframe;
  record.object = o;
  record.observation = i;
  objects_[o]->observations[i].factor = graph_.Add(std::move(record));
}

void Backend::Impl::RebuildObjectFactors(int o) {
  ObjectState& object = *objects_[o];
  const int first = graph_.FirstLiveObservation(object);
  RebuildObjectFactors(o, first, static_cast<int>(object.observations.size()));
  object.stale_observations = std::max(object.stale_observations, first);
}

void Backend::Impl::RebuildObjectFactors(int o, int begin, int end) {
  ObjectState& object = *objects_[o];
  for (int i = begin; i < end; ++i) {
    ObjectObservation& observation = object.observations[i];
    if (observation.factor >= 0) graph_.Retire(observation.factor);
    AddObjectFactor(o, i);
  }
}

void Backend::Impl::RebuildStaleObjectFactors() {
  for (size_t o = 0; o < objects_.size(); ++o) {
    ObjectState& object = *objects_[o];
    if (object.stale_observations == 0 ||
        object.status == internal::ObjectStatus::kDropped) {
      continue;
    }
    if (object.type == SymmetryType::kDiscrete) {
      for (int i = 0; i < object.upgrade_observations; ++i) {
        if (object.observations[i].angle < 0) object.observations[i].angle = 0;
      }
    }
    RebuildObjectFactors(static_cast<int>(o), 0, object.stale_observations);
    object.stale_observations = 0;
  }
}

// ---------------------------------------------------------------------------
// The detector's noise (detection_noise.h).

void Backend::Impl::UpdateDetectionNoise(
    const std::vector<std::string>& classes) {
  for (const std::string& class_name : classes) {
    const internal::ClassNoise estimate = noise_.Estimate(class_name);
    internal::ClassNoise& applied = applied_noise_[class_name];
    auto moved = [&](const std::optional<double>& now,
                     const std::optional<double>& before) {
      if (!now) return false;
      if (!before) return true;
      const double ratio = *now / *before;
      return ratio > options_.noise_update_ratio ||
             ratio < 1.0 / options_.noise_update_ratio;
    };
    if (!moved(estimate.sigma_t, applied.sigma_t) &&
        !moved(estimate.sigma_r, applied.sigma_r)) {
      continue;
    }
    applied = estimate;
    for (int o : objects_by_class_[class_name]) {
      if (objects_[o]->status != internal::ObjectStatus::kDropped) {
        RebuildObjectFactors(o);
      }
    }
  }
}

void Backend::Impl::SampleNoise(int o,
                                int k,
                                const Eigen::Vector3d& t_co,
                                const std::optional<Eigen::Quaterniond>& R_co) {
  using Kind = internal::DetectionNoiseEstimator::Kind;
  ObjectState& object = *objects_[o];
  const Rigid3d& T_wc = keyframes_[k]->T_wc_chain;
  const Eigen::Vector3d p = T_wc * t_co;
  const bool sample = object.status == internal::ObjectStatus::kConfirmed;
  const bool consecutive = object.chain_last_keyframe == k - 1;
  if (sample && object.chain_count > 0) {
    noise_.AddTranslation(
        object.class_name,
        Kind::kLevel,
        (p - object.chain_position_sum / object.chain_count).norm());
    if (consecutive) {
      noise_.AddTranslation(object.class_name,
                            Kind::kIncrement,
                            (p - object.chain_last_position).norm());
    }
  }
  object.chain_position_sum += p;
  ++object.chain_count;
  object.chain_last_position = p;
  object.chain_last_keyframe = k;
  if (!R_co || object.type != SymmetryType::kAsymmetric) {
    object.chain_last_rotation.reset();
    return;
  }
  Eigen::Quaterniond R = (T_wc.q * *R_co).normalized();
  if (object.chain_rotation_count > 0) {
    const Eigen::Quaterniond mean(
        Eigen::Vector4d(object.chain_rotation_sum.normalized()));
    if (sample) {
      noise_.AddRotation(
          object.class_name, Kind::kLevel, mean.angularDistance(R));
      if (consecutive && object.chain_last_rotation) {
        noise_.AddRotation(object.class_name,
                           Kind::kIncrement,
                           object.chain_last_rotation->angularDistance(R));
      }
    }
    // The sum averages quaternions of one sign.
    if (mean.coeffs().dot(R.coeffs()) < 0.0) R.coeffs() = -R.coeffs();
  }
  object.chain_rotation_sum += R.coeffs();
  ++object.chain_rotation_count;
  object.chain_last_rotation = R;
}

// ---------------------------------------------------------------------------
// Re-anchoring and edges.

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
    // The angles now measure from another base: out of the prior.
    std::vector<double*> thetas;
    for (const auto& theta : object.thetas) thetas.push_back(theta.get());
    graph_.RemoveFromObjectPrior(static_cast<int>(o), thetas);
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
  // The components with the effective noise, where the class has an
  // estimate (detection_noise.h); as the detection gave them otherwise.
  std::vector<PoseComponent> components = observation.components;
  const auto noise = applied_noise_.find(object->class_name);
  if (noise != applied_noise_.end()) {
    const Matrix6d sqrt_info = IsotropicPoseSqrtInfo(
        internal::EffectiveSigma(
            observation.sigma_t, observation.claimed_t, noise->second.sigma_t),
        internal::EffectiveSigma(
            observation.sigma_r, observation.claimed_r, noise->second.sigma_r));
    for (PoseComponent& c : components) c.sqrt_info = sqrt_info;
  }
  if (object->type == SymmetryType::kAsymmetric) {
    std::unique_ptr<AsymmetricObjectEdge> edge;
    Status status =
        CreateAsymmetricObjectEdge(components, options_.mixture, &edge);
    *blocks = {kf->q, kf->t, object->q, object->t};
    SYMBA_CHECK(status.ok()) << status.message();  // inputs were validated
    return edge;
  }
  if (object->type == SymmetryType::kDiscrete && observation.angle >= 0) {
    std::unique_ptr<DiscreteObjectEdge> edge;
    Status status = CreateDiscreteObjectEdge(
        components, object->anchor, options_.mixture, &edge);
    *blocks = {kf->q,
               kf->t,
               object->t,
               object->a_w,
               object->thetas[observation.angle].get()};
    SYMBA_CHECK(status.ok()) << status.message();  // inputs were validated
    return edge;
  }
  std::vector<TranslationComponent> translations;
  for (const PoseComponent& c : components) {
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
  SYMBA_CHECK(status.ok()) << status.message();  // inputs were validated
  return edge;
}

}  // namespace symba
