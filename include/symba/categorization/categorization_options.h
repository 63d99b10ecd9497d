// CategorizationOptions: the thresholds of the categorisation
// (categorize.h explains the steps, docs/categorization.md the values). A
// header of its own, without Eigen or Ceres, so that option structs can
// hold it.
#ifndef SYMBA_CATEGORIZATION_CATEGORIZATION_OPTIONS_H_
#define SYMBA_CATEGORIZATION_CATEGORIZATION_OPTIONS_H_

#include "symba/common/status.h"
#include "symba/geometry/pi.h"

namespace symba {

// Thresholds of the categorization (docs/categorization.md says why each
// default is what it is). Angles in radians, lengths in metres. The defaults
// suit hypotheses with rotation noise up to about 6 degrees per axis.
struct CategorizationOptions {
  // Relative rotations larger than this vote for the axis (step 3).
  double min_axis_angle = 30.0 * kPi / 180.0;
  // Two votes agree when their directions are this close, up to sign.
  double axis_vote_angle = 20.0 * kPi / 180.0;
  // A hypothesis is an axis inlier when R_j axis_o is this close to axis_c.
  double swing_tolerance = 18.0 * kPi / 180.0;
  // Circular DBSCAN of the twist angles: radius and core size. min_points is
  // also the smallest mode that counts as a mode (and the smallest axis
  // support).
  double cluster_eps = 12.0 * kPi / 180.0;
  int min_points = 3;
  // Merge neighbouring DBSCAN clusters closer than min_cluster_separation
  // whose union stays within max_cluster_extent (one noisy mode that DBSCAN
  // split).
  bool merge_close_clusters = true;
  // For a discrete detection, groups of at least this many DBSCAN noise
  // points (within cluster_eps, compact and min_cluster_separation from
  // every cluster) become clusters too: small modes; 0 disables.
  int rescue_min_points = 2;
  // A cluster is compact when its arc is at most this.
  double max_cluster_extent = 45.0 * kPi / 180.0;
  // Discrete needs every arc between neighbouring clusters to be at least
  // this, and at most this fraction of the axis inliers to be DBSCAN noise.
  double min_cluster_separation = 20.0 * kPi / 180.0;
  // ... and at least this times the mean extent of the two clusters.
  double separation_ratio = 1.0;
  double max_noise_fraction = 0.2;
  // Discrete also needs at least this fraction of the circle to lie in gaps
  // wider than empty_gap_angle between consecutive twists.
  double empty_gap_angle = 20.0 * kPi / 180.0;
  double min_empty_fraction = 0.7;
  // Asymmetric: hypotheses within this rotation angle of the mean pose are
  // the inliers.
  double asymmetric_inlier_angle = 20.0 * kPi / 180.0;
  // Inliers whose translation is farther than this from the inliers'
  // coordinate-wise median are dropped (metres; infinity disables).
  double translation_gate = 0.2;
  // With a discrete class prior, a cluster angle snaps to the nearest
  // multiple of 2 pi / order when it is within this of it.
  double prior_snap_angle = 15.0 * kPi / 180.0;
  // Hypotheses showing one mode of a class whose prior is discrete or
  // continuous with a known axis take the prior's type (see the header
  // comment); off: one mode always reads as asymmetric.
  bool read_one_mode_with_prior = true;

  // OK, or which option is out of range and why.
  Status Validate() const;
};

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CATEGORIZATION_OPTIONS_H_
