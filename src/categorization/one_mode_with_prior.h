// Class priors (docs/categorization.md, "Class priors"): hypotheses that
// show one mode of a symmetric class are read with the prior's type.
#ifndef SYMBA_CATEGORIZATION_ONE_MODE_WITH_PRIOR_H_
#define SYMBA_CATEGORIZATION_ONE_MODE_WITH_PRIOR_H_

#include "categorization/hypothesis_set.h"
#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// True when a one-mode detection of a class with `prior` (may be null) is
// read with the prior's type: the option is on and the prior is symmetric
// and knows its axis.
bool ReadsOneModeWithPrior(const CategorizationOptions& options,
                           const ClassPrior* prior);

// Turns an asymmetric result in `out` into the prior's type: the mean pose
// stays the base, axis_o = the prior axis (unit), axis_c = R_base axis_o and
//   twist_j = Twist(R_base^T R_j, axis_o)
// for every hypothesis. Discrete: one cluster at theta = 0 holding the
// inliers, its spread the weighted RMS of their twists, and the reference
// its highest-weight member (ties: the lowest index).
void ReadOneModeWithPrior(const ClassPrior& prior,
                          const HypothesisSet& set,
                          CategorizedDetection* out);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_ONE_MODE_WITH_PRIOR_H_
