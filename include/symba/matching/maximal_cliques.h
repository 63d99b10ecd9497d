// Maximal cliques of an undirected graph (Bron-Kerbosch with pivoting):
// the sets of mutually consistent candidates that pairwise consistency
// maximisation picks from (docs/relocalization.md).
#ifndef SYMBA_MATCHING_MAXIMAL_CLIQUES_H_
#define SYMBA_MATCHING_MAXIMAL_CLIQUES_H_

#include <vector>

namespace symba {

// adjacency[i][j] == adjacency[j][i]: vertices i and j are consistent
// (the diagonal is ignored).
using AdjacencyMatrix = std::vector<std::vector<bool>>;

struct CliqueSearch {
  // Every maximal clique with at least this many vertices...
  int min_size = 1;
  // ...up to this many cliques (the search stops there and says so).
  int max_cliques = 10000;
};

struct CliqueSearchResult {
  // Each sorted ascending; the cliques in the order found.
  std::vector<std::vector<int>> cliques;
  bool truncated = false;  // max_cliques reached: others may exist
};

CliqueSearchResult MaximalCliques(const AdjacencyMatrix& adjacency,
                                  const CliqueSearch& search);

}  // namespace symba

#endif  // SYMBA_MATCHING_MAXIMAL_CLIQUES_H_
