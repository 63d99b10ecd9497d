// How far a categorised detection's hypotheses lie from their own mode: the
// noise a multi-hypothesis detector shows without declaring it
// (docs/backend.md "Real detectors", 4).
//
// A detector that returns many hypotheses per object spreads them about
// each symmetric pose it sees; the spread within a mode is its own word on
// how well it knows the pose, as a declared sigma would be. Over the
// categorisation's inliers (outliers left out), with R_mode the rotation of
// the hypothesis' mode (the base rotation for an asymmetric detection, R_base
// Rot(axis_o, theta_c) for a member of a discrete cluster c):
//
//   translation  e_j = |t_j - t_co|                       (m, 3 DoF)
//   rotation     asymmetric, discrete: e_j = |Log(R_mode^T R_j)|
//                                                         (rad, 3 DoF)
//                continuous: e_j = angle(R_j axis_o, axis_c)
//                (rad, 2 DoF: the turn about the axis is the symmetry)
//
// and, for isotropic Gaussian noise of sigma per axis, |e| follows a chi
// distribution whose median is 1.5382 sigma (3 DoF) or 1.1774 sigma (2 DoF):
//
//   sigma = sqrt(N / (N - 1)) median_j e_j / chi_median(DoF),
//
// N the inliers (their mode's centre is fitted to them, which shrinks the
// errors by sqrt((N - 1) / N)).
//
// The median ignores the few hypotheses the categorisation kept that belong
// to no mode. A single hypothesis has no spread (count 1).
#ifndef SYMBA_CATEGORIZATION_HYPOTHESIS_SCATTER_H_
#define SYMBA_CATEGORIZATION_HYPOTHESIS_SCATTER_H_

#include <vector>

#include "symba/categorization/categorize.h"
#include "symba/detection/pose_hypothesis.h"

namespace symba {

struct HypothesisScatter {
  int count = 0;         // inliers the sigmas come from
  double sigma_t = 0.0;  // m, per axis
  double sigma_r = 0.0;  // rad, per axis
};

// The spread of `categorized`'s inliers about their modes (see above).
// `hypotheses` are the ones `categorized` was made from.
HypothesisScatter MeasureHypothesisScatter(
    const std::vector<PoseHypothesis>& hypotheses,
    const CategorizedDetection& categorized);

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_HYPOTHESIS_SCATTER_H_
