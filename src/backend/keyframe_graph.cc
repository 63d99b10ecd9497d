#include "backend/keyframe_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "backend/motion_claims.h"
#include "symba/geometry/swing_twist.h"

namespace symba::internal {

StepSigmas StepSigmasOf(const KeyframeState& kf) {
  // Information 1 / variance, finite and positive (a huge or tiny stated
  // sigma counts as unstated).
  auto usable = [](double variance) {
    return variance > 0.0 && std::isfinite(variance) &&
           std::isfinite(1.0 / variance);
  };
  StepSigmas sigmas;
  if (usable(kf.motion_variance_t) && usable(kf.motion_variance_r)) {
    sigmas.t = std::sqrt(kf.motion_variance_t);
    sigmas.r = std::sqrt(kf.motion_variance_r);
  }
  return sigmas;
}
namespace {

Matrix6d DiagonalInformation(double sigma_t, double sigma_r) {
  Matrix6d information = Matrix6d::Zero();
  information.topLeftCorner<3, 3>().diagonal().setConstant(1.0 /
                                                           (sigma_t * sigma_t));
  information.bottomRightCorner<3, 3>().diagonal().setConstant(
      1.0 / (sigma_r * sigma_r));
  return information;
}

// A camera step's role: its group the quarter octaves of its sigmas (a
// front end that knows when it has features says so), named by the first
// step's sigmas in `names`; held by the map points its keyframes shared
// (`from_previous`: the step is from k - 1); measured unless the window's
// estimate is its measurement.
GraphEdgeRole StepRole(const KeyframeState& kf,
                       const StepSigmas& sigmas,
                       bool from_previous,
                       bool in_window,
                       std::map<StatedSigmasKey, std::string>* names) {
  char name[96];
  std::snprintf(
      name, sizeof name, "motion %.3g m %.3g rad", sigmas.t, sigmas.r);
  const std::string& group =
      names->try_emplace(StatedSigmasKeyOf(sigmas.t, sigmas.r), name)
          .first->second;
  GraphEdgeRole role;
  role.held_by_others =
      from_previous && kf.points_shared_with_previous >= kMinSharedPoints;
  role.group =
      group + (role.held_by_others ? ", shared points" : ", no shared points");
  role.measured = !in_window;
  return role;
}

}  // namespace

Rigid3d AxisEdgeMeasurement(const Rigid3d& T_wc,
                            const Rigid3d& T_wo,
                            const Eigen::Vector3d& axis_w,
                            const Eigen::Vector3d& axis_c,
                            const Eigen::Vector3d& t_co_measured) {
  const Eigen::Quaterniond q_co = (T_wc.q.inverse() * T_wo.q).normalized();
  const Eigen::Vector3d predicted = T_wc.q.inverse() * axis_w.normalized();
  const Eigen::Quaterniond turn =
      MinimalRotation(predicted, Eigen::Vector3d(axis_c.normalized()));
  return Rigid3d((turn * q_co).normalized(), t_co_measured);
}

Eigen::Matrix3d AxisInformation(const Eigen::Vector3d& a_o,
                                double information) {
  const Eigen::Vector3d a = a_o.normalized();
  const Eigen::Matrix3d along = a * a.transpose();
  return information * (Eigen::Matrix3d::Identity() - along) +
         kAxisTurnInformation * along;
}

ChainStep MeasuredStep(const KeyframeList& keyframes, int k, int window_begin) {
  ChainStep step;
  if (k - 1 >= window_begin) {
    step.from = k - 1;
    step.T =
        Normalized(keyframes[k - 1]->T_wc().Inverse() * keyframes[k]->T_wc());
    return step;
  }
  // The motion factor's own keyframe: chained through k - 1 instead, a
  // front-end step after odometry-only keyframes would carry their
  // odometry's error with the front end's weight.
  const int from = keyframes[k]->motion_from;
  step.from = from >= 0 && from < k ? from : k - 1;
  step.T = Normalized(keyframes[step.from]->T_wc_chain.Inverse() *
                      keyframes[k]->T_wc_chain);
  return step;
}

PoseGraph MakeKeyframeGraph(const KeyframeList& keyframes,
                            int window_begin,
                            const std::vector<LoopConstraint>& loops,
                            const std::vector<GraphObject>& objects,
                            std::vector<GraphEdgeRole>* roles) {
  std::vector<GraphEdgeRole> edge_roles;
  std::map<StatedSigmasKey, std::string> step_groups;
  PoseGraph graph;
  const int n = static_cast<int>(keyframes.size());
  for (int k = 0; k < n; ++k) {
    graph.poses.emplace(k, Normalized(keyframes[k]->T_wc()));
  }
  graph.fixed.insert(0);
  for (int k = 1; k < n; ++k) {
    const StepSigmas sigmas = StepSigmasOf(*keyframes[k]);
    const ChainStep step = MeasuredStep(keyframes, k, window_begin);
    PoseGraphEdge edge;
    edge.from = step.from;
    edge.to = k;
    edge.T_ab = step.T;
    edge.information = DiagonalInformation(sigmas.t, sigmas.r);
    graph.edges.push_back(std::move(edge));
    if (roles != nullptr) {
      edge_roles.push_back(StepRole(*keyframes[k],
                                    sigmas,
                                    step.from == k - 1,
                                    k - 1 >= window_begin,
                                    &step_groups));
      if (k >= 2) edge_roles.back().previous = k - 2;
    }
  }
  for (const LoopConstraint& loop : loops) {
    PoseGraphEdge edge;
    edge.from = loop.earlier;
    edge.to = loop.later;
    edge.T_ab = Normalized(loop.T);
    edge.information = DiagonalInformation(loop.sigma_t, loop.sigma_r);
    graph.edges.push_back(std::move(edge));
    if (roles != nullptr) edge_roles.emplace_back();  // as stated
  }
  for (size_t o = 0; o < objects.size(); ++o) {
    const GraphObject& object = objects[o];
    const int count = static_cast<int>(object.keyframes.size());
    if (count == 0) continue;
    const int64_t vertex = n + static_cast<int64_t>(o);
    graph.poses.emplace(vertex, Normalized(object.T_wo));
    if (object.fixed) graph.fixed.insert(vertex);
    const int edges = std::min(count, kMaxObjectEdges);
    const double weight = static_cast<double>(count) / edges;
    Matrix6d information = Matrix6d::Zero();
    information.topLeftCorner<3, 3>().diagonal().setConstant(
        weight / (object.sigma_t * object.sigma_t));
    information.bottomRightCorner<3, 3>().diagonal().setConstant(
        object.rotation ? weight / (object.sigma_r * object.sigma_r)
                        : kSymmetricRotationInformation);
    const Rigid3d& T_wo = graph.poses.at(vertex);
    const Eigen::Matrix3d axis_information =
        object.HasAxis()
            ? AxisInformation(T_wo.q.inverse() * object.axis_w,
                              weight / (object.sigma_axis * object.sigma_axis))
            : Eigen::Matrix3d::Zero();
    GraphEdgeRole role;
    role.held_by_others = object.noise_stated && count >= kMinHeldViews;
    role.group = "detections " + object.class_name +
                 (!object.noise_stated    ? ", unstated noise"
                  : count < kMinHeldViews ? ", few views"
                                          : "");
    role.measured = !object.measured.empty();
    role.weight = weight;
    role.rotation_dof = object.rotation ? 3 : (object.HasAxis() ? 2 : 0);
    for (int e = 0; e < edges; ++e) {
      if (roles != nullptr) {
        role.previous = e > 0 ? static_cast<int>(graph.edges.size()) - 1 : -1;
        edge_roles.push_back(role);
      }
      // Spread over the detections, the first and the last among them.
      const int i = edges == 1 ? count - 1
                               : static_cast<int>(static_cast<int64_t>(e) *
                                                  (count - 1) / (edges - 1));
      const int k = object.keyframes[i];
      PoseGraphEdge edge;
      edge.from = k;
      edge.to = vertex;
      edge.T_ab = object.measured.empty()
                      ? Normalized(graph.poses.at(k).Inverse() * object.T_wo)
                      : Normalized(object.measured[i]);
      edge.information = information;
      if (object.HasAxis()) {
        edge.T_ab = Normalized(AxisEdgeMeasurement(graph.poses.at(k),
                                                   T_wo,
                                                   object.axis_w,
                                                   object.measured_axes[i],
                                                   edge.T_ab.t));
        edge.information.bottomRightCorner<3, 3>() = axis_information;
      }
      graph.edges.push_back(std::move(edge));
    }
  }
  if (roles != nullptr) *roles = std::move(edge_roles);
  return graph;
}

Status OptimizeKeyframeGraph(const KeyframeList& keyframes,
                             int window_begin,
                             const std::vector<LoopConstraint>& loops,
                             const std::vector<GraphObject>& objects,
                             std::vector<Rigid3d>* keyframe_poses,
                             std::vector<Rigid3d>* object_poses,
                             PoseGraphSolveSummary* summary) {
  PoseGraph graph = MakeKeyframeGraph(keyframes, window_begin, loops, objects);
  // From the current estimates, not the chordal relaxation: the estimates
  // are what the window's solves made of the objects and points, and the
  // relaxation, which sees the rotations first, has only the motion's
  // loose rotations where the camera saw no asymmetric object (on the long
  // scene it folded a featureless stretch by 13 m; docs/loop-closure.md).
  PoseGraphSolveOptions options;
  options.initialization = PoseGraphInitialization::kGiven;
  Status status = OptimizePoseGraph(options, &graph, summary);
  if (!status.ok()) return status;
  const int64_t n = static_cast<int64_t>(keyframes.size());
  keyframe_poses->clear();
  for (int64_t k = 0; k < n; ++k) keyframe_poses->push_back(graph.poses.at(k));
  object_poses->clear();
  for (size_t o = 0; o < objects.size(); ++o) {
    const auto it = graph.poses.find(n + static_cast<int64_t>(o));
    object_poses->push_back(it != graph.poses.end() ? it->second
                                                    : objects[o].T_wo);
  }
  return Status::Ok();
}

Rigid3d MeanMove(const std::vector<Rigid3d>& moves,
                 const std::vector<int>& keyframes,
                 const Eigen::Vector3d& p) {
  Eigen::Vector4d q_sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d p_sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int k : keyframes) {
    if (k < 0) continue;
    const Eigen::Quaterniond q = moves[k].q.normalized();
    // q and -q are one rotation: the hemisphere of the first.
    const double sign = count > 0 && q.coeffs().dot(q_sum) < 0.0 ? -1.0 : 1.0;
    q_sum += sign * q.coeffs();
    p_sum += moves[k] * p;
    ++count;
  }
  if (count == 0) return Rigid3d();
  const Eigen::Quaterniond q = Eigen::Quaterniond(q_sum).normalized();
  return Rigid3d(q, p_sum / count - q * p);
}

PoseGraphCovarianceOptions KeyframeGraphCovarianceOptions(
    int num_keyframes, const std::vector<GraphObject>& objects) {
  PoseGraphCovarianceOptions options;
  for (size_t o = 0; o < objects.size(); ++o) {
    if (!objects[o].keyframes.empty() && !objects[o].rotation &&
        !objects[o].HasAxis()) {
      options.rotation_held.insert(num_keyframes + static_cast<int64_t>(o));
    }
  }
  return options;
}

}  // namespace symba::internal
