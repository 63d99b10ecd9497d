// Step 1 of the categorization (docs/categorization.md): the reference
// hypothesis, against which the relative rotations are taken.
#ifndef SYMBA_CATEGORIZATION_REFERENCE_CHOICE_H_
#define SYMBA_CATEGORIZATION_REFERENCE_CHOICE_H_

#include <vector>

#include "categorization/hypothesis_set.h"

namespace symba {
namespace categorization {

// support[i] = the number of usable hypotheses j (i itself included) with
// rotation angle |log(R_i^T R_j)| <= max_angle, tested as
// |q_i . q_j| >= cos(max_angle / 2); 0 for a hypothesis that is not usable.
std::vector<int> RotationSupport(const HypothesisSet& set, double max_angle);

// The highest-weight usable hypothesis (ties: lowest index) whose support
// within min_axis_angle is at least min_points; if none has, the
// highest-weight usable one.
int ChooseReference(const HypothesisSet& set,
                    double min_axis_angle,
                    int min_points);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_REFERENCE_CHOICE_H_
