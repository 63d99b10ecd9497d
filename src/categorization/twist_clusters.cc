#include "categorization/twist_clusters.h"

#include "categorization/circle_arc.h"
#include "symba/common/check.h"

namespace symba {
namespace categorization {
namespace {

// The live cluster after `c` counter-clockwise, and the arc from c's end to
// its start; -1 if c is the only live one.
int NextLiveCluster(const std::vector<CircularCluster>& clusters,
                    const std::vector<char>& alive,
                    int c,
                    double* gap) {
  const double end = clusters[c].start + clusters[c].extent;
  int next = -1;
  *gap = kTwoPi;
  for (int d = 0; d < static_cast<int>(clusters.size()); ++d) {
    if (d == c || !alive[d]) continue;
    const double arc = ForwardArc(end, clusters[d].start);
    if (arc < *gap) {
      *gap = arc;
      next = d;
    }
  }
  return next;
}

// The live pair (from, to = the next after from) with the smallest gap below
// min_cluster_separation whose union stays compact; false if there is none.
bool ClosestMergeablePair(const CategorizationOptions& options,
                          const std::vector<CircularCluster>& clusters,
                          const std::vector<char>& alive,
                          int* from,
                          int* to) {
  bool found = false;
  double best_gap = options.min_cluster_separation;
  for (int c = 0; c < static_cast<int>(clusters.size()); ++c) {
    if (!alive[c]) continue;
    double gap = 0.0;
    const int next = NextLiveCluster(clusters, alive, c, &gap);
    if (next < 0 || gap >= best_gap) continue;
    const double union_extent = ForwardArc(
        clusters[c].start, clusters[next].start + clusters[next].extent);
    if (union_extent <= options.max_cluster_extent) {
      best_gap = gap;
      *from = c;
      *to = next;
      found = true;
    }
  }
  return found;
}

// True when `candidate` is at least min_separation from `cluster` on both
// sides and their arcs do not overlap.
bool FarApart(const CircularCluster& cluster,
              const CircularCluster& candidate,
              double min_separation) {
  const double after =
      ForwardArc(cluster.start + cluster.extent, candidate.start);
  const double before =
      ForwardArc(candidate.start + candidate.extent, cluster.start);
  return after >= min_separation && before >= min_separation &&
         after + before + cluster.extent + candidate.extent <
             kTwoPi + 1e-9;  // the arcs do not overlap
}

// Circular DBSCAN of finite angles with validated options (eps in (0, pi),
// min_points >= 1), which it cannot refuse.
CircularDbscanResult Dbscan(const std::vector<double>& angles,
                            double eps,
                            int min_points) {
  CircularDbscanOptions options;
  options.eps = eps;
  options.min_points = min_points;
  CircularDbscanResult result;
  const Status status = CircularDbscan(angles, options, &result);
  SYMBA_CHECK(status.ok()) << status.message();
  return result;
}

}  // namespace

CircularDbscanResult ClusterTwists(const std::vector<double>& twists,
                                   const CategorizationOptions& options) {
  return Dbscan(twists, options.cluster_eps, options.min_points);
}

void MergeCloseClusters(const CategorizationOptions& options,
                        CircularDbscanResult* result) {
  std::vector<CircularCluster>& clusters = result->clusters;
  const int num_raw = static_cast<int>(clusters.size());
  if (num_raw < 2 || clusters[0].ring) return;
  std::vector<int> merged_into(num_raw);
  for (int c = 0; c < num_raw; ++c) merged_into[c] = c;
  std::vector<char> alive(num_raw, 1);
  int from = -1;
  int to = -1;
  while (ClosestMergeablePair(options, clusters, alive, &from, &to)) {
    CircularCluster& a = clusters[from];
    const CircularCluster& b = clusters[to];
    a.extent = ForwardArc(a.start, b.start + b.extent);
    a.size += b.size;
    alive[to] = 0;
    for (int c = 0; c < num_raw; ++c) {
      if (merged_into[c] == to) merged_into[c] = from;
    }
  }
  // Renumber the survivors 0..M-1 in their original order.
  std::vector<int> new_label(num_raw, -1);
  int num_alive = 0;
  for (int c = 0; c < num_raw; ++c) {
    if (alive[c]) {
      new_label[c] = num_alive;
      clusters[num_alive++] = clusters[c];
    }
  }
  if (num_alive == num_raw) return;
  clusters.resize(num_alive);
  for (int& label : result->labels) {
    if (label != CircularDbscanResult::kNoiseLabel) {
      label = new_label[merged_into[label]];
    }
  }
}

void RescueSmallModes(const std::vector<double>& twists,
                      const CategorizationOptions& options,
                      CircularDbscanResult* result) {
  std::vector<double> noise_angles;
  std::vector<int> noise_index;  // position in twists
  for (int i = 0; i < static_cast<int>(result->labels.size()); ++i) {
    if (result->labels[i] == CircularDbscanResult::kNoiseLabel) {
      noise_angles.push_back(twists[i]);
      noise_index.push_back(i);
    }
  }
  // The caller runs this only with rescue_min_points > 0.
  const CircularDbscanResult rescue =
      Dbscan(noise_angles, options.cluster_eps, options.rescue_min_points);
  const int num_existing = static_cast<int>(result->clusters.size());
  for (int r = 0; r < static_cast<int>(rescue.clusters.size()); ++r) {
    const CircularCluster& candidate = rescue.clusters[r];
    if (candidate.ring || candidate.extent > options.max_cluster_extent) {
      continue;
    }
    bool apart = true;
    for (int c = 0; c < num_existing && apart; ++c) {
      apart = FarApart(
          result->clusters[c], candidate, options.min_cluster_separation);
    }
    if (!apart) continue;
    const int label = static_cast<int>(result->clusters.size());
    result->clusters.push_back(candidate);
    for (int k = 0; k < static_cast<int>(rescue.labels.size()); ++k) {
      if (rescue.labels[k] == r) {
        result->labels[noise_index[k]] = label;
        --result->num_noise;
      }
    }
  }
}

}  // namespace categorization
}  // namespace symba
