// Backend: the recipe of a keyframe, the solves and the read-back (see
// backend_impl.h for the map of the backend's parts).
#include "symba/backend/backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include <ceres/ceres.h>

#include "backend/backend_impl.h"
#include "backend/detection_observations.h"
#include "backend/keyframe_validation.h"
#include "backend/object_covariances.h"
#include "backend/relocalizer.h"
#include "common/median.h"
#include "symba/common/check.h"

namespace symba {

using internal::DetectionId;
using internal::KeyframeState;
using internal::ObjectState;

Backend::Impl::Impl(const BackendOptions& options,
                    const std::optional<PinholeIntrinsics>& intrinsics,
                    const std::map<std::string, ClassPrior>& class_priors)
    : options_(options),
      intrinsics_(intrinsics),
      class_priors_(class_priors),
      trajectory_(options_, intrinsics, &graph_, &statistics_),
      map_(options_, class_priors, &graph_, &statistics_, &assignments_),
      graph_(options_,
             trajectory_.keyframes(),
             map_.objects(),
             trajectory_.points(),
             &statistics_),
      edges_(
          options_, trajectory_.keyframes(), &map_.mutable_objects(), &graph_) {
}

std::vector<ClassNoiseEstimate> Backend::Impl::Noise() const {
  std::vector<ClassNoiseEstimate> classes;
  const internal::DetectionNoiseEstimator& noise = map_.noise();
  for (const std::string& name : noise.Classes()) {
    const internal::ClassNoise estimate = noise.Estimate(name);
    ClassNoiseEstimate c;
    c.class_name = name;
    c.sigma_t = estimate.sigma_t;
    c.sigma_r = estimate.sigma_r;
    // As BuildObjectEdge weighs a detection without a sigma: the applied
    // estimate against the floor, within the range an edge holds it to.
    // (Without estimate_noise: the default, SetObservationNoise.)
    const internal::ClassNoise used = edges_.AppliedNoise(name);
    c.weight_sigma_t =
        options_.estimate_noise
            ? UsableNoiseSigma(internal::EffectiveSigma(
                  options_.uncalibrated_sigma_t, false, used.sigma_t))
            : options_.hypothesis_sigma_t;
    c.weight_sigma_r =
        options_.estimate_noise
            ? UsableNoiseSigma(internal::EffectiveSigma(
                  options_.uncalibrated_sigma_r, false, used.sigma_r))
            : options_.hypothesis_sigma_r;
    c.translation = noise.TranslationReport(name);
    c.rotation = noise.RotationReport(name);
    c.scatter = noise.ScatterReport(name);
    c.claims = noise.ClaimsReport(name);
    c.claims.factor_t = used.claim_scale_t.value_or(1.0);
    c.claims.factor_r = used.claim_scale_r.value_or(1.0);
    if (const auto sigma_increment = noise.TranslationIncrementSigma(name)) {
      c.track_ratio = noise.TrackRatio(name, *sigma_increment);
    }
    c.weights = EdgeWeights(name);
    classes.push_back(std::move(c));
  }
  return classes;
}

ClassNoiseEstimate::Weights Backend::Impl::EdgeWeights(
    const std::string& class_name) const {
  ClassNoiseEstimate::Weights weights;
  std::vector<double> sigmas_t;
  std::vector<double> sigmas_r;
  for (int o : map_.ObjectsOfClass(class_name)) {
    const internal::ObjectState& object = *map_.objects()[o];
    if (!internal::IsMapped(object)) continue;
    for (const internal::ObjectObservation& observation : object.observations) {
      if (observation.edge_sigma_t <= 0.0) continue;  // no edge built
      if (observation.claimed_t || observation.claimed_r) {
        ++weights.declared;
      } else if (observation.from_scatter) {
        ++weights.scatter;
      } else {
        ++weights.unstated;
      }
      sigmas_t.push_back(observation.edge_sigma_t);
      if (observation.edge_sigma_r > 0.0) {
        sigmas_r.push_back(observation.edge_sigma_r);
      }
    }
  }
  if (!sigmas_t.empty()) weights.sigma_t = internal::MedianInPlace(&sigmas_t);
  if (!sigmas_r.empty()) weights.sigma_r = internal::MedianInPlace(&sigmas_r);
  return weights;
}

Status Backend::Impl::ObjectCovariances(
    std::vector<MapObjectCovariance>* covariances) {
  std::vector<MapObjectCovariance> reports;
  Status status =
      internal::ObjectCovariances(map_.objects(), &graph_, &reports);
  if (!status.ok()) return status;
  // A solve that held the past as known left the cameras' uncertainty
  // since the first keyframe out; the keyframe graph has it. A run from a
  // loaded map keeps the solve's (its objects' priors are not in the
  // graph), and so does a graph whose covariance cannot be computed: the
  // reports' source then says what they are.
  if (graph_.LastSolveHeldThePast() && !map_loaded_) {
    std::vector<internal::GraphObject> objects;
    PoseGraphCovarianceOptions options;
    const PoseGraph graph = CurrentKeyframeGraph(&objects, &options);
    const Status world =
        internal::InWorldFrame(graph,
                               static_cast<int>(trajectory_.keyframes().size()),
                               objects,
                               map_.objects(),
                               options,
                               &reports);
    static_cast<void>(world);
  }
  *covariances = std::move(reports);
  return Status::Ok();
}

PoseGraph Backend::Impl::CurrentKeyframeGraph(
    std::vector<internal::GraphObject>* objects,
    PoseGraphCovarianceOptions* options) const {
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const int window_begin =
      static_cast<int>(keyframes.size()) - options_.window_size;
  *objects = GraphObjects();
  std::vector<internal::GraphEdgeRole> roles;
  PoseGraph graph = internal::MakeKeyframeGraph(
      keyframes, window_begin, loops_, *objects, &roles);
  *options = internal::KeyframeGraphCovarianceOptions(
      static_cast<int>(keyframes.size()), *objects);
  if (options_.calibrate_covariances) {
    internal::CalibrateGraphNoise(
        graph, roles, &options->noise_factors, &covariance_noise_);
  } else {
    covariance_noise_.clear();
  }
  return graph;
}

Status Backend::Impl::KeyframeCovariances(
    const std::vector<KeyframeId>& ids,
    std::vector<KeyframeCovariance>* covariances) const {
  // Keyframe 0 holds the gauge: known, and no vertex to ask about.
  std::vector<int64_t> vertices;
  for (const KeyframeId id : ids) {
    const int k = trajectory_.IndexOf(id);
    if (k < 0) {
      return Status::Error("keyframe covariances: keyframe " +
                           std::to_string(id) + " is unknown");
    }
    if (k > 0) vertices.push_back(k);
  }
  std::vector<Matrix6d> marginals;
  if (!vertices.empty()) {
    std::vector<internal::GraphObject> objects;
    PoseGraphCovarianceOptions options;
    const PoseGraph graph = CurrentKeyframeGraph(&objects, &options);
    const Status status =
        PoseGraphCovariances(graph, vertices, options, &marginals);
    if (!status.ok()) {
      return Status::Error("keyframe covariances: " + status.message());
    }
  }
  std::vector<KeyframeCovariance> out;
  size_t next = 0;
  for (const KeyframeId id : ids) {
    KeyframeCovariance c;
    c.id = id;
    if (trajectory_.IndexOf(id) > 0) c.covariance = marginals[next++];
    out.push_back(c);
  }
  *covariances = std::move(out);
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Keyframes.

Status Backend::Impl::AddKeyframe(
    const KeyframeInput& input, std::vector<DetectionAssignment>* assignments) {
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  std::optional<internal::PreviousKeyframe> previous;
  if (!keyframes.empty()) {
    previous = internal::PreviousKeyframe{keyframes.back()->id,
                                          keyframes.back()->timestamp};
  }
  Status status =
      internal::ValidateKeyframe(input, previous, trajectory_.has_intrinsics());
  if (!status.ok()) return status;
  for (size_t i = 0; i < input.loop_closures.size(); ++i) {
    const std::string where = "keyframe " + std::to_string(input.id) +
                              ": loop_closures[" + std::to_string(i) + "]";
    if (input.loop_closures[i].keyframe == input.id) {
      return Status::Error(where + ": relates a keyframe to itself");
    }
    status = CheckLoopClosure(-1, input.loop_closures[i], where);
    if (!status.ok()) return status;
  }
  status = CategorizeDetections(input);
  if (!status.ok()) return status;

  // Nothing below can fail: the keyframe is added whole.
  const size_t first_assignment = assignments_.size();
  const int k = trajectory_.Add(
      input, options_.estimate_noise ? map_.mutable_motion_claims() : nullptr);
  const std::vector<Revisit> revisits = Revisits(k, input);
  for (size_t d = 0; d < input.detections.size(); ++d) {
    AddDetection(k,
                 input.detections[d],
                 options_.method == Method::kSymba ? &categorized_[d] : nullptr,
                 scatters_[d],
                 DetectionId(input, d),
                 revisits[d]);
  }
  map_.UpdateTentative(k);
  if (options_.min_support > 0.0) {
    map_.PruneUnsupported(k, keyframes[k]->T_wc());
  }
  if (options_.estimate_noise) UpdateDetectionNoise(input);
  // Closed after the keyframe's window solve (or at the batch solve): its
  // pose is a prediction until then.
  for (const LoopClosureInput& closure : input.loop_closures) {
    pending_loops_.emplace_back(k, closure);
  }
  if (assignments != nullptr) {
    assignments->assign(assignments_.begin() + first_assignment,
                        assignments_.end());
  }
  return Status::Ok();
}

void Backend::Impl::UpdateDetectionNoise(const KeyframeInput& input) {
  std::vector<std::string> classes;
  for (const DetectionInput& det : input.detections) {
    classes.push_back(det.class_name);
  }
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  for (const std::string& class_name : classes) {
    if (!edges_.ApplyNoise(class_name, map_.noise().Estimate(class_name))) {
      continue;
    }
    for (int o : map_.ObjectsOfClass(class_name)) {
      if (map_.objects()[o]->status != internal::ObjectStatus::kDropped) {
        edges_.Rebuild(o);
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Factors and the solves.

Status Backend::Impl::OptimizeWindow(SolveReport* report) {
  if (trajectory_.keyframes().empty()) {
    return Status::Error("no keyframes to optimise");
  }
  const auto start = std::chrono::steady_clock::now();
  internal::SolveOutcome outcome;
  const int first = std::max(
      0,
      static_cast<int>(trajectory_.keyframes().size()) - options_.window_size);
  graph_.SolveWindow(first, &outcome);
  // A failed solve leaves the closures waiting for the next one.
  if (outcome.usable) {
    solved_keyframes_ = static_cast<int>(trajectory_.keyframes().size());
  }
  bool closed = false;
  if (outcome.usable) {
    closed = !pending_loops_.empty();
    ClosePendingLoops();
    closed = DetectObjectLoop() || closed;
    if (revisit_pending_ && !closed) closed = MovePastForRevisit();
    revisit_pending_ = false;
    closed = MergeDuplicatesTheMoveJoined() || closed;
  }
  if (closed) {
    // The window again, from the moved past, with the loop constraints and
    // the merged objects.
    internal::SolveOutcome again;
    graph_.SolveWindow(first, &again);
    again.iterations += outcome.iterations;
    again.initial_cost = outcome.initial_cost;
    outcome = again;
  }
  return Finish("window", outcome, start, report);
}

Status Backend::Impl::OptimizeBatch(SolveReport* report) {
  if (trajectory_.keyframes().empty()) {
    return Status::Error("no keyframes to optimise");
  }
  const auto start = std::chrono::steady_clock::now();
  // The batch solve refuses without the history; nothing moves then.
  if (options_.keep_history || graph_.marginalized_until() == 0) {
    solved_keyframes_ = static_cast<int>(trajectory_.keyframes().size());
    ClosePendingLoops();
    MergeDuplicatesTheMoveJoined();
  }
  edges_.RebuildStale();
  internal::SolveOutcome outcome;
  const Status status = graph_.SolveBatch(&outcome);
  if (!status.ok()) return status;
  revisit_pending_ = false;  // every factor solved at once: nothing bends
  return Finish("batch", outcome, start, report);
}

Status Backend::Impl::Finish(const char* what,
                             const internal::SolveOutcome& outcome,
                             const std::chrono::steady_clock::time_point& start,
                             SolveReport* report) {
  ReanchorDriftedObjects();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ++statistics_.solves;
  statistics_.solve_seconds += seconds;
  statistics_.solve_iterations += outcome.iterations;
  if (report != nullptr) {
    report->iterations = outcome.iterations;
    report->initial_cost = outcome.initial_cost;
    report->final_cost = outcome.final_cost;
    report->seconds = seconds;
    report->converged = outcome.converged;
    report->free_keyframes = outcome.free_keyframes;
    report->residual_blocks = outcome.residual_blocks;
    report->parameter_blocks = outcome.parameter_blocks;
    report->prior_size = outcome.prior_size;
  }
  if (outcome.solved && !outcome.usable) {
    return Status::Error(std::string("the ") + what +
                         " solve failed: " + outcome.message);
  }
  return Status::Ok();
}

void Backend::Impl::ReanchorDriftedObjects() {
  const int count = static_cast<int>(map_.objects().size());
  for (int o = 0; o < count; ++o) {
    if (map_.ReanchorIfDrifted(o)) edges_.Rebuild(o);
  }
}

// ---------------------------------------------------------------------------
// Read-back.

std::vector<KeyframeEstimate> Backend::Impl::Keyframes() const {
  std::vector<KeyframeEstimate> estimates;
  estimates.reserve(trajectory_.keyframes().size());
  for (const auto& kf : trajectory_.keyframes()) {
    estimates.push_back({kf->id, kf->timestamp, kf->T_wc()});
  }
  return estimates;
}

std::vector<MapObjectEstimate> Backend::Impl::Objects() const {
  std::vector<MapObjectEstimate> estimates;
  for (const auto& object : map_.objects()) {
    if (object->status != internal::ObjectStatus::kConfirmed) continue;
    estimates.push_back(EstimateOf(*object));
  }
  return estimates;
}

std::optional<KeyframeEstimate> Backend::Impl::Keyframe(KeyframeId id) const {
  const KeyframeState* kf = trajectory_.Find(id);
  if (kf == nullptr) return std::nullopt;
  return KeyframeEstimate{kf->id, kf->timestamp, kf->T_wc()};
}

std::optional<MapObjectEstimate> Backend::Impl::Object(ObjectId id) const {
  // Object ids are indices.
  const internal::ObjectList& objects = map_.objects();
  if (id < 0 || id >= static_cast<ObjectId>(objects.size()) ||
      objects[id]->status != internal::ObjectStatus::kConfirmed) {
    return std::nullopt;
  }
  return EstimateOf(*objects[id]);
}

MapObjectEstimate Backend::Impl::EstimateOf(const ObjectState& object) const {
  MapObjectEstimate e;
  e.id = object.id;
  e.class_name = object.class_name;
  e.symmetry = object.type;
  e.t_wo = object.position();
  e.observations = object.detections;
  if (object.upgrade) {
    const internal::UpgradeRecord& u = *object.upgrade;
    e.upgrade = MapObjectEstimate::Upgrade{
        trajectory_.keyframes()[u.keyframe]->id, u.evidence, u.order, u.angle};
  } else {
    e.upgrade = object.loaded_upgrade;
  }
  if (object.type == SymmetryType::kAsymmetric) {
    e.poses.push_back(Rigid3d(object.Rotation(-1), e.t_wo));
    return e;
  }
  e.axis_w = object.axis_w().normalized();
  e.axis_o = object.a_o;
  if (object.type == SymmetryType::kDiscrete) {
    for (size_t i = 0; i < object.thetas.size(); ++i) {
      e.angles.push_back(*object.thetas[i]);
      e.angle_evidence.push_back(object.angle_evidence[i]);
      e.poses.push_back(Rigid3d(object.Rotation(static_cast<int>(i)), e.t_wo));
    }
    e.angle_probabilities = AngleProbabilities(e.angle_evidence);
  } else {
    e.poses.push_back(Rigid3d(
        SymmetricObjectRotation(object.anchor, object.axis_w(), 0.0), e.t_wo));
  }
  return e;
}

// ---------------------------------------------------------------------------
// Backend.

Status Backend::Create(const BackendOptions& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       const std::map<std::string, ClassPrior>& class_priors,
                       std::unique_ptr<Backend>* backend) {
  Status status = options.Validate();
  if (!status.ok()) return status;
  if (intrinsics) {
    const PinholeIntrinsics& k = *intrinsics;
    if (!(k.fx > 0.0 && k.fx <= kMaxCoordinate && k.fy > 0.0 &&
          k.fy <= kMaxCoordinate && std::abs(k.cx) <= kMaxCoordinate &&
          std::abs(k.cy) <= kMaxCoordinate)) {
      return Status::Error(
          "camera intrinsics: fx, fy must be in (0, 1e9] and cx, cy within "
          "+-1e9");
    }
  }
  // A bad prior must fail here, not in AddKeyframe after the keyframe was
  // added; the categorization then trusts the priors (and the options).
  for (const auto& [class_name, prior] : class_priors) {
    status = prior.Validate();
    if (!status.ok()) {
      return Status::Error("class \"" + class_name + "\": " + status.message());
    }
  }
  backend->reset(
      new Backend(std::make_unique<Impl>(options, intrinsics, class_priors)));
  return Status::Ok();
}

Backend::Backend(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Backend::~Backend() = default;

bool Backend::Searching() const {
  return relocalizer_ != nullptr && relocalizer_->searching();
}

const Backend::Impl& Backend::Run() const {
  return Searching() ? *relocalizer_->search().impl_ : *impl_;
}

Backend::Impl& Backend::Run() {
  return Searching() ? *relocalizer_->search().impl_ : *impl_;
}

Status Backend::AddKeyframe(const KeyframeInput& keyframe,
                            std::vector<DetectionAssignment>* assignments) {
  if (Searching()) return relocalizer_->Add(keyframe, assignments);
  if (relocalizer_ != nullptr && keyframe.T_wc &&
      relocalizer_->report().state ==
          RelocalizationReport::State::kRelocalized) {
    // The run gives its poses in its own frame; after the match this
    // backend's keyframes are in the map's, as the kept ones were moved.
    KeyframeInput in_map_frame = keyframe;
    in_map_frame.T_wc = relocalizer_->report().T_map_run * *keyframe.T_wc;
    return impl_->AddKeyframe(in_map_frame, assignments);
  }
  return impl_->AddKeyframe(keyframe, assignments);
}

Status Backend::OptimizeWindow(SolveReport* report) {
  if (!Searching()) return impl_->OptimizeWindow(report);
  Status status = relocalizer_->search().OptimizeWindow(report);
  if (!status.ok()) return status;
  const auto start = std::chrono::steady_clock::now();
  const bool matched = relocalizer_->TryMatch();
  relocalizer_->AddSeconds(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count());
  if (matched) return FinishRelocalization(report);
  if (relocalizer_->Exhausted()) GiveUpRelocalization();
  return Status::Ok();
}

void Backend::GiveUpRelocalization() {
  if (!Searching()) return;
  // The run goes on in its own frame: the search's state becomes this
  // backend's. The loaded map's state stays alive in the relocalizer, so
  // that references a caller holds (Assignments(), options()) stay valid.
  std::unique_ptr<Backend> search = relocalizer_->GiveUp();
  std::swap(impl_, search->impl_);
  relocalizer_->Retire(std::move(search));
}

// The search's keyframes, in the map's frame, are estimated again by this
// backend (each added and solved as it was first), associating their
// detections with the loaded objects.
Status Backend::FinishRelocalization(SolveReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<KeyframeInput> keyframes =
      relocalizer_->TakeKeyframesInMapFrame();
  // Every keyframe is added even if one fails (the search took each of
  // them, so none should), so that the run's next keyframe follows the
  // last; the first error is returned.
  Status first_error = Status::Ok();
  for (const KeyframeInput& keyframe : keyframes) {
    Status status = impl_->AddKeyframe(keyframe, nullptr);
    if (status.ok()) status = impl_->OptimizeWindow(report);
    if (!status.ok() && first_error.ok()) {
      first_error =
          Status::Error("relocalisation, keyframe " +
                        std::to_string(keyframe.id) + ": " + status.message());
    }
  }
  relocalizer_->AddSeconds(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count());
  return first_error;
}

Status Backend::OptimizeBatch(SolveReport* report) {
  return Run().OptimizeBatch(report);
}

std::optional<KeyframeEstimate> Backend::Keyframe(KeyframeId id) const {
  return Run().Keyframe(id);
}

std::optional<MapObjectEstimate> Backend::Object(ObjectId id) const {
  return impl_->Object(id);
}

std::vector<KeyframeEstimate> Backend::Keyframes() const {
  return Run().Keyframes();
}

std::vector<MapObjectEstimate> Backend::Objects() const {
  return impl_->Objects();
}

const std::vector<DetectionAssignment>& Backend::Assignments() const {
  return impl_->assignments_;
}

std::vector<LoopClosureReport> Backend::LoopClosures() const {
  return Run().LoopClosures();
}

Status Backend::AddLoopClosure(KeyframeId keyframe,
                               const LoopClosureInput& closure,
                               LoopClosureReport* report) {
  if (Searching()) {
    return Status::Error(
        "a loop closure cannot be added while relocalising (give it with "
        "its keyframe, KeyframeInput::loop_closures)");
  }
  return impl_->AddLoopClosure(keyframe, closure, report);
}

BackendStatistics Backend::Statistics() const { return Run().statistics_; }

std::vector<ClassNoiseEstimate> Backend::Noise() const { return Run().Noise(); }

MotionNoiseReport Backend::MotionNoise() const { return Run().MotionNoise(); }

Status Backend::KeyframeCovariances(
    const std::vector<KeyframeId>& ids,
    std::vector<KeyframeCovariance>* covariances) const {
  return impl_->KeyframeCovariances(ids, covariances);
}

std::vector<CovarianceNoiseGroup> Backend::CovarianceNoise() const {
  return impl_->CovarianceNoise();
}

Status Backend::ObjectCovariances(
    std::vector<MapObjectCovariance>* covariances) {
  return impl_->ObjectCovariances(covariances);
}

Status Backend::SaveMap(SavedMap* map) { return impl_->SaveMap(map); }

Status Backend::LoadMap(
    const SavedMap& map,
    const std::optional<RelocalizationOptions>& relocalize) {
  if (relocalize) {
    if (relocalize->max_keyframes < 1 || relocalize->match.min_support < 1) {
      return Status::Error(
          "relocalisation: max_keyframes and match.min_support must be at "
          "least 1");
    }
  }
  Status status = impl_->LoadMap(map);
  if (!status.ok() || !relocalize) return status;
  std::unique_ptr<Backend> search;
  status = Create(
      impl_->options_, impl_->intrinsics_, impl_->class_priors_, &search);
  if (!status.ok()) return status;  // cannot fail: these created impl_
  // The search weighs the detections as the run from the map will.
  search->impl_->RestoreNoise(map.noise);
  RelocalizationOptions options = *relocalize;
  // A discrete class's order from its prior, unless the caller gave one.
  for (const auto& [name, prior] : impl_->class_priors_) {
    if (prior.symmetry == SymmetryType::kDiscrete && prior.order >= 2) {
      options.match.symmetry_orders.emplace(name, prior.order);
    }
  }
  relocalizer_ = std::make_unique<internal::Relocalizer>(
      std::move(search), map.objects, options);
  return Status::Ok();
}

std::optional<RelocalizationReport> Backend::Relocalization() const {
  if (relocalizer_ == nullptr) return std::nullopt;
  return relocalizer_->report();
}

const BackendOptions& Backend::options() const { return impl_->options_; }

}  // namespace symba
