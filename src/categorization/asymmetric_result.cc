#include "categorization/asymmetric_result.h"

#include <cmath>

namespace symba {
namespace categorization {

double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

Eigen::Quaterniond MeanRotationNear(const HypothesisSet& set,
                                    const Eigen::Quaterniond& q_start,
                                    double inlier_angle) {
  Eigen::Quaterniond q_mean = q_start;
  for (int iteration = 0; iteration < 2; ++iteration) {
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (int j = 0; j < set.size(); ++j) {
      if (!set.usable[j]) continue;
      const Eigen::Quaterniond& q = set.q[j];
      if (RotationAngle(q_mean.conjugate() * q) > inlier_angle) continue;
      const double sign = q.coeffs().dot(q_mean.coeffs()) < 0.0 ? -1.0 : 1.0;
      sum += sign * set.w[j] * q.coeffs();
    }
    if (sum.norm() > 1e-12) {
      q_mean = Eigen::Quaterniond(sum.normalized());
    }
  }
  return q_mean;
}

void AssembleAsymmetric(const HypothesisSet& set,
                        double asymmetric_inlier_angle,
                        int r,
                        CategorizedDetection* out) {
  const int n = set.size();
  Eigen::Quaterniond q_mean =
      MeanRotationNear(set, set.q[r], asymmetric_inlier_angle);
  out->inliers.clear();
  for (int j = 0; j < n; ++j) {
    if (set.usable[j] && RotationAngle(q_mean.conjugate() * set.q[j]) <=
                             asymmetric_inlier_angle) {
      out->inliers.push_back(j);
    }
  }
  if (out->inliers.empty()) {
    out->inliers.push_back(r);
    q_mean = set.q[r];
  }
  out->type = SymmetryType::kAsymmetric;
  out->t_co = MeanTranslation(set, out->inliers);
  out->T_co_base = Rigid3d(q_mean, out->t_co);
  out->axis_o.setZero();
  out->axis_c.setZero();
  out->clusters.clear();
  out->twist.assign(n, 0.0);
}

}  // namespace categorization
}  // namespace symba
