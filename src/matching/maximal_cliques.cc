#include "symba/matching/maximal_cliques.h"

#include <algorithm>
#include <cstddef>

namespace symba {
namespace {

class BronKerbosch {
 public:
  BronKerbosch(const AdjacencyMatrix& adjacency,
               const CliqueSearch& search,
               CliqueSearchResult* result)
      : adjacency_(adjacency), search_(search), result_(result) {}

  // R: the clique so far; P: vertices that extend it; X: vertices that
  // would extend it but were already explored (so R + X is not maximal).
  void Expand(std::vector<int>& clique,
              std::vector<int> candidates,
              std::vector<int> excluded) {
    if (result_->truncated) return;
    if (static_cast<int>(clique.size() + candidates.size()) <
        search_.min_size) {
      return;
    }
    if (candidates.empty()) {
      if (excluded.empty()) Report(clique);
      return;
    }
    const int pivot = ChoosePivot(candidates, excluded);
    std::vector<int> branch;
    for (int v : candidates) {
      if (!Adjacent(pivot, v)) branch.push_back(v);
    }
    for (int v : branch) {
      clique.push_back(v);
      Expand(clique, Neighbours(v, candidates), Neighbours(v, excluded));
      clique.pop_back();
      candidates.erase(std::find(candidates.begin(), candidates.end(), v));
      excluded.push_back(v);
      if (result_->truncated) return;
    }
  }

 private:
  bool Adjacent(int a, int b) const {
    return a != b &&
           adjacency_[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
  }

  std::vector<int> Neighbours(int v, const std::vector<int>& set) const {
    std::vector<int> out;
    for (int u : set) {
      if (Adjacent(v, u)) out.push_back(u);
    }
    return out;
  }

  // The vertex of P or X with the most neighbours in P: only P's vertices
  // not adjacent to it need a branch of their own.
  int ChoosePivot(const std::vector<int>& candidates,
                  const std::vector<int>& excluded) const {
    int best = candidates.front();
    int best_count = -1;
    for (const std::vector<int>* set : {&candidates, &excluded}) {
      for (int u : *set) {
        const int count = static_cast<int>(Neighbours(u, candidates).size());
        if (count > best_count) {
          best = u;
          best_count = count;
        }
      }
    }
    return best;
  }

  void Report(const std::vector<int>& clique) {
    if (static_cast<int>(result_->cliques.size()) >= search_.max_cliques) {
      result_->truncated = true;
      return;
    }
    std::vector<int> sorted = clique;
    std::sort(sorted.begin(), sorted.end());
    result_->cliques.push_back(std::move(sorted));
  }

  const AdjacencyMatrix& adjacency_;
  const CliqueSearch& search_;
  CliqueSearchResult* result_;
};

}  // namespace

CliqueSearchResult MaximalCliques(const AdjacencyMatrix& adjacency,
                                  const CliqueSearch& search) {
  CliqueSearchResult result;
  std::vector<int> all(adjacency.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  std::vector<int> clique;
  BronKerbosch(adjacency, search, &result).Expand(clique, all, {});
  return result;
}

}  // namespace symba
