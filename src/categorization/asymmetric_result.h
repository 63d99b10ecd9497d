// Step 8 of the categorization for an asymmetric detection
// (docs/categorization.md): the mean pose and its inliers.
#ifndef SYMBA_CATEGORIZATION_ASYMMETRIC_RESULT_H_
#define SYMBA_CATEGORIZATION_ASYMMETRIC_RESULT_H_

#include <Eigen/Geometry>

#include "categorization/hypothesis_set.h"
#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// Rotation angle of unit q, in [0, pi].
double RotationAngle(const Eigen::Quaterniond& q);

// q_mean = the normalised weighted sum of the usable quaternions within
// `inlier_angle` of the current mean, sign-aligned with it; two rounds
// starting from q_start.
Eigen::Quaterniond MeanRotationNear(const HypothesisSet& set,
                                    const Eigen::Quaterniond& q_start,
                                    double inlier_angle);

// Fills `out` but its reference and diagnostics: inliers = the usable
// hypotheses within asymmetric_inlier_angle of the mean rotation around the
// reference r (r alone, with its rotation, if none), T_co_base = (that mean,
// their weighted mean translation), zero axes and twists, no clusters.
void AssembleAsymmetric(const HypothesisSet& set,
                        double asymmetric_inlier_angle,
                        int r,
                        CategorizedDetection* out);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_ASYMMETRIC_RESULT_H_
