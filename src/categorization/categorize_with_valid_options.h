// The categorization for a caller that validated its options and class
// priors once (the backend, at Backend::Create), so that they are not
// checked again for every detection.
#ifndef SYMBA_CATEGORIZATION_CATEGORIZE_WITH_VALID_OPTIONS_H_
#define SYMBA_CATEGORIZATION_CATEGORIZE_WITH_VALID_OPTIONS_H_

#include <vector>

#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// Categorize() without checking `options` and `prior`: the caller
// guarantees options.Validate() and prior->Validate() (when `prior` is not
// null) are OK. The hypotheses are checked as Categorize() checks them; the
// result is the same as Categorize()'s.
Status CategorizeWithValidOptions(const std::vector<PoseHypothesis>& hypotheses,
                                  const CategorizationOptions& options,
                                  const ClassPrior* prior,
                                  CategorizedDetection* out);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CATEGORIZE_WITH_VALID_OPTIONS_H_
