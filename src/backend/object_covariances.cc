// Each map object's covariance (object_covariances.h).
#include "backend/object_covariances.h"

#include <algorithm>
#include <map>
#include <optional>
#include <utility>

#include <Eigen/Eigenvalues>

#include "symba/factors/marginal_prior_factor.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/tangent_basis.h"
#include "symba/pose_graph/pose_graph_covariance.h"

namespace symba::internal {
namespace {

// The object's blocks: t_wo, then q_wo (asymmetric) or a_w and the angles.
std::vector<const double*> ObjectBlocks(const ObjectState& object) {
  std::vector<const double*> blocks = {object.t};
  if (object.type == SymmetryType::kAsymmetric) {
    blocks.push_back(object.q);
    return blocks;
  }
  blocks.push_back(object.a_w);
  if (object.type == SymmetryType::kDiscrete) {
    for (const auto& theta : object.thetas) blocks.push_back(theta.get());
  }
  return blocks;
}

int TangentSize(const ObjectState& object, const double* block) {
  if (block == object.t) return 3;
  if (block == object.q) return 3;
  if (block == object.a_w) return 2;
  return 1;
}

// Reads the covariance (tangent, blocks in `blocks` order) into the
// report; `axis_at` is where the axis tangent's basis is taken. False
// without the position.
bool Report(const ObjectState& object,
            const std::vector<const double*>& blocks,
            const Eigen::MatrixXd& unsymmetric,
            const Eigen::Vector3d& axis_at,
            MapObjectCovariance* report) {
  if (std::find(blocks.begin(), blocks.end(), object.t) == blocks.end()) {
    return false;
  }
  // Exactly symmetric (Ceres' and the inverse's round-off is not).
  const Eigen::MatrixXd c = 0.5 * (unsymmetric + unsymmetric.transpose());
  report->angle_variances.assign(object.thetas.size(), std::nullopt);
  int offset = 0;
  for (const double* block : blocks) {
    const int size = TangentSize(object, block);
    if (block == object.t) {
      report->position = c.block<3, 3>(offset, offset);
    } else if (block == object.q) {
      report->rotation = 4.0 * c.block<3, 3>(offset, offset);
    } else if (block == object.a_w) {
      const Eigen::Matrix<double, 3, 2> B =
          TangentBasis(Eigen::Vector3d(axis_at.normalized()));
      report->axis = B * c.block<2, 2>(offset, offset) * B.transpose();
    } else {
      for (size_t i = 0; i < object.thetas.size(); ++i) {
        if (object.thetas[i].get() == block) {
          report->angle_variances[i] = c(offset, offset);
        }
      }
    }
    offset += size;
  }
  return true;
}

// The covariance the object's own prior holds: (A^T A)^-1, if it is
// positive definite.
bool FromPrior(const ObjectState& object,
               const FactorGraph& graph,
               MapObjectCovariance* report) {
  if (object.prior_factor < 0) return false;
  const FactorRecord& record = graph.factor(object.prior_factor);
  const auto* prior =
      dynamic_cast<const MarginalPriorFactor*>(record.cost.get());
  if (prior == nullptr) return false;
  const Eigen::MatrixXd information = prior->Information();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(information);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  if (eigen.info() != Eigen::Success || !(values.minCoeff() > 0.0) ||
      values.minCoeff() < 1e-12 * values.maxCoeff()) {
    return false;
  }
  const Eigen::MatrixXd covariance = eigen.eigenvectors() *
                                     values.cwiseInverse().asDiagonal() *
                                     eigen.eigenvectors().transpose();
  Eigen::Vector3d axis_at = object.axis_w();
  std::vector<const double*> blocks;
  for (size_t b = 0; b < record.blocks.size(); ++b) {
    blocks.push_back(record.blocks[b]);
    if (record.blocks[b] == object.a_w) axis_at = prior->blocks()[b].x0;
  }
  report->source = MapObjectCovariance::Source::kPrior;
  return Report(object, blocks, covariance, axis_at, report);
}

}  // namespace

Status ObjectCovariances(const ObjectList& objects,
                         FactorGraph* graph,
                         std::vector<MapObjectCovariance>* covariances) {
  std::vector<int> confirmed;
  std::vector<std::vector<const double*>> sets;
  for (size_t o = 0; o < objects.size(); ++o) {
    if (objects[o]->status != ObjectStatus::kConfirmed) continue;
    confirmed.push_back(static_cast<int>(o));
    sets.push_back(ObjectBlocks(*objects[o]));
  }
  std::vector<WindowProblem::BlockCovariance> solved;
  if (!graph->SolveCovariances(sets, &solved)) {
    return Status::Error(
        "the covariance of the last solve cannot be computed (its problem "
        "is rank deficient)");
  }
  covariances->clear();
  for (size_t s = 0; s < confirmed.size(); ++s) {
    const ObjectState& object = *objects[confirmed[s]];
    MapObjectCovariance report;
    report.id = object.id;
    const bool ok = Report(object,
                           solved[s].blocks,
                           solved[s].covariance,
                           object.axis_w(),
                           &report) ||
                    FromPrior(object, *graph, &report);
    if (ok) covariances->push_back(std::move(report));
  }
  return Status::Ok();
}

Status InWorldFrame(const PoseGraph& graph,
                    int num_keyframes,
                    const std::vector<GraphObject>& objects,
                    const ObjectList& states,
                    const PoseGraphCovarianceOptions& options,
                    std::vector<MapObjectCovariance>* covariances) {
  std::vector<int64_t> vertices;
  std::vector<int> vertex_object;
  for (size_t o = 0; o < objects.size(); ++o) {
    if (objects[o].keyframes.empty()) continue;
    vertices.push_back(num_keyframes + static_cast<int64_t>(o));
    vertex_object.push_back(static_cast<int>(o));
  }
  std::vector<Matrix6d> marginals;
  const Status status =
      PoseGraphCovariances(graph, vertices, options, &marginals);
  if (!status.ok()) return status;

  std::map<ObjectId, MapObjectCovariance> reports;
  for (MapObjectCovariance& report : *covariances) {
    reports.emplace(report.id, std::move(report));
  }
  for (size_t v = 0; v < vertices.size(); ++v) {
    const GraphObject& g = objects[vertex_object[v]];
    const ObjectState& object = *states[vertex_object[v]];
    MapObjectCovariance& report = reports[object.id];
    if (report.angle_variances.size() != object.thetas.size()) {
      report.angle_variances.assign(object.thetas.size(), std::nullopt);
    }
    report.id = object.id;
    report.source = MapObjectCovariance::Source::kKeyframeGraph;
    report.position = marginals[v].topLeftCorner<3, 3>();
    const Eigen::Matrix3d rotation = marginals[v].bottomRightCorner<3, 3>();
    if (g.rotation) {
      report.rotation = rotation;
    } else if (g.HasAxis()) {
      const Eigen::Matrix3d A = Hat(Eigen::Vector3d(object.axis_w()));
      report.axis = A * rotation * A.transpose();
    }
  }
  std::vector<MapObjectCovariance> out;
  for (const auto& object : states) {
    const auto found = reports.find(object->id);
    if (found != reports.end()) out.push_back(std::move(found->second));
  }
  *covariances = std::move(out);
  return Status::Ok();
}

}  // namespace symba::internal
