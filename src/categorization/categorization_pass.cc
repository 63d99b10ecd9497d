#include "categorization/categorization_pass.h"

#include "categorization/symmetry_decision.h"
#include "categorization/twist_clusters.h"

namespace symba {
namespace categorization {
namespace {

// The reference is DBSCAN noise. Without any cluster, axis inliers too
// sparse for DBSCAN are spread around the axis: continuous. Otherwise the
// reference is an outlier: asymmetric, or a retry from the largest cluster.
void DecideWithoutReference(const HypothesisSet& set,
                            const CategorizationOptions& options,
                            bool may_retry,
                            Pass* pass) {
  const int num_clusters = static_cast<int>(pass->clusters.clusters.size());
  const int num_twists = static_cast<int>(pass->twists.inlier_psi.size());
  pass->type = num_clusters == 0 && num_twists >= options.min_points
                   ? SymmetryType::kContinuous
                   : SymmetryType::kAsymmetric;
  if (may_retry && num_clusters > 0) {
    pass->retry = true;
    pass->next_reference = NextReference(pass->twists, pass->clusters, set.w);
  }
}

// The reference is in a cluster: decide from the clusters' shape, then
// (discrete) rescue small modes from the noise.
void DecideFromClusters(const CategorizationOptions& options, Pass* pass) {
  ClusterEvidence evidence;
  evidence.num_clusters = static_cast<int>(pass->clusters.clusters.size());
  evidence.num_noise = pass->clusters.num_noise;
  evidence.num_twists = static_cast<int>(pass->twists.inlier_psi.size());
  evidence.shape = MeasureClusters(options, pass->clusters);
  evidence.empty_fraction = EmptyFraction(
      pass->twists.inlier_psi, pass->clusters.order, options.empty_gap_angle);
  pass->diagnostics.max_cluster_extent = evidence.shape.max_extent;
  pass->diagnostics.min_cluster_separation = evidence.shape.min_separation;
  pass->diagnostics.empty_fraction = evidence.empty_fraction;
  pass->type = DecideSymmetryType(evidence, options);
  if (pass->type == SymmetryType::kDiscrete && options.rescue_min_points > 0 &&
      pass->clusters.num_noise > 0) {
    RescueSmallModes(pass->twists.inlier_psi, options, &pass->clusters);
    if (options.merge_close_clusters) {
      MergeCloseClusters(options, &pass->clusters);
    }
  }
}

}  // namespace

Pass RunPass(const HypothesisSet& set,
             const CategorizationOptions& options,
             const std::optional<Eigen::Vector3d>& prior_axis,
             int r,
             bool may_retry) {
  Pass pass;
  CategorizationDiagnostics& diagnostics = pass.diagnostics;
  const RelativeRotations rotations =
      RelativeRotationsTo(set, r, options.min_axis_angle);
  const AxisVote vote =
      VoteAxis(rotations, set.w, options.axis_vote_angle, prior_axis);
  diagnostics.prior_axis_used = prior_axis.has_value();
  diagnostics.axis_support = vote.support_weight;
  if (vote.support < options.min_points) {
    pass.type = SymmetryType::kAsymmetric;  // no second mode
    return pass;
  }

  pass.axis = FitAxisToInliers(
      set, rotations, r, vote.guess, prior_axis.has_value(), options);
  diagnostics.num_axis_inliers = pass.axis.num_inliers;
  pass.twists = TwistsAboutAxis(
      set, r, pass.axis.axis_o, pass.axis.axis_c, pass.axis.inlier);

  pass.clusters = ClusterTwists(pass.twists.inlier_psi, options);
  diagnostics.num_raw_clusters =
      static_cast<int>(pass.clusters.clusters.size());
  if (options.merge_close_clusters) {
    MergeCloseClusters(options, &pass.clusters);
  }
  diagnostics.num_noise = pass.clusters.num_noise;

  if (LabelOf(pass.twists, pass.clusters, r) ==
      CircularDbscanResult::kNoiseLabel) {
    DecideWithoutReference(set, options, may_retry, &pass);
  } else {
    DecideFromClusters(options, &pass);
  }
  return pass;
}

}  // namespace categorization
}  // namespace symba
