// FactorGraph: the factors' registry, what each solve holds and the solves
// (factor_graph.h). Keyframes leaving the window are in window.cc.
#include "backend/factor_graph.h"

#include <algorithm>
#include <utility>

#include <ceres/solver.h>

#include "backend/keyframe_graph.h"
#include "symba/common/check.h"
#include "symba/factors/inflated_prior.h"
#include "symba/factors/line_of_sight_rows.h"

namespace symba::internal {

FactorGraph::FactorGraph(const BackendOptions& options,
                         const KeyframeList& keyframes,
                         const ObjectList& objects,
                         const PointList& points,
                         BackendStatistics* statistics)
    : options_(options),
      keyframes_(keyframes),
      objects_(objects),
      points_(points),
      statistics_(statistics) {
  marginalization_.min_winner_margin = options.marginalize_min_margin;
  marginalization_.rival_distance = options.marginalize_rival_distance;
}

void FactorGraph::SetManifold(const double* block,
                              const ceres::Manifold* manifold) {
  problem_.SetManifold(block, manifold);
}

int FactorGraph::FirstLiveObservation(const ObjectState& object) const {
  if (options_.window_policy == WindowPolicy::kCondition) return 0;
  // Observations are in keyframe order.
  const auto first =
      std::partition_point(object.observations.begin(),
                           object.observations.end(),
                           [this](const ObjectObservation& observation) {
                             return observation.keyframe < marginalized_until_;
                           });
  return static_cast<int>(first - object.observations.begin());
}

int FactorGraph::Add(FactorRecord record) {
  SYMBA_CHECK(record.cost != nullptr) << "a factor without a cost function";
  // A rebuilt edge of a keyframe that left the window serves the batch
  // solve only.
  record.marginalized = options_.window_policy != WindowPolicy::kCondition &&
                        record.keyframe >= 0 &&
                        record.keyframe < marginalized_until_;
  const int f = problem_.size();
  // A loaded object's prior belongs to no keyframe.
  if (record.keyframe >= 0) keyframes_[record.keyframe]->factors.push_back(f);
  if (record.keyframe2 >= 0) keyframes_[record.keyframe2]->factors.push_back(f);
  // Only the condition policy reads a point's factors.
  if (record.point >= 0 && options_.window_policy == WindowPolicy::kCondition) {
    points_[record.point]->factors.push_back(f);
  }
  problem_.Add(std::move(record));
  return f;
}

std::vector<int> FactorGraph::ConditionedFactors(int first_free) const {
  // The window keyframes and everything they observe, with every factor of
  // those.
  const int n = static_cast<int>(keyframes_.size());
  std::vector<char> object_free(objects_.size(), 0);
  std::vector<char> point_free(points_.size(), 0);
  std::vector<int> active;
  for (int k = first_free; k < n; ++k) {
    for (int f : keyframes_[k]->factors) {
      const FactorRecord& record = problem_.factor(f);
      if (!InMap(record, objects_)) continue;
      active.push_back(f);
      if (record.object >= 0) object_free[record.object] = 1;
      if (record.point >= 0) point_free[record.point] = 1;
    }
  }
  for (size_t o = 0; o < objects_.size(); ++o) {
    if (!object_free[o]) continue;
    for (const ObjectObservation& observation : objects_[o]->observations) {
      if (observation.factor >= 0) active.push_back(observation.factor);
    }
    // A loaded object's prior (the only object prior under condition).
    if (objects_[o]->prior_factor >= 0) {
      active.push_back(objects_[o]->prior_factor);
    }
  }
  for (size_t p = 0; p < points_.size(); ++p) {
    if (!point_free[p]) continue;
    for (int f : points_[p]->factors) {
      if (InMap(problem_.factor(f), objects_)) active.push_back(f);
    }
  }
  return active;
}

std::vector<int> FactorGraph::WindowFactors(int first_free) const {
  std::vector<int> active;
  std::vector<int> points;
  std::vector<int> objects;
  for (int k = first_free; k < static_cast<int>(keyframes_.size()); ++k) {
    for (int f : keyframes_[k]->factors) {
      const FactorRecord& record = problem_.factor(f);
      if (!InMap(record, objects_) || record.marginalized) continue;
      active.push_back(f);
      if (record.point >= 0) points.push_back(record.point);
      if (record.object >= 0) objects.push_back(record.object);
    }
  }
  std::sort(objects.begin(), objects.end());
  objects.erase(std::unique(objects.begin(), objects.end()), objects.end());
  for (int o : objects) {
    if (objects_[o]->prior_factor >= 0) {
      active.push_back(objects_[o]->prior_factor);
    }
  }
  // The points' priors from their observations that left the window.
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  for (int p : points) {
    if (points_[p]->prior_factor >= 0)
      active.push_back(points_[p]->prior_factor);
  }
  return active;
}

std::vector<int> FactorGraph::AllFactors() const {
  std::vector<int> active;
  for (int f = 0; f < problem_.size(); ++f) {
    const FactorRecord& record = problem_.factor(f);
    if (InMap(record, objects_) && !record.summary) active.push_back(f);
  }
  return active;
}

int FactorGraph::SetKeyframeFreedom(int first_free, int gauge) {
  // Every keyframe the problem holds appears in one of its factors.
  std::vector<int> held;
  for (int f : problem_.in_problem()) {
    const FactorRecord& record = problem_.factor(f);
    if (record.keyframe >= 0) held.push_back(record.keyframe);
    if (record.keyframe2 >= 0) held.push_back(record.keyframe2);
  }
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  int free_keyframes = 0;
  for (int k : held) {
    KeyframeState& kf = *keyframes_[k];
    const bool free = k >= first_free && k != gauge;
    problem_.SetConstant(kf.q, !free);
    problem_.SetConstant(kf.t, !free);
    free_keyframes += free ? 1 : 0;
  }
  return free_keyframes;
}

void FactorGraph::SolveWindow(int first, SolveOutcome* outcome) {
  if (options_.window_policy != WindowPolicy::kCondition) {
    // A leaving keyframe's edges are linearised with its current pose.
    for (int k = marginalized_until_; k < first; ++k) {
      HoldCamerasForSightRows(keyframes_[k]->factors);
    }
    while (marginalized_until_ < first) LeaveWindow(marginalized_until_++);
  }
  const int free_keyframes = Prepare(false, first);
  HoldCamerasForSightRows(problem_.in_problem());
  Solve(options_.max_iterations, free_keyframes, outcome);
}

void FactorGraph::HoldCamerasForSightRows(const std::vector<int>& factors) {
  for (int f : factors) {
    const FactorRecord& record = problem_.factor(f);
    auto* sight = dynamic_cast<LineOfSightRows*>(record.cost.get());
    if (sight == nullptr || record.keyframe < 0) continue;
    const Rigid3d T_wc = keyframes_[record.keyframe]->T_wc();
    sight->Refresh(T_wc.q, T_wc.t);
  }
}

Status FactorGraph::SolveBatch(SolveOutcome* outcome) {
  if (!options_.keep_history && marginalized_until_ > 0) {
    return Status::Error(
        "no batch solve: keyframes left the window and their factors were "
        "freed (set BackendOptions::keep_history to keep them)");
  }
  const int free_keyframes = Prepare(true, 0);
  HoldCamerasForSightRows(problem_.in_problem());
  Solve(options_.batch_max_iterations, free_keyframes, outcome);
  return Status::Ok();
}

int FactorGraph::Prepare(bool batch, int first) {
  last_solve_ = LastSolve{true, batch, first};
  WindowProblem::SyncOptions sync;
  if (batch) {
    sync.with_marginalized = true;
    problem_.Sync(AllFactors(), sync);
    return SetKeyframeFreedom(0, 0);
  }
  const WindowPolicy policy = options_.window_policy;
  // The gauge: the first keyframe while in the window; under drop the
  // oldest window keyframe.
  int gauge = 0;
  if (policy == WindowPolicy::kCondition) {
    problem_.Sync(ConditionedFactors(first), sync);
  } else {
    sync.with_prior = policy == WindowPolicy::kMarginalize;
    problem_.Sync(WindowFactors(first), sync);
    if (policy == WindowPolicy::kDrop) gauge = first;
  }
  return SetKeyframeFreedom(first, gauge);
}

bool FactorGraph::SolveCovariances(
    const std::vector<std::vector<const double*>>& sets,
    std::vector<WindowProblem::BlockCovariance>* out) {
  if (!last_solve_.any) {
    out->assign(sets.size(), WindowProblem::BlockCovariance());
    return true;
  }
  // Edges rebuilt since (re-anchoring, noise updates, upgrades) left the
  // problem without their replacements: hold what the last solve held, as
  // it is now.
  Prepare(last_solve_.batch, last_solve_.first);
  return problem_.Covariances(sets, out);
}

void FactorGraph::Solve(int max_iterations,
                        int free_keyframes,
                        SolveOutcome* outcome) {
  ceres::Solver::Summary summary;
  outcome->solved = problem_.ProblemSize().residual_blocks > 0;
  if (outcome->solved) {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = max_iterations;
    solver_options.num_threads = options_.num_threads;
    solver_options.logging_type = ceres::SILENT;
    problem_.Solve(solver_options, &summary);
  }
  outcome->usable = summary.IsSolutionUsable();
  outcome->converged = summary.termination_type == ceres::CONVERGENCE;
  outcome->iterations = static_cast<int>(summary.iterations.size());
  outcome->initial_cost = summary.initial_cost;
  outcome->final_cost = summary.final_cost;
  outcome->message = summary.message;
  outcome->free_keyframes = free_keyframes;
  const WindowProblem::Size size = problem_.ProblemSize();
  outcome->residual_blocks = size.residual_blocks;
  outcome->parameter_blocks = size.parameter_blocks;
  outcome->prior_size = size.prior_size;
}

namespace {

// `prior` on `blocks` moved as `motion_of` says.
std::unique_ptr<MarginalPriorFactor> MovedPrior(
    const MarginalPriorFactor& prior,
    const std::vector<double*>& blocks,
    const std::function<RigidBlockMotion(const double*)>& motion_of) {
  std::vector<RigidBlockMotion> motions;
  motions.reserve(blocks.size());
  for (const double* block : blocks) motions.push_back(motion_of(block));
  std::unique_ptr<MarginalPriorFactor> moved;
  const Status status = MovePriorRigidly(prior, motions, &moved);
  // The roles come from the blocks' owners, which the priors were made of.
  SYMBA_CHECK(status.ok()) << status.message();
  return moved;
}

}  // namespace

void FactorGraph::MovePriors(const std::vector<Rigid3d>& keyframe_moves,
                             const std::vector<Rigid3d>& object_moves,
                             const std::vector<Rigid3d>& point_moves,
                             const std::vector<double>& point_move_variances) {
  const std::vector<Rigid3d>& moves = keyframe_moves;
  using Role = RigidBlockRole;
  if (problem_.prior() != nullptr) {
    // Its blocks are window keyframes' poses: search from the newest.
    auto motion_of = [&](const double* block) {
      for (int k = static_cast<int>(keyframes_.size()) - 1; k >= 0; --k) {
        const KeyframeState& kf = *keyframes_[k];
        if (block == kf.q) return RigidBlockMotion{Role::kRotation, moves[k]};
        if (block == kf.t) return RigidBlockMotion{Role::kPosition, moves[k]};
      }
      return RigidBlockMotion{};
    };
    const std::vector<double*> blocks = problem_.prior_blocks();
    problem_.SetPrior(MovedPrior(*problem_.prior(), blocks, motion_of), blocks);
  }
  // An entity's prior moved by W, its blocks by their roles, then
  // inflated by `variance` in every tangent direction.
  auto move = [&](int prior_factor,
                  const Rigid3d& W,
                  const std::function<Role(const double*)>& role_of,
                  double variance) {
    if (prior_factor < 0 || (IsIdentity(W) && variance <= 0.0)) return;
    const FactorRecord& record = problem_.factor(prior_factor);
    // A dropped object's prior is retired with it. A loaded map's prior,
    // not yet merged with the run's observations (not a summary), holds
    // the map's frame: it stays.
    if (record.retired || record.cost == nullptr || !record.summary) return;
    const auto* prior =
        dynamic_cast<const MarginalPriorFactor*>(record.cost.get());
    SYMBA_CHECK(prior != nullptr) << "an entity's prior is not a prior";
    std::unique_ptr<MarginalPriorFactor> moved =
        MovedPrior(*prior, record.blocks, [&](const double* block) {
          return RigidBlockMotion{role_of(block), W};
        });
    if (variance > 0.0) {
      const Eigen::VectorXd added =
          Eigen::VectorXd::Constant(moved->A().cols(), variance);
      std::unique_ptr<MarginalPriorFactor> inflated;
      const Status status = InflatePrior(*moved, added, &inflated);
      SYMBA_CHECK(status.ok()) << status.message();
      moved = std::move(inflated);
    }
    problem_.ReplaceCost(prior_factor, std::move(moved));
  };
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectState& o = *objects_[i];
    move(
        o.prior_factor,
        object_moves[i],
        [&o](const double* block) {
          if (block == o.q) return Role::kRotation;
          if (block == o.t) return Role::kPosition;
          if (block == o.a_w) return Role::kAxis;
          return Role::kUnmoved;  // a discrete angle
        },
        0.0);
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    move(
        points_[i]->prior_factor,
        point_moves[i],
        [](const double*) { return Role::kPosition; },
        point_move_variances[i]);
  }
}

}  // namespace symba::internal
