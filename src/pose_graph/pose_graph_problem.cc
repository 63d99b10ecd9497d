#include "pose_graph/pose_graph_problem.h"

#include <cmath>
#include <numeric>
#include <string>

#include "io/text_file.h"
#include "pose_graph/pose_graph_checks.h"

namespace symba::internal {
namespace {

Status CheckQuaternion(const Eigen::Quaterniond& q, const std::string& what) {
  const double norm = q.norm();
  if (!q.coeffs().allFinite() ||
      !(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    return Status::Error(what + ": quaternion norm " + Approx(norm) +
                         " is not within " + Approx(kQuaternionNormTolerance) +
                         " of 1");
  }
  return Status::Ok();
}

Status CheckPose(const Rigid3d& T, const std::string& what) {
  if (!T.t.allFinite()) {
    return Status::Error(what + ": translation is not finite");
  }
  return CheckQuaternion(T.q, what);
}

Rigid3d Normalized(const Rigid3d& T) { return Rigid3d(T.q.normalized(), T.t); }

// Disjoint sets over vertex indices (connected components of the edges).
class DisjointSets {
 public:
  explicit DisjointSets(int size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int Find(int i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void Union(int a, int b) { parent_[Find(a)] = Find(b); }

 private:
  std::vector<int> parent_;
};

// The vertex `id`'s dense index, added on its first appearance.
Status AddVertex(const PoseGraph& graph,
                 int64_t id,
                 PreparedPoseGraph* prepared,
                 int* index) {
  const auto found = prepared->index_of.find(id);
  if (found != prepared->index_of.end()) {
    *index = found->second;
    return Status::Ok();
  }
  const auto pose = graph.poses.find(id);
  if (pose == graph.poses.end()) {
    return Status::Error("vertex " + std::to_string(id) + " does not exist");
  }
  const Status check = CheckPose(pose->second, "vertex " + std::to_string(id));
  if (!check.ok()) return check;
  *index = static_cast<int>(prepared->ids.size());
  prepared->index_of.emplace(id, *index);
  prepared->ids.push_back(id);
  prepared->states.push_back(Normalized(pose->second));
  return Status::Ok();
}

Status PrepareEdge(const PoseGraph& graph,
                   size_t k,
                   PreparedPoseGraph* prepared,
                   PreparedPoseEdge* p) {
  const PoseGraphEdge& edge = graph.edges[k];
  const std::string what = "pose graph: edge " + std::to_string(k) + " (" +
                           std::to_string(edge.from) + " -> " +
                           std::to_string(edge.to) + ")";
  Status s = AddVertex(graph, edge.from, prepared, &p->a);
  if (!s.ok()) return Status::Error(what + ": " + s.message());
  s = AddVertex(graph, edge.to, prepared, &p->b);
  if (!s.ok()) return Status::Error(what + ": " + s.message());
  if (p->a == p->b) return Status::Error(what + ": from a vertex to itself");
  s = CheckPose(edge.T_ab, what + ": measurement");
  if (!s.ok()) return s;
  if (!edge.information.allFinite()) {
    return Status::Error(what + ": information is not finite");
  }
  // The factor reads the lower triangle; a programmatic graph might not be
  // symmetric, so insist on it.
  if (!edge.information.isApprox(edge.information.transpose(), 1e-12)) {
    return Status::Error(what + ": information is not symmetric");
  }
  if (!UpperCholeskyFactor(edge.information, &p->sqrt_info) ||
      !IsotropicInformation(edge.information, &p->isotropic)) {
    return Status::Error(what + ": " + NotPositiveDefinite(edge.information));
  }
  p->T_ab = Normalized(edge.T_ab);
  return Status::Ok();
}

// Gauge: FIX vertices, plus the smallest id of every component without one.
std::vector<bool> Gauge(const PoseGraph& graph,
                        const PreparedPoseGraph& prepared) {
  const int n = static_cast<int>(prepared.ids.size());
  DisjointSets components(n);
  for (const PreparedPoseEdge& p : prepared.edges) components.Union(p.a, p.b);
  std::vector<bool> constant(n, false);
  std::vector<bool> anchored(n, false);  // by component root
  for (int i = 0; i < n; ++i) {
    if (graph.fixed.count(prepared.ids[i]) != 0) {
      constant[i] = true;
      anchored[components.Find(i)] = true;
    }
  }
  std::vector<int> smallest(n, -1);  // by component root
  for (int i = 0; i < n; ++i) {
    int& best = smallest[components.Find(i)];
    if (best < 0 || prepared.ids[i] < prepared.ids[best]) best = i;
  }
  for (int root = 0; root < n; ++root) {
    if (smallest[root] >= 0 && !anchored[root]) constant[smallest[root]] = true;
  }
  return constant;
}

}  // namespace

Status PreparePoseGraph(const PoseGraph& graph, PreparedPoseGraph* prepared) {
  PreparedPoseGraph out;
  out.edges.reserve(graph.edges.size());
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    PreparedPoseEdge p;
    const Status s = PrepareEdge(graph, k, &out, &p);
    if (!s.ok()) return s;
    out.edges.push_back(p);
  }
  for (const int64_t id : graph.fixed) {
    if (graph.poses.count(id) == 0) {
      return Status::Error("pose graph: fixed vertex " + std::to_string(id) +
                           " does not exist");
    }
  }
  out.constant = Gauge(graph, out);
  *prepared = std::move(out);
  return Status::Ok();
}

namespace {

ceres::Problem::Options NotOwningManifolds() {
  ceres::Problem::Options options;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return options;
}

}  // namespace

PoseGraphProblem::PoseGraphProblem(PoseGraphRotationError rotation_error,
                                   PreparedPoseGraph* prepared)
    : problem_(NotOwningManifolds()) {
  for (const PreparedPoseEdge& p : prepared->edges) {
    Rigid3d& T_wa = prepared->states[p.a];
    Rigid3d& T_wb = prepared->states[p.b];
    edge_blocks_.push_back(problem_.AddResidualBlock(
        PoseGraphEdgeFactor::Create(p.T_ab, p.sqrt_info, rotation_error),
        nullptr,
        T_wa.q.coeffs().data(),
        T_wa.t.data(),
        T_wb.q.coeffs().data(),
        T_wb.t.data()));
  }
  for (size_t i = 0; i < prepared->states.size(); ++i) {
    double* q = prepared->states[i].q.coeffs().data();
    problem_.SetManifold(q, &quaternion_manifold_);
    if (prepared->constant[i]) {
      problem_.SetParameterBlockConstant(q);
      problem_.SetParameterBlockConstant(prepared->states[i].t.data());
    }
  }
}

}  // namespace symba::internal
