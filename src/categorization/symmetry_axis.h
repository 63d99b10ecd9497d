// Steps 2-4 of the categorization (docs/categorization.md): the rotations
// relative to the reference, the axis votes and the least-squares symmetry
// axis with its inliers.
#ifndef SYMBA_CATEGORIZATION_SYMMETRY_AXIS_H_
#define SYMBA_CATEGORIZATION_SYMMETRY_AXIS_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "categorization/hypothesis_set.h"
#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// Step 2: omega_j = log(R_r^T R_j) in the reference's object frame.
struct RelativeRotations {
  std::vector<double> theta;         // |omega_j|; 0 if not usable
  std::vector<Eigen::Vector3d> dir;  // omega_j / theta_j for far rows, else 0
  std::vector<int> far;              // usable j with theta_j > min_axis_angle
};
RelativeRotations RelativeRotationsTo(const HypothesisSet& set,
                                      int r,
                                      double min_axis_angle);

// Step 3: the winner of the axis votes.
struct AxisVote {
  Eigen::Vector3d guess = Eigen::Vector3d::UnitZ();  // unit axis, object frame
  int support = 0;                                   // far rows agreeing
  double support_weight = 0.0;                       // their weight
};
// Far rows k agree with a direction u when |dir_k . u| >= cos(vote_angle).
// With `prior_axis` (unit), the far rows that agree with it; otherwise the
// far row whose direction collects the most weight (ties: the first).
AxisVote VoteAxis(const RelativeRotations& rotations,
                  const std::vector<double>& weights,
                  double vote_angle,
                  const std::optional<Eigen::Vector3d>& prior_axis);

// The singular pair of B = sum_{j in_set} w_j R_j, B = U diag(s) V^T, whose
// right vector is nearest `guess` (up to sign, turned towards it): it
// maximises axis_c^T B axis_o, i.e. minimises sum w_j |R_j axis_o - axis_c|^2.
// False when B axis_o vanishes.
bool FitAxis(const HypothesisSet& set,
             const std::vector<char>& in_set,
             const Eigen::Vector3d& guess,
             Eigen::Vector3d* axis_o,
             Eigen::Vector3d* axis_c);

// Step 4: the axis and its inliers.
struct AxisFit {
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();  // unit, object frame
  Eigen::Vector3d axis_c = Eigen::Vector3d::Zero();  // unit, camera frame
  std::vector<char> inlier;  // (R_j axis_o) . axis_c >= cos(swing_tolerance)
  int num_inliers = 0;
};
// Starts from the near rows and the rows that vote for `guess`; three rounds
// of (fit, inliers). With `keep_axis` (a prior axis) axis_o stays `guess`
// and axis_c = the normalised sum_j w_j R_j axis_o over the set.
AxisFit FitAxisToInliers(const HypothesisSet& set,
                         const RelativeRotations& rotations,
                         int r,
                         const Eigen::Vector3d& guess,
                         bool keep_axis,
                         const CategorizationOptions& options);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_SYMMETRY_AXIS_H_
