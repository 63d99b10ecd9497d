// The detection's hypotheses as the categorization stages read them: checked,
// rotations normalised, and gated by translation (docs/categorization.md,
// step 0).
#ifndef SYMBA_CATEGORIZATION_HYPOTHESIS_SET_H_
#define SYMBA_CATEGORIZATION_HYPOTHESIS_SET_H_

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/common/status.h"
#include "symba/detection/pose_hypothesis.h"

namespace symba {
namespace categorization {

struct HypothesisSet {
  std::vector<Eigen::Quaterniond> q;  // R_j, normalised
  std::vector<Eigen::Matrix3d> R;     // R_j as matrices
  std::vector<Eigen::Vector3d> t;     // t_j
  std::vector<double> w;              // w_j
  std::vector<char> usable;           // passed the translation gate

  int size() const { return static_cast<int>(q.size()); }
};

// OK, or an error naming the hypothesis and what is wrong: an empty set, a
// non-finite rotation or translation, a quaternion whose norm is not within
// 1e-3 of 1, a weight that is not positive and finite.
Status ValidateHypotheses(const std::vector<PoseHypothesis>& hypotheses);

// Step 0: usable[j] = |t_j - m| <= gate, m the coordinate-wise median of the
// t_j (the upper median for even N). Every hypothesis is usable when the
// gate is infinite or would drop them all.
std::vector<char> GateTranslations(
    const std::vector<PoseHypothesis>& hypotheses, double gate);

// The set of checked `hypotheses`, gated with `translation_gate`.
HypothesisSet MakeHypothesisSet(const std::vector<PoseHypothesis>& hypotheses,
                                double translation_gate);

// sum_j w_j t_j / sum_j w_j over `members`; t_0 when they have no weight.
Eigen::Vector3d MeanTranslation(const HypothesisSet& set,
                                const std::vector<int>& members);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_HYPOTHESIS_SET_H_
