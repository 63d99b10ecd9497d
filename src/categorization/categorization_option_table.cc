#include "symba/categorization/categorization_option_table.h"

#include "common/option_ranges.h"
#include "symba/geometry/angle.h"

namespace symba {
namespace {

OptionTable<CategorizationOptions> MakeCategorizationTable() {
  using O = CategorizationOptions;
  return {
      DoubleOption<O>("min_axis_angle",
                      &O::min_axis_angle,
                      "rad",
                      AngleBelowPi(),
                      "relative rotations larger than this vote for the axis"),
      DoubleOption<O>("axis_vote_angle",
                      &O::axis_vote_angle,
                      "rad",
                      AngleBelowPi(),
                      "two axis votes agree within this angle, up to sign"),
      DoubleOption<O>("swing_tolerance",
                      &O::swing_tolerance,
                      "rad",
                      AngleBelowPi(),
                      "a hypothesis is an axis inlier within this angle"),
      DoubleOption<O>("cluster_eps",
                      &O::cluster_eps,
                      "rad",
                      AngleBelowPi(),
                      "circular DBSCAN radius of the twist angles"),
      IntOption<O>("min_points",
                   &O::min_points,
                   AtLeast(1),
                   "DBSCAN core size, smallest mode and axis support"),
      BoolOption<O>("merge_close_clusters",
                    &O::merge_close_clusters,
                    "merge neighbouring clusters that one noisy mode split"),
      IntOption<O>("rescue_min_points",
                   &O::rescue_min_points,
                   AtLeast(0),
                   "discrete: groups of this many DBSCAN noise points become "
                   "clusters; 0 disables"),
      DoubleOption<O>("max_cluster_extent",
                      &O::max_cluster_extent,
                      "rad",
                      AngleBelowPi(),
                      "a cluster is compact when its arc is at most this"),
      DoubleOption<O>("min_cluster_separation",
                      &O::min_cluster_separation,
                      "rad",
                      AngleBelowPi(),
                      "discrete: least arc between neighbouring clusters"),
      DoubleOption<O>("separation_ratio",
                      &O::separation_ratio,
                      "",
                      NonNegative(),
                      "discrete: least arc between clusters over their mean "
                      "extent"),
      DoubleOption<O>("max_noise_fraction",
                      &O::max_noise_fraction,
                      "",
                      Fraction(),
                      "discrete: largest share of DBSCAN noise among the axis "
                      "inliers"),
      DoubleOption<O>("empty_gap_angle",
                      &O::empty_gap_angle,
                      "rad",
                      AngleBelowPi(),
                      "discrete: gaps between twists wider than this count as "
                      "empty"),
      DoubleOption<O>("min_empty_fraction",
                      &O::min_empty_fraction,
                      "",
                      Fraction(),
                      "discrete: least share of the circle in empty gaps"),
      DoubleOption<O>("asymmetric_inlier_angle",
                      &O::asymmetric_inlier_angle,
                      "rad",
                      AngleBelowPi(),
                      "asymmetric: inliers are within this angle of the mean "
                      "pose"),
      DoubleOption<O>("translation_gate",
                      &O::translation_gate,
                      "m",
                      PositiveOrInfinity(),
                      "inliers farther than this from the median translation "
                      "are dropped; inf disables"),
      DoubleOption<O>("prior_snap_angle",
                      &O::prior_snap_angle,
                      "rad",
                      AngleBelowPi(),
                      "a cluster angle snaps to a multiple of 2 pi / the "
                      "prior's order within this"),
      BoolOption<O>("read_one_mode_with_prior",
                    &O::read_one_mode_with_prior,
                    "one mode of a class with a symmetric prior takes the "
                    "prior's type"),
  };
}

}  // namespace

const OptionTable<CategorizationOptions>& CategorizationOptionTable() {
  static const OptionTable<CategorizationOptions> table =
      MakeCategorizationTable();
  return table;
}

}  // namespace symba
