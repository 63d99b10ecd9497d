#include "backend/window_problem.h"

#include <utility>

namespace symba::internal {
namespace {

ceres::Problem::Options ProblemOptions() {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.enable_fast_removal = true;
  return options;
}

}  // namespace

WindowProblem::WindowProblem() : problem_(ProblemOptions()) {}

void WindowProblem::SetManifold(const double* block,
                                const ceres::Manifold* manifold) {
  manifolds_[block] = manifold;
}

int WindowProblem::Add(FactorRecord record) {
  factors_.push_back(std::move(record));
  return static_cast<int>(factors_.size()) - 1;
}

void WindowProblem::Retire(int f) {
  FactorRecord& record = factors_[f];
  if (record.residual != nullptr) {
    problem_.RemoveResidualBlock(record.residual);
    record.residual = nullptr;
  }
  record.retired = true;
  record.cost.reset();
}

void WindowProblem::Sync(const std::vector<char>& active) {
  RemoveInactive(active);
  AddActive(active);
}

void WindowProblem::RemoveInactive(const std::vector<char>& active) {
  std::vector<double*> released;
  for (size_t f = 0; f < factors_.size(); ++f) {
    FactorRecord& record = factors_[f];
    if (record.residual == nullptr || active[f]) continue;
    problem_.RemoveResidualBlock(record.residual);
    record.residual = nullptr;
    released.insert(released.end(), record.blocks.begin(), record.blocks.end());
  }
  std::vector<ceres::ResidualBlockId> users;
  for (double* block : released) {
    if (!problem_.HasParameterBlock(block)) continue;
    problem_.GetResidualBlocksForParameterBlock(block, &users);
    if (users.empty()) problem_.RemoveParameterBlock(block);
  }
}

void WindowProblem::AddActive(const std::vector<char>& active) {
  for (size_t f = 0; f < factors_.size(); ++f) {
    FactorRecord& record = factors_[f];
    if (!active[f] || record.retired || record.residual != nullptr) continue;
    const std::vector<int32_t>& sizes = record.cost->parameter_block_sizes();
    for (size_t b = 0; b < record.blocks.size(); ++b) {
      EnsureBlock(record.blocks[b], sizes[b]);
    }
    record.residual =
        problem_.AddResidualBlock(record.cost.get(),
                                  const_cast<ceres::LossFunction*>(record.loss),
                                  record.blocks);
  }
}

void WindowProblem::EnsureBlock(double* block, int size) {
  if (problem_.HasParameterBlock(block)) return;
  const auto it = manifolds_.find(block);
  problem_.AddParameterBlock(block,
                             size,
                             it == manifolds_.end()
                                 ? nullptr
                                 : const_cast<ceres::Manifold*>(it->second));
}

bool WindowProblem::HasBlock(const double* block) const {
  return problem_.HasParameterBlock(block);
}

void WindowProblem::SetConstant(double* block, bool constant) {
  if (constant) {
    problem_.SetParameterBlockConstant(block);
  } else {
    problem_.SetParameterBlockVariable(block);
  }
}

void WindowProblem::Solve(const ceres::Solver::Options& options,
                          ceres::Solver::Summary* summary) {
  ceres::Solve(options, &problem_, summary);
}

}  // namespace symba::internal
