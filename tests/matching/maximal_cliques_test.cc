#include "symba/matching/maximal_cliques.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace symba {
namespace {

AdjacencyMatrix Graph(int n, const std::vector<std::pair<int, int>>& edges) {
  AdjacencyMatrix adjacency(static_cast<std::size_t>(n),
                            std::vector<bool>(static_cast<std::size_t>(n)));
  for (const auto& [a, b] : edges) {
    adjacency[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] = true;
    adjacency[static_cast<std::size_t>(b)][static_cast<std::size_t>(a)] = true;
  }
  return adjacency;
}

std::vector<std::vector<int>> Sorted(std::vector<std::vector<int>> cliques) {
  std::sort(cliques.begin(), cliques.end());
  return cliques;
}

TEST(MaximalCliques, FindsEveryMaximalCliqueOfATwoTriangleGraph) {
  // Triangles {0,1,2} and {2,3,4} share vertex 2; 5 hangs off 4; 6 alone.
  const AdjacencyMatrix graph =
      Graph(7, {{0, 1}, {0, 2}, {1, 2}, {2, 3}, {2, 4}, {3, 4}, {4, 5}});
  const CliqueSearchResult all = MaximalCliques(graph, {1, 100});
  EXPECT_FALSE(all.truncated);
  EXPECT_EQ(Sorted(all.cliques),
            (std::vector<std::vector<int>>{{0, 1, 2}, {2, 3, 4}, {4, 5}, {6}}));
  const CliqueSearchResult large = MaximalCliques(graph, {3, 100});
  EXPECT_EQ(Sorted(large.cliques),
            (std::vector<std::vector<int>>{{0, 1, 2}, {2, 3, 4}}));
}

TEST(MaximalCliques, ACompleteGraphIsOneClique) {
  std::vector<std::pair<int, int>> edges;
  for (int a = 0; a < 6; ++a) {
    for (int b = a + 1; b < 6; ++b) edges.emplace_back(a, b);
  }
  const CliqueSearchResult result = MaximalCliques(Graph(6, edges), {2, 100});
  EXPECT_EQ(result.cliques,
            (std::vector<std::vector<int>>{{0, 1, 2, 3, 4, 5}}));
}

TEST(MaximalCliques, StopsAtMaxCliquesAndSaysSo) {
  // A perfect matching of 10 edges has 10 maximal cliques.
  std::vector<std::pair<int, int>> edges;
  for (int a = 0; a < 20; a += 2) edges.emplace_back(a, a + 1);
  const CliqueSearchResult result = MaximalCliques(Graph(20, edges), {2, 4});
  EXPECT_TRUE(result.truncated);
  EXPECT_EQ(result.cliques.size(), 4u);
}

TEST(MaximalCliques, AnEmptyGraphHasNone) {
  EXPECT_TRUE(MaximalCliques({}, {1, 10}).cliques.empty());
}

}  // namespace
}  // namespace symba
