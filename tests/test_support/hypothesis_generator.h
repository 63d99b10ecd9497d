// Synthetic multi-hypothesis detections for the categorization tests and the
// accuracy benchmark (docs/categorization.md).
//
// One detection of an object with true pose T_co = (R, t) and symmetry axis
// a_o (unit, object frame, uniform on the sphere: any axis, not only z):
//   inlier j   R_j = R * Rot(a_o, phi_j) * Exp(n_j),  n_j ~ N(0, s_r^2 I_3)
//              t_j = t + m_j,                          m_j ~ N(0, s_t^2 I_3)
//     asymmetric  phi_j = 0
//     discrete    phi_j = 2 pi m / order, m the j-th visible mode in turn
//                 (the inliers are shared out evenly over the visible modes)
//     continuous  phi_j ~ U(-pi, pi)
//   outlier j  R_j uniform on SO(3), t_j = t + U(-range, range)^3
// round(outlier_fraction * N) of the N hypotheses are outliers; the order of
// all N is shuffled, so the first or the highest-weight one can be an
// outlier. All weights are 1. R is uniform on SO(3), t has x, y in [-1, 1] m
// and z in [1, 4] m. s_r is per axis: the twist about a_o has standard
// deviation s_r, the total rotation error about 1.6 s_r on average.
// A discrete view with one visible mode is expected to read as asymmetric.
#ifndef SYMBA_TESTS_TEST_SUPPORT_HYPOTHESIS_GENERATOR_H_
#define SYMBA_TESTS_TEST_SUPPORT_HYPOTHESIS_GENERATOR_H_

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/categorization/symmetry_type.h"
#include "symba/detection/pose_hypothesis.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "test_support/random.h"

namespace symba::testing {

inline constexpr double kDegree = kPi / 180.0;

struct HypothesisSetSpec {
  SymmetryType type = SymmetryType::kDiscrete;
  int order = 2;                   // discrete symmetry order
  std::vector<int> visible_modes;  // discrete: subset of [0, order); {} = all
  double rotation_sigma = 5.0 * kDegree;   // s_r, rad per axis
  double translation_sigma = 0.03;         // s_t, m per axis
  double outlier_fraction = 0.1;           // of num_hypotheses, rounded
  double outlier_translation_range = 0.3;  // m
  int num_hypotheses = 30;
};

struct GeneratedDetection {
  std::vector<PoseHypothesis> hypotheses;
  Rigid3d T_co_true;        // the object (mode 0)
  Eigen::Vector3d axis_o;   // true axis, object frame (set for every type)
  Eigen::Vector3d axis_c;   // R * axis_o
  std::vector<int> mode;    // per hypothesis: mode index (0 unless discrete),
                            // -1 for an outlier
  std::vector<double> phi;  // per hypothesis: true angle, rad
  std::vector<int> visible_modes;  // discrete: the modes shown
  SymmetryType expected_type = SymmetryType::kAsymmetric;
};

inline GeneratedDetection GenerateDetection(const HypothesisSetSpec& spec,
                                            TestRandom* random) {
  GeneratedDetection d;
  const Eigen::Quaterniond q_true = random->Rotation();
  const Eigen::Vector3d t_true(
      random->Uniform(-1, 1), random->Uniform(-1, 1), random->Uniform(1, 4));
  d.T_co_true = Rigid3d(q_true, t_true);
  d.axis_o = random->UnitVector();
  d.axis_c = q_true * d.axis_o;
  d.expected_type = spec.type;
  if (spec.type == SymmetryType::kDiscrete) {
    d.visible_modes = spec.visible_modes;
    if (d.visible_modes.empty()) {
      for (int m = 0; m < spec.order; ++m) d.visible_modes.push_back(m);
    }
    if (d.visible_modes.size() == 1) {
      d.expected_type = SymmetryType::kAsymmetric;
    }
  }

  const int n = spec.num_hypotheses;
  const int num_outliers =
      static_cast<int>(std::lround(spec.outlier_fraction * n));
  const int num_inliers = n - num_outliers;
  for (int i = 0; i < n; ++i) {
    PoseHypothesis h;
    if (i >= num_inliers) {
      const double range = spec.outlier_translation_range;
      h.T_co =
          Rigid3d(random->Rotation(),
                  t_true + Eigen::Vector3d(random->Uniform(-range, range),
                                           random->Uniform(-range, range),
                                           random->Uniform(-range, range)));
      d.mode.push_back(-1);
      d.phi.push_back(0.0);
    } else {
      int mode = 0;
      double phi = 0.0;
      if (spec.type == SymmetryType::kDiscrete) {
        mode = d.visible_modes[i % d.visible_modes.size()];
        phi = WrapToPi(kTwoPi * mode / spec.order);
      } else if (spec.type == SymmetryType::kContinuous) {
        phi = random->Uniform(-kPi, kPi);
      }
      const Eigen::Quaterniond q =
          q_true * Eigen::Quaterniond(Eigen::AngleAxisd(phi, d.axis_o)) *
          ExpSO3<double>(random->NormalVector(spec.rotation_sigma));
      h.T_co = Rigid3d(q.normalized(),
                       t_true + random->NormalVector(spec.translation_sigma));
      d.mode.push_back(mode);
      d.phi.push_back(phi);
    }
    d.hypotheses.push_back(h);
  }
  // Fisher-Yates with the test engine.
  for (int i = n - 1; i > 0; --i) {
    const int k = std::uniform_int_distribution<int>(0, i)(random->engine());
    std::swap(d.hypotheses[i], d.hypotheses[k]);
    std::swap(d.mode[i], d.mode[k]);
    std::swap(d.phi[i], d.phi[k]);
  }
  return d;
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_HYPOTHESIS_GENERATOR_H_
