// What the log header's `classes` entry says about an object class
// (docs/log-format.md), and its check.
#ifndef SYMBA_CATEGORIZATION_CLASS_PRIOR_H_
#define SYMBA_CATEGORIZATION_CLASS_PRIOR_H_

#include <Eigen/Core>

#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"

namespace symba {

inline constexpr double kMinPriorAxisNorm = 1e-100;
inline constexpr double kMaxPriorAxisNorm = 1e100;
// Zero (no axis) or a norm in [kMinPriorAxisNorm, kMaxPriorAxisNorm].
inline bool IsUsablePriorAxis(const Eigen::Vector3d& axis_o) {
  const double norm = axis_o.norm();
  return axis_o.isZero(0.0) ||
         (norm >= kMinPriorAxisNorm && norm <= kMaxPriorAxisNorm);
}

struct ClassPrior {
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  int order = 0;  // discrete: symmetry order (>= 2); 0 = unknown
  // Symmetry axis in the object frame; zero = unknown. Need not be unit,
  // but its norm must be in [kMinPriorAxisNorm, kMaxPriorAxisNorm].
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();

  // OK, or what is wrong: a symmetry that is none of the three types, an
  // order of 1 or below 0, a non-finite axis or one whose squared norm
  // would overflow or underflow. Categorize() checks it on
  // every call; a caller that checked it once may use the prior freely.
  Status Validate() const;
};

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CLASS_PRIOR_H_
