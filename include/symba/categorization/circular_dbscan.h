// DBSCAN (Ester et al., KDD 1996) for angles on the unit circle.
//
// Distance: d(a, b) = |WrapToPi(a - b)| in [0, pi] (geodesic on the circle).
// With eps in (0, pi) and min_points >= 1:
//   N(p)      = { q : d(p, q) <= eps }            (p itself included)
//   core      p is a core point if |N(p)| >= min_points
//   cluster   a maximal set of core points linked by hops d <= eps between
//             core points, plus its border points
//   border    a non-core point within eps of a core point; it joins the
//             cluster of its nearest core point (ties: the core point met
//             first counter-clockwise, i.e. the one just before it)
//   noise     every other point (label kNoiseLabel)
//
// On the circle this needs no spatial index. After sorting the angles, two
// core points are density-connected exactly when every gap between
// consecutive core points on one of the two arcs joining them is <= eps, so a
// cluster is a run of consecutive core points in sorted order, cut wherever
// two neighbouring core points are more than eps apart. Neighbour counts come
// from binary searches in the sorted, once-unrolled sequence. Cost
// O(N log N); the clusters are contiguous runs of the sorted angles (a point
// between two core points of one cluster is within eps of one of them).
//
// Output per cluster (angles in radians):
//   start   angle of the first member counter-clockwise, in (-pi, pi]
//   extent  arc from the first to the last member counter-clockwise, in
//           [0, 2 pi); for a ring (the core points close the circle with no
//           gap above eps) the arc outside the ring's largest gap
//   mean    start + mean of the members' counter-clockwise offsets from
//           start, wrapped (the arithmetic mean along the arc; for a ring it
//           has no geometric meaning)
// Clusters are numbered in increasing order of their first core point's
// angle in (-pi, pi] (a border point before it may make `start` wrap to
// near +pi); a ring is always the only cluster.
#ifndef SYMBA_CATEGORIZATION_CIRCULAR_DBSCAN_H_
#define SYMBA_CATEGORIZATION_CIRCULAR_DBSCAN_H_

#include <vector>

#include "symba/common/status.h"

namespace symba {

struct CircularDbscanOptions {
  double eps = 0.2;    // neighbourhood radius, rad, in (0, pi)
  int min_points = 3;  // |N(p)| needed for a core point, >= 1

  Status Validate() const;
};

struct CircularCluster {
  double start = 0.0;   // rad, (-pi, pi]
  double extent = 0.0;  // rad, [0, 2 pi)
  double mean = 0.0;    // rad, (-pi, pi]
  int size = 0;         // number of members (core and border)
  bool ring = false;    // the core points close the circle
};

struct CircularDbscanResult {
  static constexpr int kNoiseLabel = -1;

  // Per input angle: its cluster index, or kNoiseLabel.
  std::vector<int> labels;
  std::vector<CircularCluster> clusters;
  // Input indices sorted by wrapped angle, ascending (ties: lower index).
  std::vector<int> order;
  int num_noise = 0;
};

// Clusters `angles` (radians, any finite value; they are wrapped). Returns an
// error for invalid options or a non-finite angle, leaving `result` empty.
// `result`'s vectors are reused, so a caller that keeps one result across
// calls does not allocate once they have grown.
Status CircularDbscan(const std::vector<double>& angles,
                      const CircularDbscanOptions& options,
                      CircularDbscanResult* result);

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CIRCULAR_DBSCAN_H_
