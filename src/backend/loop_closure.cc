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
#include "backend/detection_noise.h"
#include "backend/keyframe_validation.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/geometry/pi.h"
#include "symba/geometry/swing_twist.h"

namespace symba {
namespace {

double AngleDeg(const Eigen::Quaterniond& q) {
  return kDegreesPerRadian * 2.0 *
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
  // Its information 1 / sigma^2 must be a positive finite number too.
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
  const int other = trajectory_.IndexOf(closure.keyframe);
  if (std::max(k, other) >= solved_keyframes_) {
    pending_loops_.emplace_back(k, closure);
    if (report != nullptr) *report = WaitingReport(k, closure);
    return Status::Ok();
  }
  const LoopClosureReport done = CloseLoop(k, closure);
  if (report != nullptr) *report = done;
  return Status::Ok();
}

LoopClosureReport Backend::Impl::WaitingReport(
    int k, const LoopClosureInput& closure) const {
  LoopClosureReport report;
  report.keyframe = trajectory_.keyframes()[k]->id;
  report.other = closure.keyframe;
  report.waiting = true;
  report.message = "waits for the next solve";
  return report;
}

std::vector<LoopClosureReport> Backend::Impl::LoopClosures() const {
  std::vector<LoopClosureReport> reports = loop_closures_;
  for (const auto& [k, closure] : pending_loops_) {
    reports.push_back(WaitingReport(k, closure));
  }
  return reports;
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
    MovePastByGraph(k, 0.0, &report);
  }
  if (report.message.empty()) {
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
  } else {
    // Without the moved past, the closure would kink the window against
    // the held keyframes: it is left out (reported), also of later graphs.
    loops_.pop_back();
  }

  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ++statistics_.loop_closures;
  statistics_.loop_closures_moved_past += report.moved_past ? 1 : 0;
  statistics_.loop_closure_seconds += report.seconds;
  loop_closures_.push_back(report);
  return report;
}

void Backend::Impl::MovePastByGraph(int k,
                                    double min_correction_m,
                                    LoopClosureReport* out) {
  LoopClosureReport& report = *out;
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const int window_begin =
      static_cast<int>(keyframes.size()) - options_.window_size;
  const std::vector<internal::GraphObject> objects = GraphObjects();
  std::vector<Rigid3d> keyframe_poses;
  std::vector<Rigid3d> object_poses;
  PoseGraphSolveSummary summary;
  const Status status = internal::OptimizeKeyframeGraph(keyframes,
                                                        window_begin,
                                                        loops_,
                                                        objects,
                                                        &keyframe_poses,
                                                        &object_poses,
                                                        &summary);
  if (status.ok() && (keyframe_poses[k].t - keyframes[k]->T_wc().t).norm() <
                         min_correction_m) {
    return;  // the past stays as the window left it
  }
  if (status.ok()) {
    const Rigid3d before = keyframes[k]->T_wc();
    // The window moves as one: its solves made its keyframes, objects and
    // points agree, and a bend inside it could put a point behind a
    // camera. It takes the newest keyframe's correction.
    std::vector<Rigid3d> moves(keyframes.size());
    for (size_t i = 0; i < keyframes.size(); ++i) {
      moves[i] = keyframe_poses[i] * keyframes[i]->T_wc().Inverse();
    }
    for (size_t i = std::max(0, window_begin); i < keyframes.size(); ++i) {
      moves[i] = moves.back();
    }
    for (const Rigid3d& step : moves) {
      if (step.t.norm() > 1e-3 || AngleDeg(step.q) > 0.01) {
        ++report.keyframes_moved;
      }
    }
    MovePast(moves,
             ObjectMoves(moves, objects, object_poses, window_begin),
             window_begin);
    const Rigid3d step = keyframes[k]->T_wc() * before.Inverse();
    report.moved_past = true;
    past_moved_ = true;
    report.correction_m = (keyframes[k]->T_wc().t - before.t).norm();
    report.correction_deg = AngleDeg(step.q);
    report.initial_cost = summary.given_cost;
    report.final_cost = summary.final_cost;
  } else {
    report.message = status.message();
  }
}

bool Backend::Impl::MovePastForRevisit() {
  // Below one motion step's translation noise the graph's correction is
  // within what the window absorbs, and the graph (no map points, the
  // stated motion noise) is an approximation of the run: the past stays.
  const int k = static_cast<int>(trajectory_.keyframes().size()) - 1;
  LoopClosureReport report;
  MovePastByGraph(
      k, std::sqrt(trajectory_.keyframes()[k]->motion_variance_t), &report);
  if (!report.moved_past) return false;
  ++statistics_.revisits_moved_past;
  return true;
}

std::vector<internal::GraphObject> Backend::Impl::GraphObjects() const {
  const internal::ObjectList& objects = map_.objects();
  std::vector<internal::GraphObject> out(objects.size());
  for (size_t o = 0; o < objects.size(); ++o) {
    const internal::ObjectState& object = *objects[o];
    if (!internal::IsMapped(object)) continue;
    internal::GraphObject& g = out[o];
    // The baselines call every object asymmetric, and their representative
    // hypothesis flips among a symmetric object's poses: position only.
    g.rotation = object.type == SymmetryType::kAsymmetric &&
                 options_.method == Method::kSymba;
    g.T_wo = Rigid3d(object.Rotation(-1), object.position());
    g.fixed = internal::IsLoaded(object);
    g.class_name = object.class_name;
    // A symmetric object's detections measure its axis (symba only).
    const bool symmetric_axis = object.type != SymmetryType::kAsymmetric &&
                                options_.method == Method::kSymba;
    if (symmetric_axis) g.axis_w = object.axis_w();
    const internal::ObjectObservation* first = nullptr;
    for (const internal::ObjectObservation& observation : object.observations) {
      if (observation.turned_away) continue;  // weighs nothing
      if (first == nullptr) first = &observation;
      // A symba detection makes one observation per mode.
      if (g.keyframes.empty() || g.keyframes.back() != observation.keyframe) {
        g.keyframes.push_back(observation.keyframe);
        g.measured.push_back(observation.T_co_best);
        if (symmetric_axis) {
          g.measured_axes.push_back(internal::MeasuredAxis(
              object,
              observation,
              trajectory_.keyframes()[observation.keyframe]->T_wc().q));
        }
      }
    }
    if (first == nullptr) continue;  // no view that weighs anything
    // The noise its edges are weighed with (its first detection's).
    const internal::EdgeSigmas sigmas = internal::EffectiveNoise(
        *first, edges_.AppliedNoise(object.class_name));
    g.sigma_t = sigmas.t;
    g.sigma_r = sigmas.r;
    g.noise_stated =
        first->claimed_t || first->claimed_r || first->from_scatter;
    // As the window weighs them: a continuous object's axis with
    // axis_sigma / gamma (none for gamma = 0), a discrete one's rotation
    // with the detection's sigma_r.
    g.sigma_axis =
        object.type == SymmetryType::kContinuous
            ? (options_.gamma > 0.0 ? options_.axis_sigma / options_.gamma
                                    : 0.0)
            : sigmas.r;
    // No axis where one is not a unit vector (an object without a measured
    // or object-frame axis, for any of its detections) or its noise is not
    // a usable number (an information 1 / sigma^2 finite and positive).
    auto unit = [](const Eigen::Vector3d& a) {
      return a.allFinite() && std::abs(a.norm() - 1.0) < 1e-6;
    };
    const bool usable =
        unit(g.axis_w.normalized()) && g.sigma_axis > 0.0 &&
        std::isfinite(1.0 / (g.sigma_axis * g.sigma_axis)) &&
        std::all_of(g.measured_axes.begin(), g.measured_axes.end(), unit);
    if (!usable) g.measured_axes.clear();
  }
  return out;
}

std::vector<Rigid3d> Backend::Impl::ObjectMoves(
    const std::vector<Rigid3d>& moves,
    const std::vector<internal::GraphObject>& objects,
    const std::vector<Rigid3d>& object_poses,
    int window_begin) const {
  const internal::ObjectList& states = map_.objects();
  std::vector<Rigid3d> out(objects.size());
  for (size_t o = 0; o < objects.size(); ++o) {
    const internal::ObjectState& state = *states[o];
    const internal::GraphObject& g = objects[o];
    if (state.last_keyframe < 0 ||
        state.status == internal::ObjectStatus::kDropped) {
      continue;  // never detected in this run, or gone
    }
    // Seen from the window only (a tentative object always is): it moves
    // with the window, as the window's solves placed it.
    const int first_seen = state.observations.empty()
                               ? state.last_keyframe
                               : state.observations.front().keyframe;
    if (first_seen >= window_begin) {
      out[o] = moves.back();
      continue;
    }
    if (g.keyframes.empty()) {
      // Not in the graph (tentative): the mean move of its detectors.
      std::vector<int> detectors;
      for (const internal::ObjectObservation& observation :
           state.observations) {
        detectors.push_back(observation.keyframe);
      }
      out[o] = internal::MeanMove(moves, detectors, state.position());
      continue;
    }
    const Rigid3d& after = object_poses[o];
    // An asymmetric object turns as its vertex did; a symmetric one, whose
    // vertex rotation about its axis nothing measures, as its detecting
    // keyframes did on average.
    Eigen::Quaterniond R =
        g.rotation ? (after.q * g.T_wo.q.inverse()).normalized()
                   : internal::MeanMove(moves, g.keyframes, g.T_wo.t).q;
    if (g.HasAxis()) {
      // Its axis as its vertex turned it (its edges measured the axis), the
      // turn about it as its detecting keyframes did.
      const Eigen::Vector3d axis_after =
          after.q * (g.T_wo.q.inverse() * g.axis_w);
      R = (MinimalRotation(Eigen::Vector3d(R * g.axis_w), axis_after) * R)
              .normalized();
    }
    out[o] = Rigid3d(R, after.t - R * g.T_wo.t);
  }
  return out;
}

void Backend::Impl::ClosePendingLoops() {
  for (const auto& [k, closure] : pending_loops_) CloseLoop(k, closure);
  pending_loops_.clear();
}

void Backend::Impl::MovePast(const std::vector<Rigid3d>& moves,
                             const std::vector<Rigid3d>& object_moves,
                             int window_begin) {
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const internal::ObjectList& objects = map_.objects();
  const internal::PointList& points = trajectory_.points();
  // Each point seen from the window with the window (so that it stays in
  // front of the window's cameras), any other by the mean move of its first
  // and last observer. Where those two moves take the point to different
  // places (a point seen on several visits whose keyframes the graph moved
  // differently), its prior becomes less certain by their spread: the
  // variance of the two-point distribution, (d / 2)^2 per axis with d the
  // distance between the two places. Held at full certainty, the prior of a
  // point seen on every lap would pin it where an approximate move put it,
  // against the objects and the window's cameras at the next visit.
  std::vector<Rigid3d> point_moves(points.size());
  std::vector<double> point_move_variances(points.size(), 0.0);
  for (size_t i = 0; i < points.size(); ++i) {
    const internal::PointState& point = *points[i];
    if (point.last_keyframe < 0) continue;
    if (point.last_keyframe >= window_begin) {
      point_moves[i] = moves.back();
      continue;
    }
    const Eigen::Vector3d p = Eigen::Map<const Eigen::Vector3d>(point.p);
    point_moves[i] = internal::MeanMove(
        moves, {point.first_keyframe, point.last_keyframe}, p);
    const double spread =
        (moves[point.first_keyframe] * p - moves[point.last_keyframe] * p)
            .norm();
    point_move_variances[i] = 0.25 * spread * spread;
  }
  graph_.MovePriors(moves, object_moves, point_moves, point_move_variances);

  for (size_t k = 0; k < keyframes.size(); ++k) {
    internal::WritePose(
        moves[k] * keyframes[k]->T_wc(), keyframes[k]->q, keyframes[k]->t);
  }
  for (size_t o = 0; o < objects.size(); ++o) {
    internal::ObjectState& object = *objects[o];
    const Rigid3d& W = object_moves[o];
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
        object.status != internal::ObjectStatus::kDropped &&
        !internal::IsIdentity(W)) {
      edges_.Rebuild(static_cast<int>(o));
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Map<Eigen::Vector3d> p(points[i]->p);
    p = point_moves[i] * Eigen::Vector3d(p);
  }
}

}  // namespace symba
