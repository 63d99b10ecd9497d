// Step 8 of the categorization for a continuous detection
// (docs/categorization.md): position and axis, every axis inlier kept.
#ifndef SYMBA_CATEGORIZATION_CONTINUOUS_RESULT_H_
#define SYMBA_CATEGORIZATION_CONTINUOUS_RESULT_H_

#include "categorization/categorization_pass.h"
#include "categorization/hypothesis_set.h"
#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// Fills `out` but its reference and diagnostics from a continuous pass:
// inliers = the axis inliers, T_co_base = (R_ref, their weighted mean
// translation), the pass's axes, twist_j = psi_j, no clusters.
void AssembleContinuous(const HypothesisSet& set,
                        const Pass& pass,
                        CategorizedDetection* out);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CONTINUOUS_RESULT_H_
