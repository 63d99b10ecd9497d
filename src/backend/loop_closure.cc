// Backend::Impl: loop closures the host system gives (docs/loop-closure.md).
// A relative pose between two keyframes in the window is one more factor of
// the window's solves. One whose other keyframe is outside the window first
// moves the past: the keyframe graph (keyframe_graph.h) is optimised with
// every loop closure so far, each keyframe is set to its optimised pose, and
// each object and point moves rigidly with the last keyframe that saw it,
// its prior with it (rigidly_moved_prior.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "backend/backend_impl.h"
#include "backend/keyframe_validation.h"
#include "symba/factors/relative_pose_factor.h"

namespace symba {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

double AngleDeg(const Eigen::Quaterniond& q) {
  return kRadToDeg * 2.0 *
         std::atan2(q.vec().norm(), std::abs(q.normalized().w()));
}

}  // namespace

Status Backend::Impl::CheckLoopClosure(int k,
                                       const LoopClosureInput& closure,
                                       const std::string& prefix) const {
  const int other = trajectory_.IndexOf(closure.keyframe);
  if (other < 0) {
    return Status::Error(prefix + ": unknown keyframe " +
                         std::to_string(closure.keyframe));
  }
  if (other == k) {
    return Status::Error(prefix + ": relates a keyframe to itself");
  }
  Status status = internal::CheckPose(closure.T, prefix + ": T");
  if (!status.ok()) return status;
  status = internal::CheckSigma(closure.sigma_t, prefix + ": sigma_t");
  if (!status.ok()) return status;
  return internal::CheckSigma(closure.sigma_r, prefix + ": sigma_r");
}

Status Backend::Impl::AddLoopClosure(KeyframeId keyframe,
                                     const LoopClosureInput& closure,
                                     LoopClosureReport* report) {
  const int k = trajectory_.IndexOf(keyframe);
  const std::string prefix = "loop closure of keyframe " +
                             std::to_string(keyframe) + " to " +
                             std::to_string(closure.keyframe);
  if (k < 0) {
    return Status::Error(prefix + ": unknown keyframe " +
                         std::to_string(keyframe));
  }
  Status status = CheckLoopClosure(k, closure, prefix);
  if (!status.ok()) return status;
  const LoopClosureReport done = CloseLoop(k, closure);
  if (report != nullptr) *report = done;
  return Status::Ok();
}

LoopClosureReport Backend::Impl::CloseLoop(int k,
                                           const LoopClosureInput& closure) {
  const auto start = std::chrono::steady_clock::now();
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const int other = trajectory_.IndexOf(closure.keyframe);
  internal::LoopConstraint loop;
  loop.earlier = std::min(k, other);
  loop.later = std::max(k, other);
  // closure.T is k's pose in other's frame.
  const Rigid3d T = internal::Normalized(closure.T);
  loop.T = k > other ? T : T.Inverse();
  loop.sigma_t = closure.sigma_t;
  loop.sigma_r = closure.sigma_r;
  loops_.push_back(loop);

  LoopClosureReport report;
  report.keyframe = keyframes[k]->id;
  report.other = closure.keyframe;
  const int window_begin =
      static_cast<int>(keyframes.size()) - options_.window_size;
  if (loop.earlier < std::max(window_begin, graph_.marginalized_until())) {
    std::vector<Rigid3d> corrected;
    PoseGraphSolveSummary summary;
    const Status status = internal::OptimizeKeyframeGraph(
        keyframes, loops_, &corrected, &summary);
    if (status.ok()) {
      const Rigid3d before = keyframes[k]->T_wc();
      for (size_t i = 0; i < keyframes.size(); ++i) {
        const Rigid3d step = corrected[i] * keyframes[i]->T_wc().Inverse();
        if (step.t.norm() > 1e-3 || AngleDeg(step.q) > 0.01) {
          ++report.keyframes_moved;
        }
      }
      MovePast(corrected);
      const Rigid3d step = keyframes[k]->T_wc() * before.Inverse();
      report.moved_past = true;
      report.correction_m = (keyframes[k]->T_wc().t - before.t).norm();
      report.correction_deg = AngleDeg(step.q);
      report.initial_cost = summary.given_cost;
      report.final_cost = summary.final_cost;
    } else {
      report.message = status.message();
    }
  }

  // The constraint, in every later solve that holds the later keyframe.
  internal::KeyframeState& a = *keyframes[loop.earlier];
  internal::KeyframeState& b = *keyframes[loop.later];
  internal::FactorRecord record;
  record.cost.reset(RelativePoseFactor::Create(
      loop.T, IsotropicPoseSqrtInfo(loop.sigma_t, loop.sigma_r)));
  record.blocks = {a.q, a.t, b.q, b.t};
  record.keyframe = loop.later;
  record.keyframe2 = loop.earlier;
  graph_.Add(std::move(record));

  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ++statistics_.loop_closures;
  statistics_.loop_closures_moved_past += report.moved_past ? 1 : 0;
  statistics_.loop_closure_seconds += report.seconds;
  loop_closures_.push_back(report);
  return report;
}

void Backend::Impl::ClosePendingLoops() {
  for (const auto& [k, closure] : pending_loops_) CloseLoop(k, closure);
  pending_loops_.clear();
}

void Backend::Impl::MovePast(const std::vector<Rigid3d>& corrected) {
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  std::vector<Rigid3d> moves(keyframes.size());
  for (size_t k = 0; k < keyframes.size(); ++k) {
    moves[k] = corrected[k] * keyframes[k]->T_wc().Inverse();
  }
  using Role = RigidBlockRole;
  std::unordered_map<const double*, RigidBlockMotion> motions;
  for (size_t k = 0; k < keyframes.size(); ++k) {
    motions[keyframes[k]->q] = {Role::kRotation, moves[k]};
    motions[keyframes[k]->t] = {Role::kPosition, moves[k]};
  }
  const internal::ObjectList& objects = map_.objects();
  for (const auto& object : objects) {
    if (object->last_keyframe < 0) continue;
    const Rigid3d& W = moves[object->last_keyframe];
    motions[object->q] = {Role::kRotation, W};
    motions[object->t] = {Role::kPosition, W};
    motions[object->a_w] = {Role::kAxis, W};
  }
  for (const auto& point : trajectory_.points()) {
    if (point->last_keyframe < 0) continue;
    motions[point->p] = {Role::kPosition, moves[point->last_keyframe]};
  }
  graph_.MovePriors([&motions](const double* block) {
    const auto it = motions.find(block);
    return it == motions.end() ? RigidBlockMotion{} : it->second;
  });

  for (size_t k = 0; k < keyframes.size(); ++k) {
    internal::WritePose(corrected[k], keyframes[k]->q, keyframes[k]->t);
  }
  for (size_t o = 0; o < objects.size(); ++o) {
    internal::ObjectState& object = *objects[o];
    if (object.last_keyframe < 0) continue;
    const Rigid3d& W = moves[object.last_keyframe];
    const Eigen::Quaterniond R = W.q.normalized();
    Eigen::Map<Eigen::Vector3d>(object.t) = W * object.position();
    Eigen::Map<Eigen::Quaterniond> q(object.q);
    q = (R * q).normalized();
    Eigen::Map<Eigen::Vector3d>(object.a_w) =
        (R * object.axis_w()).normalized();
    object.anchor.q_base = (R * object.anchor.q_base).normalized();
    object.anchor.a_w0 = object.anchor.q_base * object.anchor.a_o;
    // A discrete object's edges hold its anchor.
    if (object.type == SymmetryType::kDiscrete &&
        object.status != internal::ObjectStatus::kDropped) {
      edges_.Rebuild(static_cast<int>(o));
    }
  }
  for (const auto& point : trajectory_.points()) {
    if (point->last_keyframe < 0) continue;
    Eigen::Map<Eigen::Vector3d> p(point->p);
    p = moves[point->last_keyframe] * Eigen::Vector3d(p);
  }
}

}  // namespace symba
