// Backend::Impl: a keyframe's detections, per method. Categorisation runs
// for the whole keyframe before anything is added; each detection is then
// associated (the confirmed map first, then tentative objects), turned into
// observations and edges, and sampled for the detector's noise.
#include <optional>
#include <string>
#include <utility>

#include "backend/backend_impl.h"
#include "backend/detection_observations.h"
#include "categorization/categorize_with_valid_options.h"

namespace symba {

using internal::DetectionId;
using internal::KeyframeState;
using internal::Normalized;
using internal::ObjectObservation;

Status Backend::Impl::CategorizeDetections(const KeyframeInput& input) {
  if (categorized_.size() < input.detections.size()) {
    categorized_.resize(input.detections.size());
  }
  scatters_.assign(input.detections.size(), std::nullopt);
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& det = input.detections[d];
    // The baselines categorise only to measure a scatter: every method
    // weighs a detection alike.
    if (options_.method != Method::kSymba &&
        !internal::WantsScatter(det, options_)) {
      continue;
    }
    // Create validated the options and the priors.
    Status status =
        categorization::CategorizeWithValidOptions(det.hypotheses,
                                                   options_.categorization,
                                                   map_.PriorOf(det.class_name),
                                                   &categorized_[d]);
    if (!status.ok()) {
      return Status::Error("keyframe " + std::to_string(input.id) +
                           ": detection " + DetectionId(input, d) + ": " +
                           status.message());
    }
    scatters_[d] = internal::UsableScatter(det, categorized_[d], options_);
  }
  return Status::Ok();
}

std::optional<double> Backend::Impl::GateSigmaT(
    const std::string& class_name,
    const std::optional<double>& scatter_sigma_t) const {
  const internal::ClassNoise applied = edges_.AppliedNoise(class_name);
  if (!scatter_sigma_t) return applied.sigma_t;
  return internal::EffectiveSigma(
      *scatter_sigma_t, false, applied.white_sigma_t);
}

std::optional<double> Backend::Impl::GateSigmaT(
    const std::string& class_name,
    const std::optional<HypothesisScatter>& scatter) const {
  return GateSigmaT(
      class_name,
      scatter ? std::optional<double>(scatter->sigma_t) : std::nullopt);
}

double Backend::Impl::ClaimFactorT(const std::string& class_name) const {
  return edges_.AppliedNoise(class_name).claim_scale_t.value_or(1.0);
}

std::vector<Backend::Impl::Revisit> Backend::Impl::Revisits(
    int k, const KeyframeInput& input) const {
  const KeyframeState& kf = *trajectory_.keyframes()[k];
  const Rigid3d T_wc = kf.T_wc();
  const int window_begin = k + 1 - options_.window_size;
  std::vector<internal::RevisitDetection> detections;
  std::vector<int> seen;
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& detection = input.detections[d];
    // Where its association will look from: the categorisation's position,
    // or a baseline's highest-weight hypothesis.
    const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
    const Eigen::Vector3d t_co =
        options_.method == Method::kSymba
            ? categorized_[d].t_co
            : hyps[internal::HighestWeight(hyps)].T_co.t;
    internal::RevisitDetection revisit;
    revisit.class_name = &detection.class_name;
    revisit.t_w = T_wc * t_co;
    revisit.distance = t_co.norm();
    revisit.scope =
        internal::DetectionScope(detection,
                                 kf,
                                 t_co,
                                 GateSigmaT(detection.class_name, scatters_[d]),
                                 options_,
                                 ClaimFactorT(detection.class_name));
    seen.push_back(
        internal::PlaceLastSeen(map_.objects(), k, revisit.t_w, options_));
    revisit.scope.place_variance = internal::PlaceGrowth(
        trajectory_.keyframes(), seen.back(), k, revisit.distance);
    detections.push_back(revisit);
  }
  const std::vector<internal::RevisitGate> gates =
      internal::RevisitGates(map_.objects(), detections, options_);
  std::vector<Revisit> revisits(gates.size());
  for (size_t d = 0; d < gates.size(); ++d) {
    revisits[d].gate = gates[d];
    revisits[d].before_window = seen[d] < window_begin;
  }
  return revisits;
}

void Backend::Impl::ApplyRevisit(const Revisit& revisit,
                                 internal::AssociationScope* scope) const {
  if (revisit.gate.object < 0) return;
  scope->place_variance = revisit.gate.variance;
  scope->place_object = map_.objects()[revisit.gate.object].get();
}

void Backend::Impl::NoteRevisit(const Revisit& revisit, int object) {
  // Matched through the grown gate (the object lay beyond one step's), to
  // a place last seen before the window.
  if (revisit.gate.object >= 0 && object == revisit.gate.object &&
      revisit.before_window) {
    revisit_pending_ = true;
  }
}

void Backend::Impl::AddDetection(
    int k,
    const DetectionInput& detection,
    const CategorizedDetection* categorized,
    const std::optional<HypothesisScatter>& scatter,
    const std::string& detection_id,
    const Revisit& revisit) {
  const Matrix6d sqrt_info =
      internal::InitialSqrtInfo(detection, scatter, options_);
  const int object =
      categorized != nullptr
          ? AddSymba(k, detection, *categorized, scatter, sqrt_info, revisit)
          : AddSingleOrMultiHypothesis(
                k, detection, scatter, sqrt_info, revisit);
  if (scatter) map_.NoteScatter(detection.class_name, *scatter);
  const SymmetryType type =
      categorized != nullptr ? categorized->type : SymmetryType::kAsymmetric;
  ++statistics_.detections;
  assignments_.push_back({trajectory_.keyframes()[k]->id,
                          detection_id,
                          map_.objects()[object]->id,
                          type});
  map_.NoteDetection(object,
                     k,
                     static_cast<int>(assignments_.size()) - 1,
                     categorized != nullptr
                         ? categorized->t_co
                         : detection.hypotheses.front().T_co.t);
  if (options_.estimate_noise &&
      (detection.sigma_t || detection.sigma_r || scatter)) {
    SampleClaim(k, detection, categorized, scatter);
  }
}

void Backend::Impl::SampleClaim(
    int k,
    const DetectionInput& detection,
    const CategorizedDetection* categorized,
    const std::optional<HypothesisScatter>& scatter) {
  const KeyframeState& kf = *trajectory_.keyframes()[k];
  // Where its edge puts it: the categorisation's pose (its rotation only
  // when asymmetric: a symmetric one's is not one pose), or a baseline's
  // highest-weight hypothesis (its rotation only for a single-pose
  // detection of a class without a symmetric prior: the best of many
  // hypotheses of a symmetric object turns about its axis from keyframe to
  // keyframe, which mh's mixture covers and is no noise).
  const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
  Eigen::Vector3d t_co;
  std::optional<Eigen::Quaterniond> R_co;
  if (categorized != nullptr) {
    t_co = categorized->t_co;
    if (categorized->type == SymmetryType::kAsymmetric) {
      R_co = categorized->T_co_base.q;
    }
  } else {
    const Rigid3d& best = hyps[internal::HighestWeight(hyps)].T_co;
    t_co = best.t;
    const ClassPrior* prior = map_.PriorOf(detection.class_name);
    if (hyps.size() == 1 &&
        (prior == nullptr || prior->symmetry == SymmetryType::kAsymmetric)) {
      R_co = best.q;
    }
  }
  internal::ClaimedDetection claimed;
  claimed.class_name = detection.class_name;
  claimed.p_w = kf.T_wc_chain * t_co;
  if (R_co) claimed.R_w = (kf.T_wc_chain.q * R_co->normalized()).normalized();
  // As the edge takes them (SetObservationNoise): a detection that
  // declares one sigma claims the default for the other; one weighed by
  // its scatter claims nothing, but its noise is known.
  if (detection.sigma_t || detection.sigma_r) {
    claimed.sigma_t = detection.sigma_t.value_or(options_.hypothesis_sigma_t);
    claimed.sigma_r = detection.sigma_r.value_or(options_.hypothesis_sigma_r);
    const double sigma_t =
        *claimed.sigma_t * ClaimFactorT(detection.class_name);
    claimed.variance_t = sigma_t * sigma_t;
  } else if (scatter) {
    // Held to the class's frame-to-frame noise, as its edge is.
    const double sigma_t =
        GateSigmaT(detection.class_name, scatter).value_or(scatter->sigma_t);
    claimed.variance_t = sigma_t * sigma_t;
  }
  claimed.distance = t_co.norm();
  std::optional<internal::StepVariance> step;
  if (kf.motion_from == k - 1) {
    step = internal::StepVariance{kf.motion_variance_t,
                                  kf.motion_variance_r,
                                  kf.stated_motion_sigma_t,
                                  kf.stated_motion_sigma_r};
  }
  map_.SampleClaim(k, claimed, step);
}

int Backend::Impl::AddSingleOrMultiHypothesis(
    int k,
    const DetectionInput& detection,
    const std::optional<HypothesisScatter>& scatter,
    const Matrix6d& sqrt_info,
    const Revisit& revisit) {
  const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
  internal::SixDofObservation six_dof =
      internal::MakeSixDofObservation(hyps, options_.method, sqrt_info);
  const KeyframeState& kf = *trajectory_.keyframes()[k];
  const Rigid3d T_wc = kf.T_wc();
  std::vector<Rigid3d> T_wo_candidates;
  for (int j : six_dof.used) {
    T_wo_candidates.push_back(T_wc * Normalized(hyps[j].T_co));
  }
  // The map first, then the tentative objects.
  internal::AssociationScope scope =
      internal::DetectionScope(detection,
                               kf,
                               six_dof.observation.T_co_best.t,
                               GateSigmaT(detection.class_name, scatter),
                               options_,
                               ClaimFactorT(detection.class_name));
  ApplyRevisit(revisit, &scope);
  int o = internal::FindSixDofMatch(
      map_.objects(), detection.class_name, T_wo_candidates, scope, options_);
  if (o < 0) {
    scope.status = internal::ObjectStatus::kTentative;
    o = internal::FindSixDofMatch(
        map_.objects(), detection.class_name, T_wo_candidates, scope, options_);
  }
  NoteRevisit(revisit, o);
  if (o < 0) {
    o = map_.Create(detection.class_name,
                    SymmetryType::kAsymmetric,
                    T_wc * six_dof.observation.T_co_best,
                    k);
  }
  six_dof.observation.keyframe = k;
  internal::SetObservationNoise(
      detection, scatter, options_, &six_dof.observation);
  if (options_.estimate_noise) {
    map_.SampleNoise(o,
                     k,
                     kf.T_wc_chain,
                     six_dof.observation.T_co_best.t,
                     six_dof.observation.T_co_best.q);
  }
  edges_.Add(o, std::move(six_dof.observation));
  return o;
}

int Backend::Impl::AddSymba(int k,
                            const DetectionInput& detection,
                            const CategorizedDetection& cat,
                            const std::optional<HypothesisScatter>& scatter,
                            const Matrix6d& sqrt_info,
                            const Revisit& revisit) {
  const KeyframeState& kf = *trajectory_.keyframes()[k];
  const Rigid3d T_wc = kf.T_wc();
  // The map first, then the tentative objects.
  internal::AssociationScope scope =
      internal::DetectionScope(detection,
                               kf,
                               cat.t_co,
                               GateSigmaT(detection.class_name, scatter),
                               options_,
                               ClaimFactorT(detection.class_name));
  ApplyRevisit(revisit, &scope);
  auto find = [&]() {
    return internal::FindSymbaMatch(map_.objects(),
                                    T_wc,
                                    cat,
                                    detection.class_name,
                                    detection.hypotheses,
                                    map_.PriorOf(detection.class_name),
                                    scope,
                                    options_);
  };
  internal::SymbaMatch match = find();
  if (match.object < 0) {
    scope.status = internal::ObjectStatus::kTentative;
    match = find();
  }
  int o = match.object;
  NoteRevisit(revisit, o);
  if (o < 0) {
    o = map_.CreateSymba(detection.class_name, cat, T_wc, k);
  } else if (match.upgrade) {
    internal::UpgradeRecord record;
    record.keyframe = k;
    record.evidence = 1;
    map_.Upgrade(o,
                 cat.type == SymmetryType::kContinuous
                     ? SymmetryType::kContinuous
                     : SymmetryType::kDiscrete,
                 match.a_o,
                 record);
    edges_.Rebuild(o);
  } else if (match.flip) {
    const internal::ObjectMap::FlipOutcome outcome =
        map_.RecordFlip(o, k, match);
    if (outcome != internal::ObjectMap::FlipOutcome::kOutlier) {
      edges_.Rebuild(o);
    } else {
      // A rotation outlier: it joins the object without an edge.
      if (options_.estimate_noise) {
        map_.SampleNoise(o, k, kf.T_wc_chain, cat.t_co, std::nullopt);
      }
      return o;
    }
  }
  if (options_.estimate_noise) {
    map_.SampleNoise(o,
                     k,
                     kf.T_wc_chain,
                     cat.t_co,
                     cat.type == SymmetryType::kAsymmetric
                         ? std::optional<Eigen::Quaterniond>(cat.T_co_base.q)
                         : std::nullopt);
  }
  // Edges: one per discrete angle the detection shows, else one.
  const bool per_angle = map_.objects()[o]->type == SymmetryType::kDiscrete &&
                         cat.type != SymmetryType::kContinuous;
  std::vector<ObjectObservation> observations = internal::MakeSymbaObservations(
      cat, detection.hypotheses, sqrt_info, options_.merge_modes, per_angle);
  const bool one_mode = observations.size() == 1;
  const std::vector<double> shares = internal::ModeShares(observations);
  for (size_t i = 0; i < observations.size(); ++i) {
    ObjectObservation& observation = observations[i];
    observation.keyframe = k;
    internal::SetObservationNoise(detection, scatter, options_, &observation);
    if (per_angle) {
      observation.angle = map_.MatchOrAddAngle(o, T_wc, one_mode, &observation);
      map_.AddAngleEvidence(o, observation.angle, shares[i]);
    }
    edges_.Add(o, std::move(observation));
  }
  return o;
}

}  // namespace symba
