// The persistent Ceres problem behind the windowed and batch solves
// (docs/backend.md "The persistent problem"). It owns every factor ever
// added (a FactorRecord with its cost function), the marginalisation prior
// and the manifold of each parameter block, and keeps one ceres::Problem
// holding exactly the active factors: a solve adds the factors that became
// active and removes those that left, and removes parameter blocks no
// active factor uses. Sync costs O(factors in the problem before and
// after), never O(factors ever added). Not installed.
#ifndef SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_
#define SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_

#include <deque>
#include <memory>
#include <unordered_map>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <Eigen/Core>

#include "backend/backend_state.h"
#include "symba/factors/marginal_prior_factor.h"

namespace symba::internal {

class WindowProblem {
 public:
  WindowProblem();
  WindowProblem(const WindowProblem&) = delete;
  WindowProblem& operator=(const WindowProblem&) = delete;

  // The manifold a parameter block gets when it enters the problem (none:
  // Euclidean). The manifold must outlive this object.
  void SetManifold(const double* block, const ceres::Manifold* manifold);
  const ceres::Manifold* ManifoldOf(const double* block) const;

  // Takes the record (cost function non-null) and returns its index. It
  // enters the problem at the next Sync that marks it active.
  int Add(FactorRecord record);
  // Out of the problem for good (replaced by a rebuilt factor); its cost
  // function is freed.
  void Retire(int f);
  // The same factor (index, blocks, flags) with another cost function; it
  // leaves the problem and enters again at the next Sync that marks it
  // active.
  void ReplaceCost(int f, std::unique_ptr<ceres::CostFunction> cost);
  // Marginalised: out of the window solves for good (Sync skips it unless
  // with_marginalized), kept for the batch solve.
  void MarkMarginalized(int f);
  // A marginalised factor the batch solve will not need: its cost function
  // and blocks are freed, and it can never enter a solve again.
  void Forget(int f);

  const FactorRecord& factor(int f) const { return factors_[f]; }
  int size() const { return static_cast<int>(factors_.size()); }

  // The marginalisation prior (null: none) on `blocks`, replacing the
  // previous one; it enters the problem at the next Sync with_prior.
  void SetPrior(std::unique_ptr<MarginalPriorFactor> prior,
                std::vector<double*> blocks);
  const MarginalPriorFactor* prior() const { return prior_.get(); }
  const std::vector<double*>& prior_blocks() const { return prior_blocks_; }

  // Makes the problem hold exactly the factors of `active` (indices; the
  // retired ones, and the marginalised ones unless with_marginalized, are
  // skipped) and the prior if with_prior, adding their parameter blocks
  // with their manifolds and removing blocks that nothing uses any more.
  struct SyncOptions {
    bool with_prior = false;
    bool with_marginalized = false;
  };
  void Sync(const std::vector<int>& active, const SyncOptions& options);
  // The factors in the problem after the last Sync.
  const std::vector<int>& in_problem() const { return in_problem_; }

  bool HasBlock(const double* block) const;
  // The block must be in the problem.
  void SetConstant(double* block, bool constant);
  // What the problem holds after the last Sync.
  struct Size {
    int residual_blocks = 0;
    int parameter_blocks = 0;
    int prior_size = 0;  // the prior's tangent dimension (0: not in it)
  };
  Size ProblemSize() const;

  void Solve(const ceres::Solver::Options& options,
             ceres::Solver::Summary* summary);
  // For each set of blocks, the joint covariance of those the problem
  // holds free, in their tangent spaces at the current values (computed for
  // every set at once). False if Ceres cannot compute it (a rank-deficient
  // problem).
  struct BlockCovariance {
    std::vector<const double*> blocks;  // the set's blocks held free
    Eigen::MatrixXd covariance;         // tangent, in the order of blocks
  };
  bool Covariances(const std::vector<std::vector<const double*>>& sets,
                   std::vector<BlockCovariance>* covariances);

 private:
  void ReleaseUnusedBlocks();

  // A deque: adding a factor never moves the others (no peak of twice the
  // records when a vector would grow).
  std::deque<FactorRecord> factors_;
  std::unordered_map<const double*, const ceres::Manifold*> manifolds_;
  std::vector<int> in_problem_;
  int sync_stamp_ = 0;
  std::vector<double*> released_;  // blocks whose residuals left
  std::unique_ptr<MarginalPriorFactor> prior_;
  std::vector<double*> prior_blocks_;
  ceres::ResidualBlockId prior_residual_ = nullptr;
  ceres::Problem problem_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_
