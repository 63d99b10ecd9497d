// The backend's map objects: lifecycle, upgrades, angles, re-anchoring and
// the detector's noise samples (object_map.h).
#include "backend/object_map.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "backend/loaded_object_prior.h"
#include "backend/object_track.h"
#include "backend/upgrade_evidence.h"
#include "symba/geometry/pi.h"
#include "symba/geometry/swing_twist.h"

namespace symba::internal {

ObjectMap::ObjectMap(const BackendOptions& options,
                     const std::map<std::string, ClassPrior>& class_priors,
                     FactorGraph* graph,
                     BackendStatistics* statistics,
                     std::vector<DetectionAssignment>* assignments)
    : options_(options),
      class_priors_(class_priors),
      graph_(graph),
      statistics_(statistics),
      assignments_(assignments),
      noise_(options.noise_window, options.noise_min_samples),
      motion_claims_(options.noise_window,
                     options.noise_min_samples,
                     options.motion_noise_tolerance,
                     options.claimed_noise_tolerance),
      claim_pairs_(options.gate_position, options.gate_rotation) {}

const ClassPrior* ObjectMap::PriorOf(const std::string& class_name) const {
  const auto it = class_priors_.find(class_name);
  return it == class_priors_.end() ? nullptr : &it->second;
}

const std::vector<int>& ObjectMap::ObjectsOfClass(
    const std::string& class_name) const {
  static const std::vector<int> kNone;
  const auto it = objects_by_class_.find(class_name);
  return it == objects_by_class_.end() ? kNone : it->second;
}

// ---------------------------------------------------------------------------
// Lifecycle.

int ObjectMap::Create(const std::string& class_name,
                      SymmetryType type,
                      const Rigid3d& T_wo,
                      int k) {
  auto object = std::make_unique<ObjectState>();
  object->id = static_cast<int>(objects_.size());
  object->class_name = class_name;
  object->type = type;
  object->created_keyframe = k;
  objects_.push_back(std::move(object));
  ObjectState& created = *objects_.back();
  WritePose(T_wo, created.q, created.t);
  graph_->SetManifold(created.q, &quaternion_manifold_);
  graph_->SetManifold(created.a_w, &axis_manifold_);
  objects_by_class_[class_name].push_back(created.id);
  if (options_.confirm_keyframes > 1) {
    created.status = ObjectStatus::kTentative;
    tentative_.push_back(created.id);
  } else {
    ++statistics_->objects;
    ++confirmations_;
  }
  return created.id;
}

int ObjectMap::CreateSymba(const std::string& class_name,
                           const CategorizedDetection& cat,
                           const Rigid3d& T_wc,
                           int k) {
  const Rigid3d T_wo_base = T_wc * cat.T_co_base;
  const int o = Create(class_name, cat.type, T_wo_base, k);
  ObjectState& object = *objects_[o];
  if (cat.type != SymmetryType::kAsymmetric) {
    object.a_o = cat.axis_o.normalized();
    object.anchor = SymmetryAnchor::FromObjectRotation(T_wo_base.q, object.a_o);
    Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  }
  return o;
}

void ObjectMap::NoteDetection(int o,
                              int k,
                              int assignment,
                              const Eigen::Vector3d& t_co) {
  ObjectState& object = *objects_[o];
  ++object.detections;
  object.assignments.push_back(assignment);
  if (object.last_keyframe != k) {
    object.last_keyframe = k;
    ++object.keyframes_seen;
    if (object.type == SymmetryType::kAsymmetric) {
      ++class_flips_[object.class_name].keyframes;
    }
  }
  const double distance = t_co.norm();
  if (!(distance > 0.0)) return;
  view_cone_cos_ = std::min(view_cone_cos_, t_co.z() / distance);
  view_depth_ = std::max(view_depth_, distance);
}

void ObjectMap::NoteTrackStep(ObjectState& object, const TrackStep& step) {
  if (object.status == ObjectStatus::kTentative) {
    if (object.track.size() == kMaxTrackSteps) {
      object.track.erase(object.track.begin());
    }
    object.track.push_back(step);
  } else if (object.status == ObjectStatus::kConfirmed) {
    noise_.AddTrackStep(object.class_name, step);
  }
}

bool ObjectMap::TrackLooksStatic(const ObjectState& object) const {
  if (!options_.estimate_noise || options_.track_tolerance <= 0.0) {
    return true;
  }
  const std::optional<double> sigma_increment =
      noise_.TranslationIncrementSigma(object.class_name);
  if (!sigma_increment) return true;
  const std::optional<double> reference =
      noise_.TrackRatio(object.class_name, *sigma_increment);
  if (!reference) return true;
  return MedianStepRatio(object.track, *sigma_increment) <=
         options_.track_tolerance * *reference;
}

void ObjectMap::UpdateTentative(int k) {
  size_t kept = 0;
  for (int o : tentative_) {
    ObjectState& object = *objects_[o];
    if (object.keyframes_seen >= options_.confirm_keyframes &&
        TrackLooksStatic(object)) {
      object.status = ObjectStatus::kConfirmed;
      object.track = {};
      ++statistics_->objects;
      ++confirmations_;
    } else if (k - object.last_keyframe >= options_.tentative_timeout) {
      Drop(o);
    } else {
      tentative_[kept++] = o;
    }
  }
  tentative_.resize(kept);
}

void ObjectMap::PruneUnsupported(int k, const Rigid3d& T_wc) {
  const Rigid3d T_cw = T_wc.Inverse();
  for (size_t o = 0; o < objects_.size(); ++o) {
    ObjectState& object = *objects_[o];
    if (object.status != ObjectStatus::kConfirmed) continue;
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
      Drop(static_cast<int>(o));
      --statistics_->objects;
    }
  }
}

void ObjectMap::Drop(int o) {
  ObjectState& object = *objects_[o];
  object.status = ObjectStatus::kDropped;
  for (ObjectObservation& observation : object.observations) {
    if (observation.factor >= 0) graph_->Retire(observation.factor);
    observation.factor = -1;
  }
  if (object.prior_factor >= 0) graph_->Retire(object.prior_factor);
  object.prior_factor = -1;
  for (int a : object.assignments) (*assignments_)[a].object = -1;
  ++statistics_->objects_dropped;
}

std::vector<ObjectObservation> ObjectMap::MergeInto(int from, int into) {
  ObjectState& duplicate = *objects_[from];
  ObjectState& object = *objects_[into];
  duplicate.status = ObjectStatus::kDropped;
  for (ObjectObservation& observation : duplicate.observations) {
    if (observation.factor >= 0) graph_->Retire(observation.factor);
    observation.factor = -1;
  }
  // What its detections that left the window told about it is lost with
  // its prior: a few detections, against the merged object's own.
  if (duplicate.prior_factor >= 0) graph_->Retire(duplicate.prior_factor);
  duplicate.prior_factor = -1;
  for (int a : duplicate.assignments) {
    (*assignments_)[a].object = object.id;
    object.assignments.push_back(a);
  }
  duplicate.assignments.clear();
  object.detections += duplicate.detections;
  object.keyframes_seen += duplicate.keyframes_seen;
  object.keyframes_in_view += duplicate.keyframes_in_view;
  object.keyframes_seen_in_view += duplicate.keyframes_seen_in_view;
  object.last_keyframe =
      std::max(object.last_keyframe, duplicate.last_keyframe);
  object.flips.insert(
      object.flips.end(), duplicate.flips.begin(), duplicate.flips.end());
  object.flips_left_behind += duplicate.flips_left_behind;
  object.flip_keyframes += duplicate.flip_keyframes;
  // The noise samples go on from the copy detected last (a revisit's
  // duplicate, or the earlier object where the two were seen in turn): the
  // front end's chain has drifted since the other was last seen, and a
  // level measured against its old mean would be the drift, not the
  // detector.
  if (duplicate.chain.last_keyframe > object.chain.last_keyframe) {
    object.chain = duplicate.chain;
  }
  --statistics_->objects;
  ++statistics_->objects_merged;
  return std::move(duplicate.observations);
}

int ObjectMap::MatchOrAddAngle(int o,
                               const Eigen::Quaterniond& R_wo,
                               const std::vector<int>& taken,
                               int* multiple) {
  return MatchFoldOrAddAngle(o, R_wo, KnownOrder(o), taken, multiple);
}

int ObjectMap::MatchFoldOrAddAngle(int o,
                                   const Eigen::Quaterniond& R_wo,
                                   int order,
                                   const std::vector<int>& taken,
                                   int* multiple) {
  *multiple = 0;
  const int angle = FindAngle(*objects_[o], R_wo, options_.gate_angle);
  if (angle >= 0) return angle;
  if (order > 0) {
    const FoldedAngle folded =
        FoldToAngle(*objects_[o], R_wo, order, options_.gate_angle);
    if (folded.angle >= 0 &&
        std::find(taken.begin(), taken.end(), folded.angle) == taken.end()) {
      *multiple = folded.multiple;
      ++statistics_->folded_angles;
      return folded.angle;
    }
  }
  return AddAngle(o, R_wo);
}

void ObjectMap::TurnByFold(int o,
                           int multiple,
                           ObjectObservation* observation) const {
  const int order = KnownOrder(o);
  if (multiple == 0 || order <= 0) return;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(
      -multiple * kTwoPi / order, Eigen::Vector3d(objects_[o]->a_o)));
  observation->T_co_best.q = (observation->T_co_best.q * turn).normalized();
  for (PoseComponent& component : observation->components) {
    component.T_co.q = (component.T_co.q * turn).normalized();
  }
}

int ObjectMap::AddAngle(int o, const Eigen::Quaterniond& R_wo) {
  ObjectState& object = *objects_[o];
  object.thetas.push_back(
      std::make_unique<double>(NewAngleTheta(object, R_wo)));
  object.angle_evidence.push_back(0.0);
  return static_cast<int>(object.thetas.size()) - 1;
}

void ObjectMap::Load(const MapObjectEstimate& e) {
  while (static_cast<int>(objects_.size()) < e.id) {
    auto placeholder = std::make_unique<ObjectState>();
    placeholder->id = static_cast<int>(objects_.size());
    placeholder->status = ObjectStatus::kDropped;
    objects_.push_back(std::move(placeholder));
  }
  // Its angle-0 pose: a symmetric object's anchor makes theta = angles[0]
  // (or 0 for a continuous one) reproduce the first pose.
  Rigid3d T_wo(e.poses.front().q.normalized(), e.t_wo);
  if (e.symmetry == SymmetryType::kDiscrete) {
    T_wo.q = T_wo.q * Eigen::Quaterniond(Eigen::AngleAxisd(
                          -e.angles.front(), e.axis_o.normalized()));
  }
  const int o = Create(e.class_name, e.symmetry, T_wo, -1);
  ObjectState& object = *objects_[o];
  if (object.status == ObjectStatus::kTentative) {
    tentative_.pop_back();
    object.status = ObjectStatus::kConfirmed;
    ++statistics_->objects;
  }
  object.detections = e.observations;
  object.loaded_detections = e.observations;
  object.loaded_upgrade = e.upgrade;
  if (e.symmetry != SymmetryType::kAsymmetric) {
    object.a_o = e.axis_o.normalized();
    object.anchor = SymmetryAnchor::FromObjectRotation(T_wo.q, object.a_o);
    Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  }
  for (size_t i = 0; i < e.angles.size(); ++i) {
    object.thetas.push_back(std::make_unique<double>(e.angles[i]));
    object.angle_evidence.push_back(
        i < e.angle_evidence.size() ? e.angle_evidence[i] : 0.0);
  }
  FactorRecord record;
  if (e.covariance &&
      MakeLoadedObjectPrior(o, &object, *e.covariance, &record)) {
    object.prior_factor = graph_->Add(std::move(record));
  }
}

// ---------------------------------------------------------------------------
// Upgrades and angles.

ObjectMap::FlipOutcome ObjectMap::RecordFlip(int o,
                                             int k,
                                             const SymbaMatch& match) {
  ObjectState& object = *objects_[o];
  FlipEvidence flip;
  flip.keyframe = k;
  flip.a_o = match.a_o;
  flip.angle = match.flip_angle;
  const ClassPrior* prior = PriorOf(object.class_name);
  const int known_order =
      prior && prior->symmetry == SymmetryType::kDiscrete ? prior->order : 0;
  if (object.flips.empty() || object.flips.back().keyframe != k) {
    ++object.flip_keyframes;
    CountClassFlip(object.class_name, flip.angle, known_order, 1);
  }
  const ClassFlipCounts& class_flips = class_flips_[object.class_name];
  object.flips.push_back(flip);
  const FlipConsensus consensus = ConsistentFlips(
      object.flips, flip, options_.gate_axis, options_.gate_angle);
  const int order = FlipOrder(consensus.mean_angle, known_order);
  // keyframes_seen counts this keyframe only after the detection.
  const int seen = object.keyframes_seen + (object.last_keyframe == k ? 0 : 1);
  // The views a turn left behind are flips; a loaded map's are views.
  const int unflipped = seen - object.flip_keyframes -
                        object.flips_left_behind + object.loaded_detections;
  if (FlipsOutvoteTheRotation(unflipped,
                              consensus.count,
                              options_.upgrade_confusion_rate,
                              options_.upgrade_odds) &&
      consensus.count >= options_.upgrade_evidence) {
    Turn(o, match.R_wo_flip, unflipped, match.flip_angle, known_order);
    return FlipOutcome::kTurned;
  }
  if (order == 0 || consensus.count < options_.upgrade_evidence ||
      consensus.count < options_.upgrade_min_fraction * seen ||
      TwoRotationsLogOdds(
          unflipped, consensus.count, options_.upgrade_confusion_rate) <
          std::log(options_.upgrade_odds) ||
      !class_flips.FlipsAsSymmetric(order, options_.upgrade_min_fraction)) {
    ++statistics_->rotation_outliers;
    return FlipOutcome::kOutlier;
  }
  UpgradeRecord record;
  record.keyframe = k;
  record.evidence = consensus.count;
  record.order = order;
  record.angle = consensus.mean_angle;
  Upgrade(o, SymmetryType::kDiscrete, match.a_o, record);
  return FlipOutcome::kUpgraded;
}

void ObjectMap::CountClassFlip(const std::string& class_name,
                               double angle,
                               int known_order,
                               int count) {
  ClassFlipCounts& class_flips = class_flips_[class_name];
  for (int order = 2; order <= options_.max_upgrade_order; ++order) {
    if ((known_order == 0 || order == known_order) &&
        FitsOrder(angle, order, options_.upgrade_angle_tolerance)) {
      class_flips.flip_keyframes_by_order[order] += count;
    }
  }
}

void ObjectMap::Turn(int o,
                     const Eigen::Quaterniond& R_wo,
                     int left_behind,
                     double angle,
                     int known_order) {
  ObjectState& object = *objects_[o];
  // What its views said, rotation and position, came from poses the
  // detector had wrong: out of its prior, and its views still in the window
  // carry no information (on YCB-Video 0014 a can made from a detection
  // turned by 86 degrees and 9 cm off stayed there, held by its first four
  // views, while the 35 flips that turned it had no edge).
  if (object.prior_factor >= 0) graph_->Retire(object.prior_factor);
  object.prior_factor = -1;
  const Eigen::Quaterniond R_old = object.Rotation(-1);
  const Eigen::Quaterniond R_new = R_wo.normalized();
  Eigen::Map<Eigen::Quaterniond>(object.q) = R_new;
  // Every earlier view turns with the object (its residual stays small)
  // and weighs nothing: in the window, in a batch solve over the kept
  // history and in the keyframe graph (Backend::Impl::GraphObjects).
  const Eigen::Quaterniond turn = R_old.conjugate() * R_new;
  for (ObjectObservation& observation : object.observations) {
    for (PoseComponent& c : observation.components) {
      c.T_co.q = (c.T_co.q * turn).normalized();
    }
    observation.T_co_best.q = (observation.T_co_best.q * turn).normalized();
    observation.turned_away = true;
    observation.edge_sigma_t = observation.edge_sigma_r = 0.0;
  }
  // Its flips were measured from the rotation it leaves: out of its class's
  // counts (each keyframe's first, as counted), and the views it leaves
  // behind are its flips now, by the same angle.
  for (size_t i = 0; i < object.flips.size(); ++i) {
    if (i == 0 || object.flips[i].keyframe != object.flips[i - 1].keyframe) {
      CountClassFlip(object.class_name, object.flips[i].angle, known_order, -1);
    }
  }
  CountClassFlip(object.class_name, angle, known_order, left_behind);
  object.flips.clear();
  object.flip_keyframes = 0;
  object.flips_left_behind = left_behind;
  // Its rotation samples of the detector's noise were about the rotation it
  // leaves (detection_noise.h): they start again.
  object.chain.rotation_sum.setZero();
  object.chain.rotation_count = 0;
  object.chain.last_rotation.reset();
  ++statistics_->objects_turned;
}

int ObjectMap::FlipOrder(double angle, int known_order) const {
  if (known_order > 0) {
    return FitsOrder(angle, known_order, options_.upgrade_angle_tolerance)
               ? known_order
               : 0;
  }
  return PlausibleOrder(
      angle, options_.max_upgrade_order, options_.upgrade_angle_tolerance);
}

void ObjectMap::Upgrade(int o,
                        SymmetryType type,
                        const Eigen::Vector3d& a_o,
                        const UpgradeRecord& record) {
  ObjectState& object = *objects_[o];
  object.upgrade = record;
  object.upgrade->type = type;
  object.flips.clear();
  object.flip_keyframes = 0;
  // The prior's rotation of the asymmetric object has no counterpart in
  // the symmetric parameters: it is marginalised out of the prior, whose
  // information on the position stays (docs/backend.md "The window").
  graph_->RemoveFromObjectPrior(o, {object.q});
  const Eigen::Quaterniond R_wo = object.Rotation(-1);
  object.type = type;
  object.a_o = a_o.normalized();
  object.anchor = SymmetryAnchor::FromObjectRotation(R_wo, object.a_o);
  Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  if (type == SymmetryType::kDiscrete) {
    // The asymmetric pose is angle 0; every past observation constrains it.
    object.thetas.push_back(std::make_unique<double>(0.0));
    object.upgrade_observations = static_cast<int>(object.observations.size());
    // Each earlier detection with an edge (and each of a loaded map's, an
    // asymmetric object's) saw the object at angle 0.
    object.angle_evidence.push_back(object.upgrade_observations +
                                    object.loaded_detections);
    for (size_t i = graph_->FirstLiveObservation(object);
         i < object.observations.size();
         ++i) {
      object.observations[i].angle = 0;
    }
  }
  ++statistics_->object_upgrades;
}

int ObjectMap::KnownOrder(int o) const {
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
int ObjectMap::MatchOrAddAngle(int o,
                               const Rigid3d& T_wc,
                               bool may_fold,
                               ObjectObservation* observation) {
  const Eigen::Quaterniond R_wo = (T_wc * observation->T_co_best).q;
  int multiple = 0;
  const int angle =
      MatchFoldOrAddAngle(o, R_wo, may_fold ? KnownOrder(o) : 0, {}, &multiple);
  TurnByFold(o, multiple, observation);
  return angle;
}

void ObjectMap::AddAngleEvidence(int o, int angle, double share) {
  objects_[o]->angle_evidence[angle] += share;
}

bool ObjectMap::ReanchorIfDrifted(int o) {
  ObjectState& object = *objects_[o];
  if (object.type != SymmetryType::kDiscrete) return false;
  const Eigen::Vector3d a_w = object.axis_w();
  if (std::acos(std::min(1.0, a_w.dot(object.anchor.a_w0))) <=
      options_.reanchor_angle) {
    return false;
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
  graph_->RemoveFromObjectPrior(o, thetas);
  return true;
}

// ---------------------------------------------------------------------------
// The detector's noise (detection_noise.h).

void ObjectMap::SampleNoise(int o,
                            int k,
                            const Rigid3d& T_wc_chain,
                            const Eigen::Vector3d& t_co,
                            const std::optional<Eigen::Quaterniond>& R_co) {
  using Kind = DetectionNoiseEstimator::Kind;
  ObjectState& object = *objects_[o];
  const Eigen::Vector3d p = T_wc_chain * t_co;
  const bool sample = object.status == ObjectStatus::kConfirmed;
  const bool consecutive = object.chain.last_keyframe == k - 1;
  if (sample && object.chain.count > 0) {
    const Eigen::Vector3d level =
        p - object.chain.position_sum / object.chain.count;
    noise_.AddTranslation(object.class_name, Kind::kLevel, level.norm());
    if (t_co.norm() > 0.0) {
      const Eigen::Vector3d sight = (T_wc_chain.q * t_co).normalized();
      const double along = level.dot(sight);
      noise_.AddSightLevel(
          object.class_name, std::abs(along), (level - along * sight).norm());
    }
    if (consecutive) {
      noise_.AddTranslation(object.class_name,
                            Kind::kIncrement,
                            (p - object.chain.last_position).norm());
    }
  }
  const int j = object.chain.last_keyframe;
  if (j >= 0 && j < k) {
    // The map alone (its tests) may not hold the keyframes: no growth.
    const KeyframeList& keyframes = graph_->keyframes();
    const double growth = k < static_cast<int>(keyframes.size())
                              ? PlaceGrowth(keyframes, j, k, t_co.norm())
                              : 0.0;
    NoteTrackStep(object,
                  TrackStep{(p - object.chain.last_position).norm(), growth});
  }
  object.chain.position_sum += p;
  ++object.chain.count;
  object.chain.last_position = p;
  object.chain.last_keyframe = k;
  if (!R_co || object.type != SymmetryType::kAsymmetric) {
    object.chain.last_rotation.reset();
    return;
  }
  Eigen::Quaterniond R = (T_wc_chain.q * *R_co).normalized();
  if (object.chain.rotation_count > 0) {
    const Eigen::Quaterniond mean(
        Eigen::Vector4d(object.chain.rotation_sum.normalized()));
    if (sample) {
      noise_.AddRotation(
          object.class_name, Kind::kLevel, mean.angularDistance(R));
      if (consecutive && object.chain.last_rotation) {
        noise_.AddRotation(object.class_name,
                           Kind::kIncrement,
                           object.chain.last_rotation->angularDistance(R));
      }
    }
    // The sum averages quaternions of one sign.
    if (mean.coeffs().dot(R.coeffs()) < 0.0) R.coeffs() = -R.coeffs();
  }
  object.chain.rotation_sum += R.coeffs();
  ++object.chain.rotation_count;
  object.chain.last_rotation = R;
}

}  // namespace symba::internal
