// FactorGraph: keyframes leaving the window (docs/backend.md "The
// window"). Under marginalize, a leaving keyframe's factors are linearised
// into priors (marginalization.h): its motion factors into the keyframe
// prior (given its pose under the conditional chain prior; with its pose
// eliminated by the Schur complement, together with the current prior,
// under the marginal one), its object edges and point observations into
// each object's and point's own prior, given its pose. Under drop its
// factors just leave. Every step here touches the leaving keyframe's
// factors and the priors only.
#include <algorithm>
#include <utility>

#include "backend/factor_graph.h"
#include "symba/common/check.h"

namespace symba::internal {
namespace {

std::vector<double*> ObjectBlocks(ObjectState& object) {
  std::vector<double*> blocks = {object.q, object.t, object.a_w};
  for (const auto& theta : object.thetas) blocks.push_back(theta.get());
  return blocks;
}

}  // namespace

void FactorGraph::LeaveWindow(int k) {
  KeyframeState& kf = *keyframes_[k];
  const bool marginalize = options_.window_policy == WindowPolicy::kMarginalize;
  // Under a marginal chain prior a point observation informs both the
  // keyframe's pose (given the point) and the point (given the pose): it
  // enters each with half its information, so that it is counted once.
  // Under a conditional one the pose is final and the point gets it all.
  const bool marginal_chain = options_.chain_prior == ChainPrior::kMarginal;
  const double point_share = marginal_chain ? 0.5 : 1.0;
  std::vector<MarginalizationTerm> terms;
  // Keyframes that left before k and still appear in its factors (a motion
  // factor across a gap in the front end's poses) are constant.
  std::vector<const double*> constant;
  std::vector<int> leaving;
  std::vector<std::pair<int, int>> point_factors;   // (point, factor)
  std::vector<std::pair<int, int>> object_factors;  // (object, factor)
  for (int f : kf.factors) {
    const FactorRecord& record = problem_.factor(f);
    if (record.retired || record.marginalized) continue;
    leaving.push_back(f);
    if (!marginalize || !InMap(record, objects_)) continue;
    if (record.point >= 0) {
      point_factors.emplace_back(record.point, f);
      if (marginal_chain) {
        terms.push_back(
            {record.cost.get(), record.loss, record.blocks, point_share});
        constant.push_back(points_[record.point]->p);
      }
      continue;
    }
    if (record.object >= 0) {
      object_factors.emplace_back(record.object, f);
      continue;
    }
    terms.push_back({record.cost.get(), record.loss, record.blocks});
    for (int other : {record.keyframe, record.keyframe2}) {
      if (other >= 0 && other < k) {
        constant.push_back(keyframes_[other]->q);
        constant.push_back(keyframes_[other]->t);
      }
    }
  }
  ++statistics_->marginalized_keyframes;
  if (!marginalize) {
    for (int f : leaving) problem_.MarkMarginalized(f);
    ForgetLeftKeyframe(k, leaving);
    return;
  }
  std::sort(point_factors.begin(), point_factors.end());
  for (size_t i = 0; i < point_factors.size();) {
    size_t end = i;
    std::vector<int> factors;
    while (end < point_factors.size() &&
           point_factors[end].first == point_factors[i].first) {
      factors.push_back(point_factors[end++].second);
    }
    PointState& point = *points_[point_factors[i].first];
    MergeIntoOwnPrior(factors,
                      {point.p},
                      point_share,
                      -1,
                      point_factors[i].first,
                      &point.prior_factor);
    i = end;
  }
  std::sort(object_factors.begin(), object_factors.end());
  for (size_t i = 0; i < object_factors.size();) {
    size_t end = i;
    std::vector<int> factors;
    while (end < object_factors.size() &&
           object_factors[end].first == object_factors[i].first) {
      factors.push_back(object_factors[end++].second);
    }
    ObjectState& object = *objects_[object_factors[i].first];
    MergeIntoOwnPrior(factors,
                      ObjectBlocks(object),
                      1.0,
                      object_factors[i].first,
                      -1,
                      &object.prior_factor);
    i = end;
  }
  for (int f : leaving) problem_.MarkMarginalized(f);
  if (problem_.prior() != nullptr) {
    terms.push_back({problem_.prior(), nullptr, problem_.prior_blocks()});
  }
  // The first keyframe is the gauge: constant, not eliminated. A
  // conditional chain holds the leaving keyframe at its estimate too.
  const BlockRole own_role =
      k == 0 || !marginal_chain ? BlockRole::kConstant : BlockRole::kEliminate;
  auto describe = [&](const double* block) {
    BlockDescription description{BlockRole::kKeep, problem_.ManifoldOf(block)};
    if (block == kf.q || block == kf.t) {
      description.role = own_role;
    } else if (std::find(constant.begin(), constant.end(), block) !=
               constant.end()) {
      description.role = BlockRole::kConstant;
    }
    return description;
  };
  MarginalizationResult result;
  const Status status = Marginalize(terms, describe, marginalization_, &result);
  // Every block in the problem has a manifold the prior expresses.
  SYMBA_CHECK(status.ok()) << status.message();
  statistics_->ambiguous_edges_dropped += result.ambiguous;
  problem_.SetPrior(std::move(result.prior), std::move(result.blocks));
  ForgetLeftKeyframe(k, leaving);
}

void FactorGraph::ForgetLeftKeyframe(int k, const std::vector<int>& left) {
  // Nothing reads a keyframe's factor list once it left the window.
  std::vector<int>().swap(keyframes_[k]->factors);
  if (options_.keep_history) return;
  for (int f : left) {
    const FactorRecord& record = problem_.factor(f);
    if (record.object >= 0 && record.observation >= 0) {
      ObjectObservation& observation =
          objects_[record.object]->observations[record.observation];
      std::vector<PoseComponent>().swap(observation.components);
    }
    problem_.Forget(f);
  }
}

void FactorGraph::MergeIntoOwnPrior(const std::vector<int>& factors,
                                    const std::vector<double*>& own,
                                    double share,
                                    int object,
                                    int point,
                                    int* prior_factor) {
  std::vector<MarginalizationTerm> terms;
  for (int f : factors) {
    const FactorRecord& record = problem_.factor(f);
    terms.push_back({record.cost.get(), record.loss, record.blocks, share});
  }
  if (*prior_factor >= 0) {
    const FactorRecord& prior = problem_.factor(*prior_factor);
    terms.push_back({prior.cost.get(), nullptr, prior.blocks});
  }
  // The keyframe's pose is final: the observation is conditioned on it.
  auto describe = [&](const double* block) {
    BlockDescription description{BlockRole::kKeep, problem_.ManifoldOf(block)};
    if (std::find(own.begin(), own.end(), block) == own.end()) {
      description.role = BlockRole::kConstant;
    }
    return description;
  };
  ReplaceOwnPrior(terms, describe, object, point, prior_factor);
}

void FactorGraph::ReplaceOwnPrior(const std::vector<MarginalizationTerm>& terms,
                                  const BlockDescriber& describe,
                                  int object,
                                  int point,
                                  int* prior_factor) {
  MarginalizationResult result;
  const Status status = Marginalize(terms, describe, marginalization_, &result);
  // Every block in the problem has a manifold the prior expresses.
  SYMBA_CHECK(status.ok()) << status.message();
  statistics_->ambiguous_edges_dropped += result.ambiguous;
  // The old prior (one of the terms) is used up only now.
  if (*prior_factor >= 0) problem_.Retire(*prior_factor);
  *prior_factor = -1;
  if (result.prior == nullptr) return;
  FactorRecord record;
  record.cost = std::move(result.prior);
  record.blocks = std::move(result.blocks);
  record.object = object;
  record.point = point;
  record.summary = true;
  *prior_factor = problem_.Add(std::move(record));
}

void FactorGraph::RemoveFromObjectPrior(int o,
                                        const std::vector<double*>& blocks) {
  ObjectState& object = *objects_[o];
  if (object.prior_factor < 0) return;
  const FactorRecord& prior = problem_.factor(object.prior_factor);
  const bool touched =
      std::any_of(blocks.begin(), blocks.end(), [&](const double* b) {
        return std::find(prior.blocks.begin(), prior.blocks.end(), b) !=
               prior.blocks.end();
      });
  if (!touched) return;
  // Eliminate `blocks` (their information on the rest stays).
  auto describe = [&](const double* block) {
    BlockDescription description{BlockRole::kKeep, problem_.ManifoldOf(block)};
    if (std::find(blocks.begin(), blocks.end(), block) != blocks.end()) {
      description.role = BlockRole::kEliminate;
    }
    return description;
  };
  ReplaceOwnPrior({{prior.cost.get(), nullptr, prior.blocks}},
                  describe,
                  o,
                  -1,
                  &object.prior_factor);
}

}  // namespace symba::internal
