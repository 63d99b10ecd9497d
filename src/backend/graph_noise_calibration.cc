#include "backend/graph_noise_calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <Eigen/Cholesky>

#include "symba/factors/pose_graph_edge.h"

namespace symba::internal {
namespace {

// The whitened error of one 3-row part: L^T e with Omega_part = L L^T, so
// that |w|^2 = e^T Omega_part e.
Eigen::Vector3d Whitened(const Eigen::Matrix3d& information,
                         const Eigen::Vector3d& e) {
  const Eigen::LLT<Eigen::Matrix3d> llt(information);
  return llt.matrixU() * e;
}

// Sums over one group's measured residuals for one part of them (the
// translation rows or the rotation rows).
struct PartSums {
  double squared = 0.0;  // sum |r_i|^2
  double dof = 0.0;      // sum d_i
  // Over the edges with a predecessor p in their chain: sum r_i . r_p,
  // sum |r_i|^2 and sum |r_p|^2.
  double cross = 0.0;
  double squared_with_predecessor = 0.0;
  double predecessor_squared = 0.0;

  double Mean() const { return dof > 0.0 ? squared / dof : 0.0; }
  double Correlation() const {
    if (!(squared_with_predecessor > 0.0) || !(predecessor_squared > 0.0)) {
      return 0.0;
    }
    return std::clamp(
        cross / std::sqrt(squared_with_predecessor * predecessor_squared),
        0.0,
        kMaxCorrelation);
  }
  void Add(const Eigen::Vector3d& r,
           int dof_r,
           const Eigen::Vector3d* predecessor) {
    squared += r.squaredNorm();
    dof += dof_r;
    if (predecessor == nullptr) return;
    cross += r.dot(*predecessor);
    squared_with_predecessor += r.squaredNorm();
    predecessor_squared += predecessor->squaredNorm();
  }
};

struct GroupSums {
  int edges = 0;
  int residuals = 0;
  bool held_by_others = false;
  PartSums translation;
  PartSums rotation;
};

// The factor a group's part gets (see the header).
double Factor(const PartSums& part, bool held_by_others) {
  const double f = part.Mean() * PersistenceVarianceFactor(part.Correlation());
  return held_by_others ? std::max(kMinVarianceFactor, f) : std::max(1.0, f);
}

}  // namespace

void CalibrateGraphNoise(const PoseGraph& graph,
                         const std::vector<GraphEdgeRole>& roles,
                         std::vector<EdgeNoiseFactors>* factors,
                         std::vector<CovarianceNoiseGroup>* groups) {
  const size_t n = graph.edges.size();
  if (roles.size() != n) {  // no roles to go by: every edge as stated
    factors->assign(n, EdgeNoiseFactors());
    groups->clear();
    return;
  }
  std::map<std::string, GroupSums> sums;
  // Each measured edge's whitened residual parts, for its successor.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> whitened(n);
  std::vector<bool> has_residual(n, false);
  for (size_t i = 0; i < n; ++i) {
    const GraphEdgeRole& role = roles[i];
    if (role.group.empty()) continue;
    GroupSums& group = sums[role.group];
    ++group.edges;
    group.held_by_others = role.held_by_others;
    if (!role.measured || !(role.weight > 0.0)) continue;
    const PoseGraphEdge& edge = graph.edges[i];
    const Vector6<double> e = PoseGraphEdgeError(
        graph.poses.at(edge.from),
        graph.poses.at(edge.to),
        edge.T_ab.Inverse(),
        RotationErrorScale(PoseGraphRotationError::kRadians));
    const double scale = 1.0 / std::sqrt(role.weight);
    whitened[i].first =
        scale * Whitened(edge.information.topLeftCorner<3, 3>(), e.head<3>());
    whitened[i].second =
        scale *
        Whitened(edge.information.bottomRightCorner<3, 3>(), e.tail<3>());
    has_residual[i] =
        whitened[i].first.allFinite() && whitened[i].second.allFinite();
    if (!has_residual[i]) continue;
    const int p = role.previous;
    const bool chained = p >= 0 && static_cast<size_t>(p) < i &&
                         has_residual[p] && roles[p].group == role.group;
    ++group.residuals;
    group.translation.Add(
        whitened[i].first, 3, chained ? &whitened[p].first : nullptr);
    if (role.rotation_dof > 0) {
      group.rotation.Add(whitened[i].second,
                         role.rotation_dof,
                         chained ? &whitened[p].second : nullptr);
    }
  }

  std::map<std::string, EdgeNoiseFactors> by_group;
  std::vector<CovarianceNoiseGroup> reports;
  for (const auto& [name, group] : sums) {
    CovarianceNoiseGroup report;
    report.name = name;
    report.edges = group.edges;
    report.residuals = group.residuals;
    report.held_by_others = group.held_by_others;
    report.residual_t = group.translation.Mean();
    report.residual_r = group.rotation.Mean();
    report.correlation_t = group.translation.Correlation();
    report.correlation_r = group.rotation.Correlation();
    if (group.residuals >= kMinGroupResiduals) {
      report.factor_t = Factor(group.translation, group.held_by_others);
      if (group.rotation.dof > 0.0) {
        report.factor_r = Factor(group.rotation, group.held_by_others);
      }
    }
    by_group[name] = {report.factor_t, report.factor_r};
    reports.push_back(std::move(report));
  }
  std::vector<EdgeNoiseFactors> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (roles[i].group.empty()) continue;
    out[i] = by_group.at(roles[i].group);
    // Rotation rows that measure nothing (a regulariser) stay as they are.
    if (roles[i].rotation_dof == 0) out[i].rotation = 1.0;
  }
  *factors = std::move(out);
  *groups = std::move(reports);
}

}  // namespace symba::internal
