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

const ClassPrior* Backend::Impl::PriorOf(const std::string& class_name) const {
  const auto it = class_priors_.find(class_name);
  return it == class_priors_.end() ? nullptr : &it->second;
}

Status Backend::Impl::CategorizeDetections(const KeyframeInput& input) {
  if (options_.method != Method::kSymba) return Status::Ok();
  if (categorized_.size() < input.detections.size()) {
    categorized_.resize(input.detections.size());
  }
  for (size_t d = 0; d < input.detections.size(); ++d) {
    const DetectionInput& det = input.detections[d];
    // Create validated the options and the priors.
    Status status =
        categorization::CategorizeWithValidOptions(det.hypotheses,
                                                   options_.categorization,
                                                   PriorOf(det.class_name),
                                                   &categorized_[d]);
    if (!status.ok()) {
      return Status::Error("keyframe " + std::to_string(input.id) +
                           ": detection " + DetectionId(input, d) + ": " +
                           status.message());
    }
  }
  return Status::Ok();
}

void Backend::Impl::AddDetection(int k,
                                 const DetectionInput& detection,
                                 const CategorizedDetection* categorized,
                                 const std::string& detection_id) {
  const Matrix6d sqrt_info = IsotropicPoseSqrtInfo(
      detection.sigma_t.value_or(options_.hypothesis_sigma_t),
      detection.sigma_r.value_or(options_.hypothesis_sigma_r));
  const int object = categorized != nullptr
                         ? AddSymba(k, detection, *categorized, sqrt_info)
                         : AddSingleOrMultiHypothesis(k, detection, sqrt_info);
  const SymmetryType type =
      categorized != nullptr ? categorized->type : SymmetryType::kAsymmetric;
  NoteViewCone(categorized != nullptr ? categorized->t_co
                                      : detection.hypotheses.front().T_co.t);
  ++objects_[object]->detections;
  ++statistics_.detections;
  assignments_.push_back(
      {keyframes_[k]->id, detection_id, objects_[object]->id, type});
  NoteDetection(object, k, static_cast<int>(assignments_.size()) - 1);
}

void Backend::Impl::SetObservationNoise(const DetectionInput& detection,
                                        ObjectObservation* observation) const {
  // A detection that gives a sigma is calibrated: what it gives is taken
  // as it is, the options' default fills in the other. Without either: the
  // default, or with estimation the floor for an uncalibrated detector.
  const bool calibrated = detection.sigma_t || detection.sigma_r;
  const bool uncalibrated_floor = !calibrated && options_.estimate_noise;
  observation->sigma_t = detection.sigma_t.value_or(
      uncalibrated_floor ? options_.uncalibrated_sigma_t
                         : options_.hypothesis_sigma_t);
  observation->sigma_r = detection.sigma_r.value_or(
      uncalibrated_floor ? options_.uncalibrated_sigma_r
                         : options_.hypothesis_sigma_r);
  observation->claimed_t = calibrated;
  observation->claimed_r = calibrated;
}

internal::AssociationScope Backend::Impl::Scope(
    const DetectionInput& detection, int k, const Eigen::Vector3d& t_co) const {
  internal::AssociationScope scope;
  scope.sigma_t = GateSigma(detection);
  const KeyframeState& kf = *keyframes_[k];
  scope.prediction_variance =
      kf.motion_variance_t + t_co.squaredNorm() * kf.motion_variance_r;
  return scope;
}

std::optional<double> Backend::Impl::GateSigma(
    const DetectionInput& detection) const {
  const auto it = applied_noise_.find(detection.class_name);
  const std::optional<double> estimate =
      it == applied_noise_.end() ? std::nullopt : it->second.sigma_t;
  // The gate wants the scatter itself, not the floor of the weighting.
  if (detection.sigma_t || detection.sigma_r) {
    return detection.sigma_t.value_or(options_.hypothesis_sigma_t);
  }
  return estimate;
}

int Backend::Impl::AddSingleOrMultiHypothesis(int k,
                                              const DetectionInput& detection,
                                              const Matrix6d& sqrt_info) {
  const std::vector<PoseHypothesis>& hyps = detection.hypotheses;
  internal::SixDofObservation six_dof =
      internal::MakeSixDofObservation(hyps, options_.method, sqrt_info);
  const Rigid3d T_wc = keyframes_[k]->T_wc();
  std::vector<Rigid3d> T_wo_candidates;
  for (int j : six_dof.used) {
    T_wo_candidates.push_back(T_wc * Normalized(hyps[j].T_co));
  }
  // The map first, then the tentative objects.
  internal::AssociationScope scope =
      Scope(detection, k, six_dof.observation.T_co_best.t);
  int o = internal::FindSixDofMatch(
      objects_, detection.class_name, T_wo_candidates, scope, options_);
  if (o < 0) {
    scope.status = internal::ObjectStatus::kTentative;
    o = internal::FindSixDofMatch(
        objects_, detection.class_name, T_wo_candidates, scope, options_);
  }
  if (o < 0) {
    o = CreateObject(detection.class_name, SymmetryType::kAsymmetric, k);
    internal::WritePose(
        T_wc * six_dof.observation.T_co_best, objects_[o]->q, objects_[o]->t);
  }
  six_dof.observation.keyframe = k;
  SetObservationNoise(detection, &six_dof.observation);
  if (options_.estimate_noise) {
    SampleNoise(
        o, k, six_dof.observation.T_co_best.t, six_dof.observation.T_co_best.q);
  }
  AddObservation(o, std::move(six_dof.observation));
  return o;
}

int Backend::Impl::AddSymba(int k,
                            const DetectionInput& detection,
                            const CategorizedDetection& cat,
                            const Matrix6d& sqrt_info) {
  const Rigid3d T_wc = keyframes_[k]->T_wc();
  // The map first, then the tentative objects.
  internal::AssociationScope scope = Scope(detection, k, cat.t_co);
  auto find = [&]() {
    return internal::FindSymbaMatch(objects_,
                                    T_wc,
                                    cat,
                                    detection.class_name,
                                    detection.hypotheses,
                                    PriorOf(detection.class_name),
                                    scope,
                                    options_);
  };
  internal::SymbaMatch match = find();
  if (match.object < 0) {
    scope.status = internal::ObjectStatus::kTentative;
    match = find();
  }
  int o = match.object;
  if (o < 0) {
    o = CreateSymbaObject(detection.class_name, cat, T_wc, k);
  } else if (match.upgrade) {
    internal::UpgradeRecord record;
    record.keyframe = k;
    record.evidence = 1;
    UpgradeObject(o,
                  cat.type == SymmetryType::kContinuous
                      ? SymmetryType::kContinuous
                      : SymmetryType::kDiscrete,
                  match.a_o,
                  record);
  } else if (match.flip && !RecordFlip(o, k, match)) {
    // A rotation outlier: it joins the object without an edge.
    if (options_.estimate_noise) SampleNoise(o, k, cat.t_co, std::nullopt);
    return o;
  }
  if (options_.estimate_noise) {
    SampleNoise(o,
                k,
                cat.t_co,
                cat.type == SymmetryType::kAsymmetric
                    ? std::optional<Eigen::Quaterniond>(cat.T_co_base.q)
                    : std::nullopt);
  }
  // Edges: one per discrete angle the detection shows, else one.
  const bool per_angle = objects_[o]->type == SymmetryType::kDiscrete &&
                         cat.type != SymmetryType::kContinuous;
  std::vector<ObjectObservation> observations = internal::MakeSymbaObservations(
      cat, detection.hypotheses, sqrt_info, options_.merge_modes, per_angle);
  const bool one_mode = observations.size() == 1;
  for (ObjectObservation& observation : observations) {
    observation.keyframe = k;
    SetObservationNoise(detection, &observation);
    if (per_angle) {
      observation.angle = MatchOrAddAngle(o, T_wc, one_mode, &observation);
    }
    AddObservation(o, std::move(observation));
  }
  return o;
}

}  // namespace symba
