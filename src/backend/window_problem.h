// The persistent Ceres problem behind the windowed and batch solves
// (docs/backend.md "The persistent problem"). It owns every factor ever
// added (a FactorRecord with its cost function) and the manifold of each
// parameter block, and keeps one ceres::Problem holding exactly the active
// factors: a solve adds the factors that became active and removes those
// that left, and removes parameter blocks no active factor uses. Nothing is
// rebuilt per keyframe. Not installed.
#ifndef SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_
#define SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_

#include <unordered_map>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "backend/backend_state.h"

namespace symba::internal {

class WindowProblem {
 public:
  WindowProblem();
  WindowProblem(const WindowProblem&) = delete;
  WindowProblem& operator=(const WindowProblem&) = delete;

  // The manifold a parameter block gets when it enters the problem (none:
  // Euclidean). The manifold must outlive this object.
  void SetManifold(const double* block, const ceres::Manifold* manifold);

  // Takes the record (cost function non-null) and returns its index. It
  // enters the problem at the next Sync that marks it active.
  int Add(FactorRecord record);
  // Out of the problem for good (replaced by a rebuilt factor); its cost
  // function is freed.
  void Retire(int f);

  const FactorRecord& factor(int f) const { return factors_[f]; }
  int size() const { return static_cast<int>(factors_.size()); }

  // Makes the problem hold exactly the non-retired factors with active[f]
  // (active.size() == size()), adding their parameter blocks with their
  // manifolds and removing blocks that no factor uses any more.
  void Sync(const std::vector<char>& active);

  bool HasBlock(const double* block) const;
  // The block must be in the problem.
  void SetConstant(double* block, bool constant);
  int NumResidualBlocks() const { return problem_.NumResidualBlocks(); }

  void Solve(const ceres::Solver::Options& options,
             ceres::Solver::Summary* summary);

 private:
  void RemoveInactive(const std::vector<char>& active);
  void AddActive(const std::vector<char>& active);
  void EnsureBlock(double* block, int size);

  std::vector<FactorRecord> factors_;
  std::unordered_map<const double*, const ceres::Manifold*> manifolds_;
  ceres::Problem problem_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_WINDOW_PROBLEM_H_
