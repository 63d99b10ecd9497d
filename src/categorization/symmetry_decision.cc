#include "categorization/symmetry_decision.h"

#include <algorithm>

#include "categorization/circle_arc.h"

namespace symba {
namespace categorization {
namespace {

// The cluster after `c` counter-clockwise and the arc from c's end to its
// start (2 pi and c itself if c is alone).
int NextCluster(const std::vector<CircularCluster>& clusters,
                int c,
                double* gap) {
  const double end = clusters[c].start + clusters[c].extent;
  *gap = kTwoPi;
  int next = c;
  for (int d = 0; d < static_cast<int>(clusters.size()); ++d) {
    if (d == c) continue;
    const double arc = ForwardArc(end, clusters[d].start);
    if (arc < *gap) {
      *gap = arc;
      next = d;
    }
  }
  return next;
}

}  // namespace

int LabelOf(const SignedTwists& twists,
            const CircularDbscanResult& clusters,
            int r) {
  int label = CircularDbscanResult::kNoiseLabel;
  for (int i = 0; i < static_cast<int>(twists.inlier_owner.size()); ++i) {
    if (twists.inlier_owner[i] == r) label = clusters.labels[i];
  }
  return label;
}

int NextReference(const SignedTwists& twists,
                  const CircularDbscanResult& clusters,
                  const std::vector<double>& weights) {
  const int num_clusters = static_cast<int>(clusters.clusters.size());
  int largest = 0;
  for (int c = 1; c < num_clusters; ++c) {
    if (clusters.clusters[c].size > clusters.clusters[largest].size) {
      largest = c;
    }
  }
  int next = -1;
  for (int i = 0; i < static_cast<int>(twists.inlier_owner.size()); ++i) {
    const int j = twists.inlier_owner[i];
    if (clusters.labels[i] == largest &&
        (next < 0 || weights[j] > weights[next] ||
         (weights[j] == weights[next] && j < next))) {
      next = j;
    }
  }
  return next;
}

ClusterShape MeasureClusters(const CategorizationOptions& options,
                             const CircularDbscanResult& clusters) {
  const std::vector<CircularCluster>& all = clusters.clusters;
  ClusterShape shape;
  for (const CircularCluster& c : all) {
    shape.max_extent = std::max(shape.max_extent, c.ring ? kTwoPi : c.extent);
    shape.all_compact =
        shape.all_compact && !c.ring && c.extent <= options.max_cluster_extent;
  }
  if (all.size() < 2 || !shape.all_compact) return shape;
  shape.min_separation = kTwoPi;
  shape.separated = true;
  for (int c = 0; c < static_cast<int>(all.size()); ++c) {
    double gap = 0.0;
    const int next = NextCluster(all, c, &gap);
    shape.min_separation = std::min(shape.min_separation, gap);
    const double mean_extent = 0.5 * (all[c].extent + all[next].extent);
    shape.separated = shape.separated &&
                      gap >= options.min_cluster_separation &&
                      gap >= options.separation_ratio * mean_extent;
  }
  return shape;
}

double EmptyFraction(const std::vector<double>& twists,
                     const std::vector<int>& sorted_order,
                     double empty_gap_angle) {
  const int n = static_cast<int>(twists.size());
  double empty = 0.0;
  for (int k = 0; k < n; ++k) {
    const double from = twists[sorted_order[k]];
    const double to = twists[sorted_order[(k + 1) % n]];
    const double gap = n == 1 ? kTwoPi : ForwardArc(from, to);
    if (gap > empty_gap_angle) empty += gap;
  }
  return empty / kTwoPi;
}

SymmetryType DecideSymmetryType(const ClusterEvidence& evidence,
                                const CategorizationOptions& options) {
  const bool few_noise =
      evidence.num_noise <= options.max_noise_fraction * evidence.num_twists;
  const bool compact = evidence.shape.all_compact && few_noise;
  if (evidence.num_clusters == 1 && compact) return SymmetryType::kAsymmetric;
  if (evidence.num_clusters >= 2 && compact && evidence.shape.separated &&
      evidence.empty_fraction >= options.min_empty_fraction) {
    return SymmetryType::kDiscrete;
  }
  return SymmetryType::kContinuous;
}

}  // namespace categorization
}  // namespace symba
