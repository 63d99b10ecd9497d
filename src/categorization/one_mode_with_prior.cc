#include "categorization/one_mode_with_prior.h"

#include <cmath>

#include <Eigen/Geometry>

#include "symba/geometry/angle.h"
#include "symba/geometry/swing_twist.h"

namespace symba {
namespace categorization {

bool ReadsOneModeWithPrior(const CategorizationOptions& options,
                           const ClassPrior* prior) {
  return options.read_one_mode_with_prior && prior != nullptr &&
         prior->symmetry != SymmetryType::kAsymmetric &&
         prior->axis_o.norm() > 0.0;
}

void ReadOneModeWithPrior(const ClassPrior& prior,
                          const HypothesisSet& set,
                          CategorizedDetection* out) {
  const Eigen::Vector3d a_o = prior.axis_o.normalized();
  const Eigen::Quaterniond& q_base = out->T_co_base.q;
  out->axis_o = a_o;
  out->axis_c = q_base * a_o;
  for (int j = 0; j < set.size(); ++j) {
    out->twist[j] = WrapToPi(
        TwistAngle(Eigen::Quaterniond(q_base.conjugate() * set.q[j]), a_o));
  }
  out->type = prior.symmetry;
  out->diagnostics.prior_type_used = true;
  if (prior.symmetry != SymmetryType::kDiscrete) return;
  AngleCluster cluster;
  cluster.members = out->inliers;
  double sum_sq = 0.0;
  for (int j : out->inliers) {
    cluster.weight += set.w[j];
    sum_sq += set.w[j] * out->twist[j] * out->twist[j];
  }
  cluster.spread = std::sqrt(sum_sq / cluster.weight);
  out->clusters.assign(1, cluster);
  // The reference's cluster is clusters[0] (categorize.h).
  out->reference = out->inliers.front();
  for (int j : out->inliers) {
    if (set.w[j] > set.w[out->reference]) out->reference = j;
  }
}

}  // namespace categorization
}  // namespace symba
