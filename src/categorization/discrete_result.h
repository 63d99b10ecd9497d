// Step 8 of the categorization for a discrete detection and the snap of its
// angles to a class prior's order (docs/categorization.md).
#ifndef SYMBA_CATEGORIZATION_DISCRETE_RESULT_H_
#define SYMBA_CATEGORIZATION_DISCRETE_RESULT_H_

#include <vector>

#include "categorization/categorization_pass.h"
#include "categorization/hypothesis_set.h"
#include "symba/categorization/categorize.h"

namespace symba {
namespace categorization {

// The modes of a discrete pass, per DBSCAN cluster c.
struct ModeAngles {
  std::vector<int> label;      // per hypothesis: its cluster, or kNoiseLabel
  std::vector<double> mean;    // psibar_c, (-pi, pi]
  std::vector<double> weight;  // sum of the members' weights
};
// psibar_c = start_c + sum_j w_j arc(start_c, psi_j) / sum_j w_j over the
// members j of c: the weighted mean of the twists along the cluster's arc.
ModeAngles MeanModeAngles(const HypothesisSet& set, const Pass& pass);

// Class prior of order K >= 2: when every theta_c is within snap_angle of a
// multiple m_c of 2 pi / K and the m_c (mod K) are distinct, theta_c becomes
// WrapToPi(m_c 2 pi / K) and the offset (the base twist relative to R_ref)
// is re-estimated from every member j of a cluster,
//   offset += sum_j w_j WrapToPi(psi_j - offset - m_c(j) 2 pi / K) / sum_j w_j,
// wrapped to (-pi, pi]; returns true. Otherwise changes nothing, false.
bool SnapToOrder(int order,
                 double snap_angle,
                 const std::vector<int>& label,
                 const std::vector<double>& psi,
                 const std::vector<double>& weights,
                 double* offset,
                 std::vector<double>* theta);

// Fills `out` but its reference and the pass's diagnostics from a discrete
// pass with reference r: R_base = R_ref Rot(axis_o, psibar of r's cluster),
// theta_c = WrapToPi(psibar_c - psibar_ref) (snapped with a discrete prior
// with an order), clusters[0] the reference's and the others
// counter-clockwise, spread_c the weighted RMS of WrapToPi(twist_j -
// theta_c), inliers every cluster member, t_co their weighted mean.
void AssembleDiscrete(const HypothesisSet& set,
                      const Pass& pass,
                      int r,
                      const ClassPrior* prior,
                      double prior_snap_angle,
                      CategorizedDetection* out);

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_DISCRETE_RESULT_H_
