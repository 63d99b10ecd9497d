#include "categorization/continuous_result.h"

namespace symba {
namespace categorization {

void AssembleContinuous(const HypothesisSet& set,
                        const Pass& pass,
                        CategorizedDetection* out) {
  out->inliers.clear();
  for (int j = 0; j < set.size(); ++j) {
    if (pass.axis.inlier[j]) out->inliers.push_back(j);
  }
  out->type = SymmetryType::kContinuous;
  out->t_co = MeanTranslation(set, out->inliers);
  out->T_co_base = Rigid3d(pass.twists.q_ref, out->t_co);
  out->axis_o = pass.axis.axis_o;
  out->axis_c = pass.axis.axis_c;
  out->clusters.clear();
  out->twist.assign(pass.twists.psi.begin(), pass.twists.psi.end());
}

}  // namespace categorization
}  // namespace symba
