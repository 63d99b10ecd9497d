// Step 7 of the categorization (docs/categorization.md): whether the
// reference is confirmed, and the symmetry type the twist clusters show.
#ifndef SYMBA_CATEGORIZATION_SYMMETRY_DECISION_H_
#define SYMBA_CATEGORIZATION_SYMMETRY_DECISION_H_

#include <vector>

#include "categorization/signed_twists.h"
#include "symba/categorization/categorize.h"
#include "symba/categorization/circular_dbscan.h"

namespace symba {
namespace categorization {

// The cluster label of hypothesis r (kNoiseLabel if it is DBSCAN noise or
// not an axis inlier).
int LabelOf(const SignedTwists& twists,
            const CircularDbscanResult& clusters,
            int r);

// The reference for a second pass when r is noise: the highest-weight member
// of the largest cluster (ties: the lower cluster index, then the lower
// hypothesis index). Needs at least one cluster.
int NextReference(const SignedTwists& twists,
                  const CircularDbscanResult& clusters,
                  const std::vector<double>& weights);

// The shape of the clusters the decision reads.
struct ClusterShape {
  double max_extent = 0.0;      // 2 pi for a ring
  bool all_compact = true;      // no ring, every extent <= max_cluster_extent
  double min_separation = 0.0;  // smallest gap; 0 unless >= 2 compact clusters
  // Every gap g from a cluster's end to the next cluster's start satisfies
  // g >= min_cluster_separation and g >= separation_ratio * (mean extent of
  // the two); false unless >= 2 compact clusters.
  bool separated = false;
};
ClusterShape MeasureClusters(const CategorizationOptions& options,
                             const CircularDbscanResult& clusters);

// E = (1 / 2 pi) * the sum of the gaps wider than empty_gap_angle between
// consecutive sorted twists (`sorted_order` indexes `twists` in ascending
// order; one twist leaves a gap of 2 pi).
double EmptyFraction(const std::vector<double>& twists,
                     const std::vector<int>& sorted_order,
                     double empty_gap_angle);

// What the decision reads of a pass whose reference is in a cluster.
struct ClusterEvidence {
  int num_clusters = 0;
  int num_noise = 0;   // DBSCAN noise among the axis inliers
  int num_twists = 0;  // the axis inliers
  ClusterShape shape;
  double empty_fraction = 0.0;
};
// Asymmetric: one compact cluster and noise <= max_noise_fraction of the
// twists. Discrete: >= 2 compact, separated clusters, little noise and
// E >= min_empty_fraction. Otherwise continuous.
SymmetryType DecideSymmetryType(const ClusterEvidence& evidence,
                                const CategorizationOptions& options);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_SYMMETRY_DECISION_H_
