// Step 6 of the categorization and its rescue of small modes (7b)
// (docs/categorization.md): the modes of the twist angles on the circle.
#ifndef SYMBA_CATEGORIZATION_TWIST_CLUSTERS_H_
#define SYMBA_CATEGORIZATION_TWIST_CLUSTERS_H_

#include <vector>

#include "symba/categorization/categorize.h"
#include "symba/categorization/circular_dbscan.h"

namespace symba {
namespace categorization {

// Circular DBSCAN of `twists` with radius cluster_eps and core size
// min_points (valid options: it cannot fail on finite twists).
CircularDbscanResult ClusterTwists(const std::vector<double>& twists,
                                   const CategorizationOptions& options);

// Neighbouring clusters closer than min_cluster_separation whose union spans
// at most max_cluster_extent are one mode that a gap above eps split: they
// are merged, closest pair first. The survivors keep their order and are
// renumbered 0..M-1 (labels too); start, extent and size are kept up to
// date, mean is not. A ring is left alone.
void MergeCloseClusters(const CategorizationOptions& options,
                        CircularDbscanResult* clusters);

// Discrete only: DBSCAN of the noise points of `clusters` with core size
// rescue_min_points (> 0); each group that is compact (not a ring, extent
// <= max_cluster_extent) and at least min_cluster_separation from every
// existing cluster on both sides becomes a cluster, appended; its points
// leave the noise.
void RescueSmallModes(const std::vector<double>& twists,
                      const CategorizationOptions& options,
                      CircularDbscanResult* clusters);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_TWIST_CLUSTERS_H_
