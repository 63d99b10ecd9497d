// The backend's factor graph: every factor between keyframes, objects and
// points (in a WindowProblem), which of them a solve holds, and the window:
// keyframes leaving it are marginalised into priors or dropped, and what
// no later solve needs is freed (docs/backend.md "The window";
// docs/architecture.md). It owns the factors, the priors and how far the
// window has moved; the keyframes, objects and points are the backend's,
// and it changes only their factor bookkeeping (factor lists, prior
// factors, and without keep_history the hypotheses of observations that
// left). Not installed.
#ifndef SYMBA_SRC_BACKEND_FACTOR_GRAPH_H_
#define SYMBA_SRC_BACKEND_FACTOR_GRAPH_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <ceres/manifold.h>

#include "backend/association.h"
#include "backend/backend_state.h"
#include "backend/marginalization.h"
#include "backend/window_problem.h"
#include "symba/backend/backend.h"
#include "symba/backend/backend_options.h"
#include "symba/factors/rigidly_moved_prior.h"

namespace symba::internal {

using KeyframeList = std::vector<std::unique_ptr<KeyframeState>>;
using PointList = std::vector<std::unique_ptr<PointState>>;

// What a solve did (the Ceres summary's part the backend reports) and the
// size of its problem.
struct SolveOutcome {
  bool solved = false;  // false: the problem had no residual blocks
  bool usable = true;
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::string message;
  int free_keyframes = 0;
  int residual_blocks = 0;
  int parameter_blocks = 0;
  int prior_size = 0;  // the keyframe prior's tangent dimension in the solve
};

// A factor is in the map unless it was retired or its object is not
// confirmed.
inline bool InMap(const FactorRecord& record, const ObjectList& objects) {
  return !record.retired &&
         (record.object < 0 ||
          objects[record.object]->status == ObjectStatus::kConfirmed);
}

class FactorGraph {
 public:
  // The containers are the backend's and must outlive the graph.
  FactorGraph(const BackendOptions& options,
              const KeyframeList& keyframes,
              const ObjectList& objects,
              const PointList& points,
              BackendStatistics* statistics);

  // The manifold a parameter block gets in every solve (none: Euclidean);
  // it must outlive the graph.
  void SetManifold(const double* block, const ceres::Manifold* manifold);
  // Registers a factor with the keyframes and points it touches; returns
  // its index. A rebuilt edge of a keyframe that left the window serves the
  // batch solve only.
  int Add(FactorRecord record);
  // Out of every solve for good (replaced or dropped); its cost is freed.
  void Retire(int f) { problem_.Retire(f); }
  const FactorRecord& factor(int f) const { return problem_.factor(f); }
  const KeyframeList& keyframes() const { return keyframes_; }
  // The first observation of `object` whose keyframe has not left the
  // window (0 under condition). O(log observations).
  int FirstLiveObservation(const ObjectState& object) const;
  // Eliminates `blocks` from object o's prior (their information on the
  // object's other blocks stays); nothing if the prior has none of them.
  void RemoveFromObjectPrior(int o, const std::vector<double*>& blocks);

  // Keyframes before this one have left the window.
  int marginalized_until() const { return marginalized_until_; }
  // A loop closure moved keyframe k by keyframe_moves[k] (T_wc <- W T_wc):
  // every prior moves rigidly (rigidly_moved_prior.h), the keyframe
  // prior's blocks each with their keyframe, object o's prior by
  // object_moves[o], point p's by point_moves[p] and then made less
  // certain by point_move_variances[p] (m^2, isotropic: how uncertain its
  // move is; inflated_prior.h). Replaced in place.
  void MovePriors(const std::vector<Rigid3d>& keyframe_moves,
                  const std::vector<Rigid3d>& object_moves,
                  const std::vector<Rigid3d>& point_moves,
                  const std::vector<double>& point_move_variances);

  // The window solve: keyframes before `first` leave the window, then the
  // window's factors and the priors (marginalize), every factor of what
  // the window observes (condition) or the window's factors (drop) are
  // solved with at most max_iterations.
  void SolveWindow(int first, SolveOutcome* outcome);
  // For each set of blocks, the joint covariance (tangent) of those the last
  // solve's selection holds free, at the current values: the problem is
  // first synced again as that solve would sync it now (edges rebuilt since
  // enter, and a keyframe added since, if in the window), which may change
  // the order of the next solve's residuals (its result at round-off
  // level). Nothing before the first solve.
  bool SolveCovariances(const std::vector<std::vector<const double*>>& sets,
                        std::vector<WindowProblem::BlockCovariance>* out);
  // Whether the last solve was a window solve that held keyframes as known
  // (they had left its window, or under drop its oldest keyframe was the
  // gauge): its covariances are then conditioned on them.
  bool LastSolveHeldThePast() const {
    return last_solve_.any && !last_solve_.batch && last_solve_.first > 0;
  }

  // Every factor in the map, everything free but the first keyframe.
  // Fails without keep_history once keyframes have left the window.
  Status SolveBatch(SolveOutcome* outcome);

 private:
  // condition: the window keyframes' factors and every factor of what they
  // observe (grows with the run).
  std::vector<int> ConditionedFactors(int first_free) const;
  // marginalize, drop: the window keyframes' factors and the priors of what
  // they observe.
  std::vector<int> WindowFactors(int first_free) const;
  // batch: every factor in the map.
  std::vector<int> AllFactors() const;
  // Those of `factors` that are edges with LineOfSightRows hold their
  // keyframe's current pose from now on (before a solve, over the factors
  // in its problem, and before a keyframe leaves the window, over its
  // factors: those rows take the cameras as given). O(factors).
  void HoldCamerasForSightRows(const std::vector<int>& factors);
  // Sets the keyframes the problem holds constant or free (free: index >=
  // first_free, not the gauge); returns the free count. O(problem size).
  int SetKeyframeFreedom(int first_free, int gauge);
  // Syncs the problem to the factors of a window solve from `first` (or of
  // the batch solve) and sets the keyframes' freedom; returns the free
  // count.
  int Prepare(bool batch, int first);
  void Solve(int max_iterations, int free_keyframes, SolveOutcome* outcome);

  // Keyframe k leaves the window: under marginalize its motion factors go
  // into the keyframe prior, its object edges and point observations into
  // each object's and point's own prior; under drop they just leave.
  void LeaveWindow(int k);
  // The factors of a point or object (`own`: its blocks) from a keyframe
  // that leaves the window, conditioned on everything else and merged with
  // `share` of their information into its own prior (*prior_factor).
  void MergeIntoOwnPrior(const std::vector<int>& factors,
                         const std::vector<double*>& own,
                         double share,
                         int object,
                         int point,
                         int* prior_factor);
  // Marginalises `terms` (`describe` says which blocks are the entity's) and
  // stores the result as the entity's prior in place of *prior_factor.
  void ReplaceOwnPrior(const std::vector<MarginalizationTerm>& terms,
                       const BlockDescriber& describe,
                       int object,
                       int point,
                       int* prior_factor);
  // Frees what keyframe k's `left` factors hold that no window solve needs
  // again: its factor list, and without keep_history the factors' cost
  // functions and their observations' hypotheses.
  void ForgetLeftKeyframe(int k, const std::vector<int>& left);

  const BackendOptions& options_;
  const KeyframeList& keyframes_;
  const ObjectList& objects_;
  const PointList& points_;
  BackendStatistics* statistics_;
  MarginalizationOptions marginalization_;
  WindowProblem problem_;
  // Keyframes before this one have left the window.
  int marginalized_until_ = 0;
  // What the last solve held (Prepare's arguments).
  struct LastSolve {
    bool any = false;
    bool batch = false;
    int first = 0;
  };
  LastSolve last_solve_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_FACTOR_GRAPH_H_
