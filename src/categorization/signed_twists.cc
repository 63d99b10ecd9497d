#include "categorization/signed_twists.h"

#include "symba/geometry/swing_twist.h"

namespace symba {
namespace categorization {

SignedTwists TwistsAboutAxis(const HypothesisSet& set,
                             int r,
                             const Eigen::Vector3d& axis_o,
                             const Eigen::Vector3d& axis_c,
                             const std::vector<char>& axis_inlier) {
  const int n = set.size();
  SignedTwists twists;
  twists.q_ref = (MinimalRotation<double>(set.R[r] * axis_o, axis_c) * set.q[r])
                     .normalized();
  const Eigen::Quaterniond q_ref_inv = twists.q_ref.conjugate();
  twists.psi.assign(n, 0.0);
  for (int j = 0; j < n; ++j) {
    twists.psi[j] = TwistAngle<double>(q_ref_inv * set.q[j], axis_o);
    if (axis_inlier[j]) {
      twists.inlier_psi.push_back(twists.psi[j]);
      twists.inlier_owner.push_back(j);
    }
  }
  return twists;
}

}  // namespace categorization
}  // namespace symba
