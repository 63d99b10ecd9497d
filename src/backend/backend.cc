// Backend: keyframes, detections per method, the solves and the read-back.
// The object lifecycle is in map_objects.cc; see backend_impl.h for the map
// of the backend's units.
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
#include "symba/common/check.h"

namespace symba {

using internal::DetectionId;
using internal::FactorRecord;
using internal::KeyframeState;
using internal::Normalized;
using internal::ObjectObservation;
using internal::ObjectState;
using internal::PointState;

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

}  // namespace

Backend::Impl::Impl(const BackendOptions& options,
                    const std::optional<PinholeIntrinsics>& intrinsics,
                    const std::map<std::string, ClassPrior>& class_priors)
    : options_(options),
      intrinsics_(intrinsics),
      class_priors_(class_priors),
      object_loss_(MakeLoss(options.object_loss, options.object_loss_scale)),
      point_loss_(std::make_unique<ceres::HuberLoss>(options.point_loss_scale)),
      noise_(options.noise_window, options.noise_min_samples) {}

int Backend::Impl::WindowStart() const {
  return std::max(0,
                  static_cast<int>(keyframes_.size()) - options_.window_size);
}

// ---------------------------------------------------------------------------
// Keyframes.

Status Backend::Impl::AddKeyframe(const KeyframeInput& input) {
  std::optional<internal::PreviousKeyframe> previous;
  if (!keyframes_.empty()) {
    previous = internal::PreviousKeyframe{keyframes_.back()->id,
                                          keyframes_.back()->timestamp};
  }
  Status status =
      internal::ValidateKeyframe(input, previous, intrinsics_.has_value());
  if (!status.ok()) return status;
  status = CategorizeDetections(input);
  if (!status.ok()) return status;

  // Nothing below can fail: the keyframe is added whole.
  auto kf = std::make_unique<KeyframeState>();
  kf->id = input.id;
  kf->timestamp = input.timestamp;
  internal::WritePose(InitialPose(input), kf->q, kf->t);
  kf->T_wc_chain = ChainPose(input);
  if (input.T_wc) kf->T_wc_frontend = Normalized(*input.T_wc);
  const int k = static_cast<int>(keyframes_.size());
  keyframes_.push_back(std::move(kf));
  problem_.SetManifold(keyframes_[k]->q, &quaternion_manifold_);
  ++statistics_.keyframes;

  AddCameraFactors(k, input);
  if (input.T_wc) last_frontend_keyframe_ = k;
  AddPointObservations(k, input);
  for (size_t d = 0; d < input.detections.size(); ++d) {
    AddDetection(k,
                 input.detections[d],
                 options_.method == Method::kSymba ? &categorized_[d] : nullptr,
                 DetectionId(input, d));
  }
  UpdateTentativeObjects(k);
  if (options_.min_support > 0.0) PruneUnsupportedObjects(k);
  if (options_.estimate_noise) {
    std::vector<std::string> classes;
    for (const DetectionInput& det : input.detections) {
      classes.push_back(det.class_name);
    }
    std::sort(classes.begin(), classes.end());
    classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
    UpdateDetectionNoise(classes);
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Factors and the solves.

int Backend::Impl::AddFactor(FactorRecord record) {
  SYMBA_CHECK(record.cost != nullptr) << "a factor without a cost function";
  const int f = problem_.size();
  keyframes_[record.keyframe]->factors.push_back(f);
  if (record.keyframe2 >= 0) keyframes_[record.keyframe2]->factors.push_back(f);
  if (record.object >= 0) objects_[record.object]->factors.push_back(f);
  if (record.point >= 0) points_[record.point]->factors.push_back(f);
  problem_.Add(std::move(record));
  return f;
}

bool Backend::Impl::InMap(const FactorRecord& record) const {
  return !record.retired &&
         (record.object < 0 || objects_[record.object]->status ==
                                   internal::ObjectStatus::kConfirmed);
}

void Backend::Impl::MarkActive(int first_free,
                               std::vector<char>* keyframe_free,
                               std::vector<char>* active) const {
  // The free set: window keyframes (not the gauge) and all they observe.
  const int n = static_cast<int>(keyframes_.size());
  keyframe_free->assign(n, 0);
  std::vector<char> object_free(objects_.size(), 0);
  std::vector<char> point_free(points_.size(), 0);
  for (int k = first_free; k < n; ++k) {
    (*keyframe_free)[k] = k > 0;
    for (int f : keyframes_[k]->factors) {
      const FactorRecord& record = problem_.factor(f);
      if (!InMap(record)) continue;
      if (record.object >= 0) object_free[record.object] = 1;
      if (record.point >= 0) point_free[record.point] = 1;
    }
  }
  // Active: every factor of a free keyframe, object or point.
  active->assign(problem_.size(), 0);
  auto mark = [&](const std::vector<int>& list) {
    for (int f : list) (*active)[f] = InMap(problem_.factor(f));
  };
  for (int k = first_free; k < n; ++k) mark(keyframes_[k]->factors);
  for (size_t o = 0; o < objects_.size(); ++o) {
    if (object_free[o]) mark(objects_[o]->factors);
  }
  for (size_t p = 0; p < points_.size(); ++p) {
    if (point_free[p]) mark(points_[p]->factors);
  }
}

int Backend::Impl::FixKeyframesOutsideWindow(
    const std::vector<char>& keyframe_free) {
  int free_keyframes = 0;
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    KeyframeState& kf = *keyframes_[k];
    if (!problem_.HasBlock(kf.q)) continue;
    problem_.SetConstant(kf.q, !keyframe_free[k]);
    problem_.SetConstant(kf.t, !keyframe_free[k]);
    if (keyframe_free[k]) ++free_keyframes;
  }
  return free_keyframes;
}

Status Backend::Impl::Optimize(int first_free,
                               int max_iterations,
                               SolveReport* report) {
  if (keyframes_.empty()) return Status::Error("no keyframes to optimise");
  const auto start = std::chrono::steady_clock::now();

  std::vector<char> keyframe_free;
  std::vector<char> active;
  MarkActive(first_free, &keyframe_free, &active);
  problem_.Sync(active);
  // Keyframes outside the window (and the gauge) are constant.
  const int free_keyframes = FixKeyframesOutsideWindow(keyframe_free);

  ceres::Solver::Summary summary;
  if (problem_.NumResidualBlocks() > 0) {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = max_iterations;
    solver_options.num_threads = options_.num_threads;
    solver_options.logging_type = ceres::SILENT;
    problem_.Solve(solver_options, &summary);
  }
  ReanchorDriftedObjects();

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ++statistics_.solves;
  statistics_.solve_seconds += seconds;
  statistics_.solve_iterations += static_cast<int>(summary.iterations.size());
  if (report != nullptr) {
    report->iterations = static_cast<int>(summary.iterations.size());
    report->initial_cost = summary.initial_cost;
    report->final_cost = summary.final_cost;
    report->seconds = seconds;
    report->converged = summary.termination_type == ceres::CONVERGENCE;
    report->free_keyframes = free_keyframes;
    report->residual_blocks = problem_.NumResidualBlocks();
  }
  if (problem_.NumResidualBlocks() > 0 && !summary.IsSolutionUsable()) {
    return Status::Error("the solver failed: " + summary.message);
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Read-back.

std::vector<KeyframeEstimate> Backend::Impl::Keyframes() const {
  std::vector<KeyframeEstimate> estimates;
  estimates.reserve(keyframes_.size());
  for (const auto& kf : keyframes_) {
    estimates.push_back({kf->id, kf->timestamp, kf->T_wc()});
  }
  return estimates;
}

std::vector<MapObjectEstimate> Backend::Impl::Objects() const {
  std::vector<MapObjectEstimate> estimates;
  for (const auto& object : objects_) {
    if (object->status != internal::ObjectStatus::kConfirmed) continue;
    MapObjectEstimate e;
    e.id = object->id;
    e.class_name = object->class_name;
    e.symmetry = object->type;
    e.t_wo = object->position();
    e.observations = object->detections;
    if (object->upgrade) {
      const internal::UpgradeRecord& u = *object->upgrade;
      e.upgrade = MapObjectEstimate::Upgrade{
          keyframes_[u.keyframe]->id, u.evidence, u.order, u.angle};
    }
    if (object->type == SymmetryType::kAsymmetric) {
      e.poses.push_back(Rigid3d(object->Rotation(-1), e.t_wo));
    } else {
      e.axis_w = object->axis_w().normalized();
      e.axis_o = object->a_o;
      if (object->type == SymmetryType::kDiscrete) {
        for (size_t i = 0; i < object->thetas.size(); ++i) {
          e.angles.push_back(*object->thetas[i]);
          e.poses.push_back(
              Rigid3d(object->Rotation(static_cast<int>(i)), e.t_wo));
        }
      } else {
        e.poses.push_back(Rigid3d(
            SymmetricObjectRotation(object->anchor, object->axis_w(), 0.0),
            e.t_wo));
      }
    }
    estimates.push_back(std::move(e));
  }
  return estimates;
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
    if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0.0 &&
          k.fy > 0.0 && std::isfinite(k.cx) && std::isfinite(k.cy))) {
      return Status::Error(
          "camera intrinsics: fx, fy must be positive, all finite");
    }
  }
  // Categorize's own checks on every prior (a one-hypothesis detection
  // always passes the rest): a bad prior must fail here, not in AddKeyframe
  // after the keyframe was added.
  for (const auto& [class_name, prior] : class_priors) {
    CategorizedDetection scratch;
    status = Categorize(
        {PoseHypothesis{}}, options.categorization, &prior, &scratch);
    if (!status.ok()) {
      return Status::Error("class prior \"" + class_name +
                           "\": " + status.message());
    }
  }
  backend->reset(
      new Backend(std::make_unique<Impl>(options, intrinsics, class_priors)));
  return Status::Ok();
}

Backend::Backend(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Backend::~Backend() = default;

Status Backend::AddKeyframe(const KeyframeInput& keyframe) {
  return impl_->AddKeyframe(keyframe);
}

Status Backend::OptimizeWindow(SolveReport* report) {
  return impl_->Optimize(
      impl_->WindowStart(), impl_->options_.max_iterations, report);
}

Status Backend::OptimizeBatch(SolveReport* report) {
  return impl_->Optimize(0, impl_->options_.batch_max_iterations, report);
}

std::vector<KeyframeEstimate> Backend::Keyframes() const {
  return impl_->Keyframes();
}

std::vector<MapObjectEstimate> Backend::Objects() const {
  return impl_->Objects();
}

const std::vector<DetectionAssignment>& Backend::Assignments() const {
  return impl_->assignments_;
}

BackendStatistics Backend::Statistics() const { return impl_->statistics_; }

const BackendOptions& Backend::options() const { return impl_->options_; }

}  // namespace symba
