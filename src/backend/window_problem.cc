#include "backend/window_problem.h"

#include <algorithm>
#include <utility>

#include <ceres/covariance.h>

#include "symba/common/check.h"

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

// Adds `block` to `problem` with its manifold unless the problem has it.
void EnsureBlock(
    const std::unordered_map<const double*, const ceres::Manifold*>& manifolds,
    double* block,
    int size,
    ceres::Problem* problem) {
  if (problem->HasParameterBlock(block)) return;
  const auto it = manifolds.find(block);
  problem->AddParameterBlock(block,
                             size,
                             it == manifolds.end()
                                 ? nullptr
                                 : const_cast<ceres::Manifold*>(it->second));
}

// Takes *residual (if any) out of `problem`; its blocks join `released`,
// to be removed once nothing uses them.
void RemoveResidual(ceres::ResidualBlockId* residual,
                    const std::vector<double*>& blocks,
                    ceres::Problem* problem,
                    std::vector<double*>* released) {
  if (*residual == nullptr) return;
  problem->RemoveResidualBlock(*residual);
  *residual = nullptr;
  released->insert(released->end(), blocks.begin(), blocks.end());
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

const ceres::Manifold* WindowProblem::ManifoldOf(const double* block) const {
  const auto it = manifolds_.find(block);
  return it == manifolds_.end() ? nullptr : it->second;
}

void WindowProblem::Retire(int f) {
  FactorRecord& record = factors_[f];
  RemoveResidual(&record.residual, record.blocks, &problem_, &released_);
  record.retired = true;
  record.cost.reset();
}

void WindowProblem::ReplaceCost(int f,
                                std::unique_ptr<ceres::CostFunction> cost) {
  FactorRecord& record = factors_[f];
  SYMBA_CHECK(!record.retired && cost != nullptr)
      << "replacing a retired factor";
  RemoveResidual(&record.residual, record.blocks, &problem_, &released_);
  record.cost = std::move(cost);
}

void WindowProblem::MarkMarginalized(int f) {
  FactorRecord& record = factors_[f];
  RemoveResidual(&record.residual, record.blocks, &problem_, &released_);
  record.marginalized = true;
}

void WindowProblem::Forget(int f) {
  FactorRecord& record = factors_[f];
  SYMBA_CHECK(record.marginalized && record.residual == nullptr)
      << "forgetting a factor still in the window";
  record.cost.reset();
  std::vector<double*>().swap(record.blocks);
}

void WindowProblem::SetPrior(std::unique_ptr<MarginalPriorFactor> prior,
                             std::vector<double*> blocks) {
  RemoveResidual(&prior_residual_, prior_blocks_, &problem_, &released_);
  prior_ = std::move(prior);
  prior_blocks_ = prior_ ? std::move(blocks) : std::vector<double*>();
}

void WindowProblem::ReleaseUnusedBlocks() {
  std::vector<ceres::ResidualBlockId> users;
  for (double* block : released_) {
    if (!problem_.HasParameterBlock(block)) continue;
    problem_.GetResidualBlocksForParameterBlock(block, &users);
    if (users.empty()) problem_.RemoveParameterBlock(block);
  }
  released_.clear();
}

void WindowProblem::Sync(const std::vector<int>& active,
                         const SyncOptions& options) {
  ++sync_stamp_;
  std::vector<int> wanted;
  wanted.reserve(active.size());
  for (int f : active) {
    FactorRecord& record = factors_[f];
    if (record.retired || record.sync_stamp == sync_stamp_) continue;
    if (record.marginalized && !options.with_marginalized) continue;
    record.sync_stamp = sync_stamp_;
    wanted.push_back(f);
  }
  for (int f : in_problem_) {
    FactorRecord& record = factors_[f];
    if (record.sync_stamp != sync_stamp_) {
      RemoveResidual(&record.residual, record.blocks, &problem_, &released_);
    }
  }
  if (!options.with_prior)
    RemoveResidual(&prior_residual_, prior_blocks_, &problem_, &released_);
  ReleaseUnusedBlocks();
  for (int f : wanted) {
    FactorRecord& record = factors_[f];
    if (record.residual != nullptr) continue;
    SYMBA_CHECK(record.cost != nullptr) << "a forgotten factor in a solve";
    const std::vector<int32_t>& sizes = record.cost->parameter_block_sizes();
    for (size_t b = 0; b < record.blocks.size(); ++b) {
      EnsureBlock(manifolds_, record.blocks[b], sizes[b], &problem_);
    }
    record.residual =
        problem_.AddResidualBlock(record.cost.get(),
                                  const_cast<ceres::LossFunction*>(record.loss),
                                  record.blocks);
  }
  if (options.with_prior && prior_ && prior_residual_ == nullptr) {
    const std::vector<int32_t>& sizes = prior_->parameter_block_sizes();
    for (size_t b = 0; b < prior_blocks_.size(); ++b) {
      EnsureBlock(manifolds_, prior_blocks_[b], sizes[b], &problem_);
    }
    prior_residual_ =
        problem_.AddResidualBlock(prior_.get(), nullptr, prior_blocks_);
  }
  in_problem_ = std::move(wanted);
}

WindowProblem::Size WindowProblem::ProblemSize() const {
  Size size;
  size.residual_blocks = problem_.NumResidualBlocks();
  size.parameter_blocks = problem_.NumParameterBlocks();
  size.prior_size =
      prior_residual_ != nullptr ? static_cast<int>(prior_->A().cols()) : 0;
  return size;
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

bool WindowProblem::Covariances(
    const std::vector<std::vector<const double*>>& sets,
    std::vector<BlockCovariance>* covariances) {
  covariances->assign(sets.size(), BlockCovariance());
  std::vector<std::pair<const double*, const double*>> pairs;
  for (size_t s = 0; s < sets.size(); ++s) {
    std::vector<const double*>& held = (*covariances)[s].blocks;
    for (const double* block : sets[s]) {
      if (problem_.HasParameterBlock(block) &&
          !problem_.IsParameterBlockConstant(block)) {
        held.push_back(block);
      }
    }
    for (size_t a = 0; a < held.size(); ++a) {
      for (size_t b = a; b < held.size(); ++b) {
        pairs.emplace_back(held[a], held[b]);
      }
    }
  }
  if (pairs.empty()) return true;
  ceres::Covariance::Options options;
  options.num_threads = 1;
  ceres::Covariance covariance(options);
  if (!covariance.Compute(pairs, &problem_)) return false;
  for (BlockCovariance& set : *covariances) {
    if (set.blocks.empty()) continue;
    int size = 0;
    for (const double* b : set.blocks) {
      size += problem_.ParameterBlockTangentSize(b);
    }
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(
        size, size);
    if (!covariance.GetCovarianceMatrixInTangentSpace(set.blocks, c.data())) {
      return false;
    }
    set.covariance = c;
  }
  return true;
}

void WindowProblem::Solve(const ceres::Solver::Options& options,
                          ceres::Solver::Summary* summary) {
  ceres::Solve(options, &problem_, summary);
}

}  // namespace symba::internal
