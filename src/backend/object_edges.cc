// The edges between keyframes and map objects (object_edges.h).
#include "backend/object_edges.h"

#include <algorithm>
#include <utility>

#include "symba/common/check.h"
#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/continuous_object_edge.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/factors/line_of_sight_rows.h"

namespace symba::internal {

namespace {

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

// True if `now` exists and is off `before` (or there is none) by more than
// `ratio` either way.
bool Moved(const std::optional<double>& now,
           const std::optional<double>& before,
           double ratio) {
  if (!now) return false;
  if (!before) return true;
  const double change = *now / *before;
  return change > ratio || change < 1.0 / ratio;
}

// Takes (t, r) into (kept_t, kept_r) if either moved beyond `ratio`; a
// sigma the estimate does not have (yet) stays as it was. True if so.
bool ApplyPair(const std::optional<double>& t,
               const std::optional<double>& r,
               double ratio,
               std::optional<double>* kept_t,
               std::optional<double>* kept_r) {
  if (!Moved(t, *kept_t, ratio) && !Moved(r, *kept_r, ratio)) return false;
  if (t) *kept_t = t;
  if (r) *kept_r = r;
  return true;
}

}  // namespace

ObjectEdges::ObjectEdges(const BackendOptions& options,
                         const KeyframeList& keyframes,
                         ObjectList* objects,
                         FactorGraph* graph)
    : options_(options),
      keyframes_(keyframes),
      objects_(*objects),
      graph_(graph),
      loss_(MakeLoss(options.object_loss, options.object_loss_scale)) {}

void ObjectEdges::Add(int o, ObjectObservation observation) {
  ObjectState& object = *objects_[o];
  object.observations.push_back(std::move(observation));
  ObjectObservation& added = object.observations.back();
  if (added.components.empty()) {
    // A merged copy's view that had left the window: its edge went with
    // the copy's prior.
    added.edge_sigma_t = added.edge_sigma_r = 0.0;
    return;
  }
  AddFactor(o, static_cast<int>(object.observations.size()) - 1);
}

void ObjectEdges::AddFactor(int o, int i) {
  const ObjectObservation& observation = objects_[o]->observations[i];
  FactorRecord record;
  EdgeSigmas sigmas;
  record.cost = BuildEdge(keyframes_[observation.keyframe].get(),
                          objects_[o].get(),
                          observation,
                          &record.blocks,
                          &sigmas);
  record.loss = loss_.get();
  record.keyframe = observation.keyframe;
  record.object = o;
  record.observation = i;
  ObjectObservation& built = objects_[o]->observations[i];
  built.factor = graph_->Add(std::move(record));
  // What the edge weighs with, for the noise report (ClassNoiseEstimate::
  // weights): a continuous view weighs its axis with axis_sigma.
  const ObjectState& object = *objects_[o];
  const bool weighs_rotation =
      !built.turned_away &&
      (object.type == SymmetryType::kAsymmetric ||
       (object.type == SymmetryType::kDiscrete && built.angle >= 0));
  built.edge_sigma_t = built.turned_away ? 0.0 : sigmas.t;
  built.edge_sigma_r = weighs_rotation ? sigmas.r : 0.0;
}

void ObjectEdges::Rebuild(int o) {
  ObjectState& object = *objects_[o];
  const int first = graph_->FirstLiveObservation(object);
  Rebuild(o, first, static_cast<int>(object.observations.size()));
  object.stale_observations = std::max(object.stale_observations, first);
}

void ObjectEdges::RestoreKeyframeOrder(int o) {
  ObjectState& object = *objects_[o];
  auto by_keyframe = [](const ObjectObservation& a,
                        const ObjectObservation& b) {
    return a.keyframe < b.keyframe;
  };
  if (std::is_sorted(object.observations.begin(),
                     object.observations.end(),
                     by_keyframe)) {
    return;
  }
  std::stable_sort(
      object.observations.begin(), object.observations.end(), by_keyframe);
  // Every edge that can be built is built afresh with its new index; the
  // others' hypotheses are gone and so is anything to rebuild.
  Rebuild(o, 0, static_cast<int>(object.observations.size()));
  object.stale_observations = 0;
}

void ObjectEdges::Rebuild(int o, int begin, int end) {
  ObjectState& object = *objects_[o];
  for (int i = begin; i < end; ++i) {
    ObjectObservation& observation = object.observations[i];
    // Its hypotheses were freed when its keyframe left the window (without
    // keep_history): no edge can be built, and no solve would use one.
    if (observation.components.empty()) continue;
    if (observation.factor >= 0) graph_->Retire(observation.factor);
    AddFactor(o, i);
  }
}

void ObjectEdges::RebuildStale() {
  for (size_t o = 0; o < objects_.size(); ++o) {
    ObjectState& object = *objects_[o];
    if (object.stale_observations == 0 ||
        object.status == ObjectStatus::kDropped) {
      continue;
    }
    if (object.type == SymmetryType::kDiscrete) {
      for (int i = 0; i < object.upgrade_observations; ++i) {
        if (object.observations[i].angle < 0) object.observations[i].angle = 0;
      }
    }
    Rebuild(static_cast<int>(o), 0, object.stale_observations);
    object.stale_observations = 0;
  }
}

bool ObjectEdges::ApplyNoise(const std::string& class_name,
                             const ClassNoise& estimate) {
  // The entry exists from the class's first update on: from then on its
  // edges are built with the effective noise (BuildEdge).
  ClassNoise& applied = applied_noise_[class_name];
  const double ratio = options_.noise_update_ratio;
  // The estimate and the white part each move on their own.
  const bool estimate_moved = ApplyPair(estimate.sigma_t,
                                        estimate.sigma_r,
                                        ratio,
                                        &applied.sigma_t,
                                        &applied.sigma_r);
  const bool white_moved = ApplyPair(estimate.white_sigma_t,
                                     estimate.white_sigma_r,
                                     ratio,
                                     &applied.white_sigma_t,
                                     &applied.white_sigma_r);
  // A claim's factor (HeldFactor); an applied factor of none is 1.
  const double tolerance = options_.claimed_noise_tolerance;
  const auto factor = [tolerance](const std::optional<double>& scale,
                                  const std::optional<double>& applied) {
    const double before = applied.value_or(1.0);
    return scale ? HeldFactor(*scale, before, tolerance) : before;
  };
  const std::optional<double> factor_t =
      factor(estimate.claim_scale_t, applied.claim_scale_t);
  const std::optional<double> factor_r =
      factor(estimate.claim_scale_r, applied.claim_scale_r);
  const auto or_one = [](const std::optional<double>& applied) {
    return std::optional<double>(applied.value_or(1.0));
  };
  const bool claims_moved =
      Moved(factor_t, or_one(applied.claim_scale_t), ratio) ||
      Moved(factor_r, or_one(applied.claim_scale_r), ratio);
  if (claims_moved) {
    applied.claim_scale_t = factor_t;
    applied.claim_scale_r = factor_r;
  }
  // How much wider its errors are along the line of sight
  // (LineOfSightRows).
  const bool sight_moved =
      options_.sight_rows &&
      Moved(estimate.sight_anisotropy, applied.sight_anisotropy, ratio);
  if (sight_moved) applied.sight_anisotropy = estimate.sight_anisotropy;
  return estimate_moved || white_moved || claims_moved || sight_moved;
}

EdgeSigmas EffectiveNoise(const ObjectObservation& observation,
                          const ClassNoise& applied) {
  // Held within the range of a given sigma (backend_options.h), whatever a
  // loaded map's noise or claim factors or an estimate from extreme
  // detections made of it: the edges' and the keyframe graph's information
  // stays finite and invertible.
  if (observation.from_scatter) {
    return {UsableNoiseSigma(EffectiveSigma(
                observation.sigma_t, false, applied.white_sigma_t)),
            UsableNoiseSigma(EffectiveSigma(
                observation.sigma_r, false, applied.white_sigma_r))};
  }
  // A claim times its class's claim factor (ApplyNoise); else the larger
  // of the floor and the estimate.
  const double sigma_t =
      observation.claimed_t
          ? observation.sigma_t * applied.claim_scale_t.value_or(1.0)
          : EffectiveSigma(observation.sigma_t, false, applied.sigma_t);
  const double sigma_r =
      observation.claimed_r
          ? observation.sigma_r * applied.claim_scale_r.value_or(1.0)
          : EffectiveSigma(observation.sigma_r, false, applied.sigma_r);
  return {UsableNoiseSigma(sigma_t), UsableNoiseSigma(sigma_r)};
}

ClassNoise ObjectEdges::AppliedNoise(const std::string& class_name) const {
  const auto it = applied_noise_.find(class_name);
  return it == applied_noise_.end() ? ClassNoise{} : it->second;
}

EdgeSigmas ObjectEdges::BuildNoise(const ObjectState& object,
                                   const ObjectObservation& observation) const {
  const auto noise = applied_noise_.find(object.class_name);
  if (noise != applied_noise_.end()) {
    return EffectiveNoise(observation, noise->second);
  }
  // Isotropic per detection (InitialSqrtInfo): one component tells.
  const Matrix6d& sqrt_info = observation.components.front().sqrt_info;
  return {1.0 / sqrt_info(0, 0), 1.0 / sqrt_info(3, 3)};
}

Eigen::Vector3d MeasuredAxis(const ObjectState& object,
                             const ObjectObservation& observation,
                             const Eigen::Quaterniond& q_wc) {
  Eigen::Vector3d a_c =
      observation.axis_c.norm() > 0.0
          ? observation.axis_c.normalized()
          : Eigen::Vector3d(observation.T_co_best.q * object.a_o.normalized());
  if ((q_wc * a_c).dot(object.axis_w()) < 0.0) a_c = -a_c;
  return a_c;
}

// The edge of one observation for the object's current type (method notes
// Eq. 14-20): asymmetric 6 DoF on (T_wc, T_wo); discrete on (T_wc, t_wo,
// a_w, theta_i); continuous (or a continuous view of a discrete object) on
// (T_wc, t_wo, a_w) with the measured axis signed like the map axis.
std::unique_ptr<ceres::CostFunction> ObjectEdges::BuildEdge(
    KeyframeState* kf,
    ObjectState* object,
    const ObjectObservation& observation,
    std::vector<double*>* blocks,
    EdgeSigmas* sigmas) const {
  std::unique_ptr<ceres::CostFunction> edge =
      BuildMixtureEdge(kf, object, observation, blocks, sigmas);
  const std::optional<SightSigmas> sight = SightNoise(*object, observation);
  if (!sight) return edge;
  const auto position = std::find(blocks->begin(), blocks->end(), object->t);
  SYMBA_CHECK(position != blocks->end());
  const Rigid3d T_wc = kf->T_wc();
  return std::make_unique<LineOfSightRows>(
      std::move(edge),
      static_cast<int>(position - blocks->begin()),
      observation.T_co_best.t,
      sight->along,
      sight->across,
      T_wc.q,
      T_wc.t);
}

std::optional<SightSigmas> ObjectEdges::SightNoise(
    const ObjectState& object, const ObjectObservation& observation) const {
  if (!options_.estimate_noise || !options_.sight_rows ||
      observation.turned_away || observation.claimed_t ||
      observation.from_scatter || !(observation.T_co_best.t.norm() > 0.0)) {
    return std::nullopt;
  }
  const auto noise = applied_noise_.find(object.class_name);
  if (noise == applied_noise_.end() || !noise->second.sigma_t) {
    return std::nullopt;
  }
  const double across = UsableNoiseSigma(*noise->second.sigma_t);
  // Only where the floor weighs the edge: across the line of sight the rows
  // add what it withholds; along it as much as the class's errors there
  // allow (kappa times), never more than the floor.
  if (!(observation.sigma_t > across)) return std::nullopt;
  const double along =
      noise->second.sight_anisotropy
          ? std::min(observation.sigma_t,
                     std::max(1.0, *noise->second.sight_anisotropy) * across)
          : observation.sigma_t;
  return SightSigmas{UsableNoiseSigma(along), across};
}

std::unique_ptr<ceres::CostFunction> ObjectEdges::BuildMixtureEdge(
    KeyframeState* kf,
    ObjectState* object,
    const ObjectObservation& observation,
    std::vector<double*>* blocks,
    EdgeSigmas* sigmas) const {
  // The components with the effective noise, once the class's noise was
  // updated (detection_noise.h); as the detection gave them before.
  std::vector<PoseComponent> components = observation.components;
  *sigmas = BuildNoise(*object, observation);
  if (applied_noise_.count(object->class_name) > 0) {
    const Matrix6d sqrt_info = IsotropicPoseSqrtInfo(sigmas->t, sigmas->r);
    for (PoseComponent& c : components) c.sqrt_info = sqrt_info;
  }
  if (observation.turned_away) {
    for (PoseComponent& c : components) {
      c.sqrt_info = Matrix6d::Identity() / kUninformativeSigma;
    }
  }
  if (options_.detection_errors == DetectionErrors::kIndependent &&
      !observation.turned_away) {
    for (PoseComponent& c : components) {
      c.sqrt_info = DetectionSqrtInfo(c.sqrt_info, c.T_co.t);
    }
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
  axis.a_c = MeasuredAxis(*object, observation, kf->T_wc().q);
  axis.sqrt_info =
      Eigen::Matrix2d::Identity() /
      (observation.turned_away ? kUninformativeSigma : options_.axis_sigma);
  axis.gamma = options_.gamma;
  std::unique_ptr<ContinuousObjectEdge> edge;
  Status status =
      CreateContinuousObjectEdge(translations, axis, options_.mixture, &edge);
  *blocks = {kf->q, kf->t, object->t, object->a_w};
  SYMBA_CHECK(status.ok()) << status.message();  // inputs were validated
  return edge;
}

}  // namespace symba::internal
