// Step 5 of the categorization (docs/categorization.md): every hypothesis'
// signed twist about the symmetry axis, relative to the reference with its
// axis aligned.
#ifndef SYMBA_CATEGORIZATION_SIGNED_TWISTS_H_
#define SYMBA_CATEGORIZATION_SIGNED_TWISTS_H_

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "categorization/hypothesis_set.h"

namespace symba {
namespace categorization {

struct SignedTwists {
  // R_ref = Swing(R_r axis_o -> axis_c) * R_r, so R_j ~= R_ref Rot(axis_o, psi_j).
  Eigen::Quaterniond q_ref = Eigen::Quaterniond::Identity();
  std::vector<double> psi;         // per hypothesis, (-pi, pi]
  std::vector<double> inlier_psi;  // psi of the axis inliers, ascending j
  std::vector<int> inlier_owner;   // the hypothesis of each inlier_psi
};

// psi_j = Twist(R_ref^T R_j, axis_o) (method Eq. 7) for every hypothesis;
// `axis_inlier` picks the ones that are clustered.
SignedTwists TwistsAboutAxis(const HypothesisSet& set,
                             int r,
                             const Eigen::Vector3d& axis_o,
                             const Eigen::Vector3d& axis_c,
                             const std::vector<char>& axis_inlier);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_SIGNED_TWISTS_H_
