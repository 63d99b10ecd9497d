// Steps 2-7 of the categorization (docs/categorization.md) with one
// reference: the axis, the twists, their clusters and the decision.
#ifndef SYMBA_CATEGORIZATION_CATEGORIZATION_PASS_H_
#define SYMBA_CATEGORIZATION_CATEGORIZATION_PASS_H_

#include <optional>

#include <Eigen/Core>

#include "categorization/hypothesis_set.h"
#include "categorization/signed_twists.h"
#include "categorization/symmetry_axis.h"
#include "symba/categorization/categorize.h"
#include "symba/categorization/circular_dbscan.h"

namespace symba {
namespace categorization {

// What one pass found; the discrete and continuous results are read from it.
struct Pass {
  SymmetryType type = SymmetryType::kAsymmetric;
  // The reference is noise of a pass that may retry: run again with
  // next_reference.
  bool retry = false;
  int next_reference = -1;
  // Steps 4-6; empty when the votes found no second mode.
  AxisFit axis;
  SignedTwists twists;
  CircularDbscanResult clusters;  // of twists.inlier_psi, merged (rescued)
  // passes is left to the caller; prior_order_snapped and prior_type_used
  // belong to the results.
  CategorizationDiagnostics diagnostics;
};

// Steps 2-7 with reference r. `prior_axis` (unit) replaces the voted axis;
// `may_retry` allows asking for a second pass when r is an outlier.
Pass RunPass(const HypothesisSet& set,
             const CategorizationOptions& options,
             const std::optional<Eigen::Vector3d>& prior_axis,
             int r,
             bool may_retry);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CATEGORIZATION_PASS_H_
