#include "categorization/discrete_result.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "categorization/circle_arc.h"
#include "symba/geometry/angle.h"

namespace symba {
namespace categorization {
namespace {

// Cluster indices with the reference's first and the others by their
// counter-clockwise arc from theta = 0.
std::vector<int> ClustersInOutputOrder(const std::vector<double>& theta,
                                       int c_ref) {
  std::vector<int> order(theta.size());
  for (int c = 0; c < static_cast<int>(order.size()); ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double arc_a = a == c_ref ? -1.0 : ForwardArc(0.0, theta[a]);
    const double arc_b = b == c_ref ? -1.0 : ForwardArc(0.0, theta[b]);
    return arc_a < arc_b;
  });
  return order;
}

// Output cluster c at angle theta: its members (ascending) and spread, the
// weighted RMS of WrapToPi(twist_j - theta).
AngleCluster OutputCluster(const std::vector<int>& label,
                           const std::vector<double>& twist,
                           const std::vector<double>& weights,
                           int c,
                           double theta,
                           double weight) {
  AngleCluster cluster;
  cluster.theta = theta;
  cluster.weight = weight;
  double sum_sq = 0.0;
  for (int j = 0; j < static_cast<int>(label.size()); ++j) {
    if (label[j] != c) continue;
    cluster.members.push_back(j);
    const double e = WrapToPi(twist[j] - theta);
    sum_sq += weights[j] * e * e;
  }
  cluster.spread = std::sqrt(sum_sq / weight);
  return cluster;
}

}  // namespace

ModeAngles MeanModeAngles(const HypothesisSet& set, const Pass& pass) {
  const CircularDbscanResult& dbscan = pass.clusters;
  const int num_clusters = static_cast<int>(dbscan.clusters.size());
  ModeAngles modes;
  modes.label.assign(set.size(), CircularDbscanResult::kNoiseLabel);
  modes.mean.assign(num_clusters, 0.0);
  modes.weight.assign(num_clusters, 0.0);
  const std::vector<int>& owner = pass.twists.inlier_owner;
  for (int i = 0; i < static_cast<int>(owner.size()); ++i) {
    const int c = dbscan.labels[i];
    if (c == CircularDbscanResult::kNoiseLabel) continue;
    const int j = owner[i];
    modes.label[j] = c;
    modes.mean[c] +=
        set.w[j] * ForwardArc(dbscan.clusters[c].start, pass.twists.psi[j]);
    modes.weight[c] += set.w[j];
  }
  for (int c = 0; c < num_clusters; ++c) {
    modes.mean[c] =
        WrapToPi(dbscan.clusters[c].start + modes.mean[c] / modes.weight[c]);
  }
  return modes;
}

bool SnapToOrder(int order,
                 double snap_angle,
                 const std::vector<int>& label,
                 const std::vector<double>& psi,
                 const std::vector<double>& weights,
                 double* offset,
                 std::vector<double>* theta) {
  const int num_clusters = static_cast<int>(theta->size());
  const double step = kTwoPi / order;
  std::vector<int> multiple(num_clusters);
  for (int c = 0; c < num_clusters; ++c) {
    const long nearest = std::lround((*theta)[c] / step);
    if (!(std::abs((*theta)[c] - nearest * step) <= snap_angle)) return false;
    multiple[c] = ((static_cast<int>(nearest) % order) + order) % order;
    for (int d = 0; d < c; ++d) {
      if (multiple[d] == multiple[c]) return false;
    }
  }
  double sum = 0.0;
  double total = 0.0;
  for (int j = 0; j < static_cast<int>(label.size()); ++j) {
    if (label[j] == CircularDbscanResult::kNoiseLabel) continue;
    sum += weights[j] * WrapToPi(psi[j] - *offset - multiple[label[j]] * step);
    total += weights[j];
  }
  *offset = WrapToPi(*offset + sum / total);
  for (int c = 0; c < num_clusters; ++c) {
    (*theta)[c] = WrapToPi(multiple[c] * step);
  }
  return true;
}

void AssembleDiscrete(const HypothesisSet& set,
                      const Pass& pass,
                      int r,
                      const ClassPrior* prior,
                      double prior_snap_angle,
                      CategorizedDetection* out) {
  const int n = set.size();
  const ModeAngles modes = MeanModeAngles(set, pass);
  const int num_clusters = static_cast<int>(modes.mean.size());
  const int c_ref = modes.label[r];
  double offset = modes.mean[c_ref];  // twist of R_base relative to R_ref
  std::vector<double> theta(num_clusters);
  for (int c = 0; c < num_clusters; ++c) {
    theta[c] = WrapToPi(modes.mean[c] - offset);
  }
  theta[c_ref] = 0.0;
  out->diagnostics.prior_order_snapped =
      prior != nullptr && prior->symmetry == SymmetryType::kDiscrete &&
      prior->order >= 2 &&
      SnapToOrder(prior->order,
                  prior_snap_angle,
                  modes.label,
                  pass.twists.psi,
                  set.w,
                  &offset,
                  &theta);

  const Eigen::Quaterniond q_base =
      (pass.twists.q_ref *
       Eigen::Quaterniond(Eigen::AngleAxisd(offset, pass.axis.axis_o)))
          .normalized();
  out->twist.resize(n);
  for (int j = 0; j < n; ++j) {
    out->twist[j] = WrapToPi(pass.twists.psi[j] - offset);
  }
  out->clusters.clear();
  for (int c : ClustersInOutputOrder(theta, c_ref)) {
    out->clusters.push_back(OutputCluster(
        modes.label, out->twist, set.w, c, theta[c], modes.weight[c]));
  }
  out->inliers.clear();
  for (int j = 0; j < n; ++j) {
    if (modes.label[j] != CircularDbscanResult::kNoiseLabel) {
      out->inliers.push_back(j);
    }
  }
  out->type = SymmetryType::kDiscrete;
  out->t_co = MeanTranslation(set, out->inliers);
  out->T_co_base = Rigid3d(q_base, out->t_co);
  out->axis_o = pass.axis.axis_o;
  out->axis_c = pass.axis.axis_c;
}

}  // namespace categorization
}  // namespace symba
