#include "categorization/symmetry_axis.h"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "symba/geometry/so3.h"

namespace symba {
namespace categorization {

RelativeRotations RelativeRotationsTo(const HypothesisSet& set,
                                      int r,
                                      double min_axis_angle) {
  const int n = set.size();
  const Eigen::Quaterniond q_r_inv = set.q[r].conjugate();
  RelativeRotations rotations;
  rotations.theta.assign(n, 0.0);
  rotations.dir.assign(n, Eigen::Vector3d::Zero());
  for (int j = 0; j < n; ++j) {
    if (!set.usable[j]) continue;
    const Eigen::Vector3d omega =
        LogSO3(Eigen::Quaterniond(q_r_inv * set.q[j]));
    const double theta = omega.norm();
    rotations.theta[j] = theta;
    if (theta > min_axis_angle) {
      rotations.dir[j] = omega / theta;
      rotations.far.push_back(j);
    }
  }
  return rotations;
}

AxisVote VoteAxis(const RelativeRotations& rotations,
                  const std::vector<double>& weights,
                  double vote_angle,
                  const std::optional<Eigen::Vector3d>& prior_axis) {
  const double cos_vote = std::cos(vote_angle);
  const std::vector<Eigen::Vector3d>& dir = rotations.dir;
  AxisVote vote;
  if (prior_axis) {
    vote.guess = *prior_axis;
    for (int k : rotations.far) {
      if (std::abs(dir[k].dot(vote.guess)) >= cos_vote) {
        ++vote.support;
        vote.support_weight += weights[k];
      }
    }
    return vote;
  }
  double best_weight = -1.0;
  for (int i : rotations.far) {
    int count = 0;
    double weight = 0.0;
    for (int k : rotations.far) {
      if (std::abs(dir[i].dot(dir[k])) >= cos_vote) {
        ++count;
        weight += weights[k];
      }
    }
    if (weight > best_weight) {
      best_weight = weight;
      vote.support = count;
      vote.support_weight = weight;
      vote.guess = dir[i];
    }
  }
  return vote;
}

bool FitAxis(const HypothesisSet& set,
             const std::vector<char>& in_set,
             const Eigen::Vector3d& guess,
             Eigen::Vector3d* axis_o,
             Eigen::Vector3d* axis_c) {
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
  for (int j = 0; j < static_cast<int>(in_set.size()); ++j) {
    if (in_set[j]) B += set.w[j] * set.R[j];
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  int best = 0;
  double best_dot = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double dot = std::abs(svd.matrixV().col(k).dot(guess));
    if (dot > best_dot) {
      best_dot = dot;
      best = k;
    }
  }
  Eigen::Vector3d a_o = svd.matrixV().col(best);
  if (a_o.dot(guess) < 0.0) a_o = -a_o;
  const Eigen::Vector3d b = B * a_o;
  if (!(b.norm() > 1e-12 * (1.0 + B.norm()))) return false;
  *axis_o = a_o;
  *axis_c = b.normalized();
  return true;
}

AxisFit FitAxisToInliers(const HypothesisSet& set,
                         const RelativeRotations& rotations,
                         int r,
                         const Eigen::Vector3d& guess,
                         bool keep_axis,
                         const CategorizationOptions& options) {
  const int n = set.size();
  const double cos_vote = std::cos(options.axis_vote_angle);
  AxisFit fit;
  std::vector<char>& in_set = fit.inlier;
  in_set.assign(n, 0);
  for (int j = 0; j < n; ++j) {
    if (!set.usable[j]) continue;
    in_set[j] = rotations.theta[j] <= options.min_axis_angle ||
                std::abs(rotations.dir[j].dot(guess)) >= cos_vote;
  }
  Eigen::Vector3d axis_o = guess;
  Eigen::Vector3d axis_c = set.R[r] * guess;
  const double cos_swing = std::cos(options.swing_tolerance);
  constexpr int kAxisIterations = 3;
  for (int iteration = 0; iteration < kAxisIterations; ++iteration) {
    if (keep_axis) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 0; j < n; ++j) {
        if (in_set[j]) sum += set.w[j] * (set.R[j] * axis_o);
      }
      if (sum.norm() > 1e-12) axis_c = sum.normalized();
    } else {
      Eigen::Vector3d a_o, a_c;
      if (FitAxis(set, in_set, axis_o, &a_o, &a_c)) {
        axis_o = a_o;
        axis_c = a_c;
      }
    }
    int count = 0;
    for (int j = 0; j < n; ++j) {
      in_set[j] = set.usable[j] && (set.R[j] * axis_o).dot(axis_c) >= cos_swing;
      count += in_set[j];
    }
    fit.num_inliers = count;
    if (count == 0) break;
  }
  fit.axis_o = axis_o;
  fit.axis_c = axis_c;
  return fit;
}

}  // namespace categorization
}  // namespace symba
