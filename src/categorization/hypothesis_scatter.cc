#include "symba/categorization/hypothesis_scatter.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "common/median.h"

namespace symba {
namespace {

// Each inlier's rotation error about its mode (see the header).
std::vector<double> RotationErrors(const std::vector<PoseHypothesis>& hyps,
                                   const CategorizedDetection& cat) {
  std::vector<double> errors;
  switch (cat.type) {
    case SymmetryType::kAsymmetric:
      for (int j : cat.inliers) {
        errors.push_back(cat.T_co_base.q.angularDistance(hyps[j].T_co.q));
      }
      break;
    case SymmetryType::kDiscrete:
      for (const AngleCluster& cluster : cat.clusters) {
        const Eigen::Quaterniond R_mode =
            cat.T_co_base.q *
            Eigen::Quaterniond(Eigen::AngleAxisd(cluster.theta, cat.axis_o));
        for (int j : cluster.members) {
          errors.push_back(R_mode.angularDistance(hyps[j].T_co.q));
        }
      }
      break;
    case SymmetryType::kContinuous: {
      const Eigen::Vector3d axis_c = cat.axis_c.normalized();
      for (int j : cat.inliers) {
        const Eigen::Vector3d a = hyps[j].T_co.q.normalized() * cat.axis_o;
        errors.push_back(std::atan2(a.cross(axis_c).norm(), a.dot(axis_c)));
      }
      break;
    }
  }
  return errors;
}

}  // namespace

HypothesisScatter MeasureHypothesisScatter(
    const std::vector<PoseHypothesis>& hypotheses,
    const CategorizedDetection& categorized) {
  HypothesisScatter scatter;
  std::vector<double> translation_errors;
  for (int j : categorized.inliers) {
    translation_errors.push_back(
        (hypotheses[j].T_co.t - categorized.t_co).norm());
  }
  std::vector<double> rotation_errors = RotationErrors(hypotheses, categorized);
  scatter.count = static_cast<int>(
      std::min(translation_errors.size(), rotation_errors.size()));
  if (scatter.count < 2) return scatter;
  // The errors are taken about a centre fitted to the same inliers, which
  // shrinks them by sqrt((N - 1) / N).
  const double fitted_centre = std::sqrt(scatter.count / (scatter.count - 1.0));
  scatter.sigma_t = fitted_centre *
                    internal::MedianInPlace(&translation_errors) /
                    internal::kChi3Median;
  scatter.sigma_r =
      fitted_centre * internal::MedianInPlace(&rotation_errors) /
      (categorized.type == SymmetryType::kContinuous ? internal::kChi2Median
                                                     : internal::kChi3Median);
  return scatter;
}

}  // namespace symba
