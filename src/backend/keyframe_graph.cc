#include "backend/keyframe_graph.h"

#include <cmath>
#include <utility>

namespace symba::internal {
namespace {

Matrix6d IsotropicInformation(double sigma_t, double sigma_r) {
  Matrix6d information = Matrix6d::Zero();
  information.topLeftCorner<3, 3>().diagonal().setConstant(1.0 /
                                                           (sigma_t * sigma_t));
  information.bottomRightCorner<3, 3>().diagonal().setConstant(
      1.0 / (sigma_r * sigma_r));
  return information;
}

}  // namespace

PoseGraph MakeKeyframeGraph(const KeyframeList& keyframes,
                            const std::vector<LoopConstraint>& loops) {
  PoseGraph graph;
  const int n = static_cast<int>(keyframes.size());
  for (int k = 0; k < n; ++k) {
    graph.poses.emplace(k, Normalized(keyframes[k]->T_wc()));
  }
  graph.fixed.insert(0);
  for (int k = 1; k < n; ++k) {
    const KeyframeState& kf = *keyframes[k];
    const bool stated =
        kf.motion_variance_t > 0.0 && kf.motion_variance_r > 0.0;
    PoseGraphEdge edge;
    edge.from = k - 1;
    edge.to = k;
    edge.T_ab = Normalized(graph.poses.at(k - 1).Inverse() * graph.poses.at(k));
    edge.information =
        stated ? IsotropicInformation(std::sqrt(kf.motion_variance_t),
                                      std::sqrt(kf.motion_variance_r))
               : IsotropicInformation(kUnstatedMotionSigmaT,
                                      kUnstatedMotionSigmaR);
    graph.edges.push_back(std::move(edge));
  }
  for (const LoopConstraint& loop : loops) {
    PoseGraphEdge edge;
    edge.from = loop.earlier;
    edge.to = loop.later;
    edge.T_ab = Normalized(loop.T);
    edge.information = IsotropicInformation(loop.sigma_t, loop.sigma_r);
    graph.edges.push_back(std::move(edge));
  }
  return graph;
}

Status OptimizeKeyframeGraph(const KeyframeList& keyframes,
                             const std::vector<LoopConstraint>& loops,
                             std::vector<Rigid3d>* corrected,
                             PoseGraphSolveSummary* summary) {
  PoseGraph graph = MakeKeyframeGraph(keyframes, loops);
  PoseGraphSolveOptions options;
  Status status = OptimizePoseGraph(options, &graph, summary);
  if (!status.ok()) return status;
  corrected->clear();
  corrected->reserve(graph.poses.size());
  for (const auto& [k, T_wc] : graph.poses) corrected->push_back(T_wc);
  return Status::Ok();
}

}  // namespace symba::internal
