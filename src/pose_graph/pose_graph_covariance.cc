#include "symba/pose_graph/pose_graph_covariance.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <ceres/covariance.h>
#include <ceres/crs_matrix.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "pose_graph/pose_graph_problem.h"

namespace symba {
namespace {

// Ceres's quaternion tangent d moves R to Exp(2 d) R (left, world frame):
// the rotation vector is twice it.
constexpr double kRotationPerTangent = 2.0;

// A requested vertex's blocks, each null where the problem holds it.
struct FreeBlocks {
  const double* t = nullptr;
  const double* q = nullptr;
};

FreeBlocks FreeBlocksOf(const Rigid3d& T, ceres::Problem* problem) {
  FreeBlocks free;
  if (!problem->IsParameterBlockConstant(T.t.data())) free.t = T.t.data();
  if (!problem->IsParameterBlockConstant(T.q.coeffs().data())) {
    free.q = T.q.coeffs().data();
  }
  return free;
}

// Every pair of free blocks within each vertex, once (Ceres refuses a pair
// asked twice).
std::vector<std::pair<const double*, const double*>> Pairs(
    const std::vector<FreeBlocks>& vertices) {
  std::set<std::pair<const double*, const double*>> pairs;
  for (const FreeBlocks& v : vertices) {
    if (v.t != nullptr) pairs.emplace(v.t, v.t);
    if (v.q != nullptr) pairs.emplace(v.q, v.q);
    if (v.t != nullptr && v.q != nullptr) pairs.emplace(v.t, v.q);
  }
  return {pairs.begin(), pairs.end()};
}

// [t; w] from the tangent blocks; zero where a block is held.
Matrix6d VertexCovariance(const ceres::Covariance& covariance,
                          const FreeBlocks& v) {
  Matrix6d c = Matrix6d::Zero();
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
  if (v.t != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.t, v.t, block.data());
    c.topLeftCorner<3, 3>() = block;
  }
  if (v.q != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.q, v.q, block.data());
    c.bottomRightCorner<3, 3>() =
        kRotationPerTangent * kRotationPerTangent * block;
  }
  if (v.t != nullptr && v.q != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.t, v.q, block.data());
    c.topRightCorner<3, 3>() = kRotationPerTangent * block;
    c.bottomLeftCorner<3, 3>() = c.topRightCorner<3, 3>().transpose();
  }
  // Exactly symmetric (Ceres's round-off is not).
  return 0.5 * (c + c.transpose());
}

Status CheckNoiseFactors(const std::vector<EdgeNoiseFactors>& factors,
                         size_t edges) {
  if (factors.size() != edges) {
    return Status::Error(
        "pose graph covariance: " + std::to_string(factors.size()) +
        " noise factors for " + std::to_string(edges) + " edges");
  }
  for (size_t e = 0; e < factors.size(); ++e) {
    for (const double f : {factors[e].translation, factors[e].rotation}) {
      if (!(f > 0.0) || !std::isfinite(f)) {
        return Status::Error("pose graph covariance: edge " +
                             std::to_string(e) + "'s noise factor " +
                             std::to_string(f) + " is not finite and positive");
      }
    }
  }
  return Status::Ok();
}

// The free blocks' tangent columns: each free block of the problem (every
// vertex's t, then q) and where its columns start.
struct TangentColumns {
  std::vector<double*> blocks;
  std::map<const double*, int> start;
  int count = 0;
};

TangentColumns FreeColumns(internal::PreparedPoseGraph* prepared,
                           ceres::Problem* problem) {
  TangentColumns columns;
  for (Rigid3d& state : prepared->states) {
    for (double* block : {state.t.data(), state.q.coeffs().data()}) {
      if (problem->IsParameterBlockConstant(block)) continue;
      columns.blocks.push_back(block);
      columns.start[block] = columns.count;
      columns.count += 3;  // t is Euclidean, q's tangent has size 3
    }
  }
  return columns;
}

using SparseMatrix = Eigen::SparseMatrix<double>;

// The whitened Jacobian at the poses (rows: 6 per edge, in edge order;
// columns: the free blocks' tangents).
SparseMatrix WhitenedJacobian(const ceres::CRSMatrix& crs) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(crs.values.size());
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
      entries.emplace_back(row, crs.cols[k], crs.values[k]);
    }
  }
  SparseMatrix J(crs.num_rows, crs.num_cols);
  J.setFromTriplets(entries.begin(), entries.end());
  return J;
}

// sqrt(F) per whitened row: each edge's translation rows, then rotation.
Eigen::VectorXd RowFactors(const std::vector<EdgeNoiseFactors>& factors) {
  Eigen::VectorXd rows(6 * factors.size());
  for (size_t e = 0; e < factors.size(); ++e) {
    rows.segment<3>(6 * e).setConstant(std::sqrt(factors[e].translation));
    rows.segment<3>(6 * e + 3).setConstant(std::sqrt(factors[e].rotation));
  }
  return rows;
}

// Below this ratio of the smallest to the largest pivot of H's LDL^T the
// information is taken as rank deficient. The pivots lie between H's
// smallest and largest eigenvalues, so this catches a vertex its edges do
// not determine (a zero or negative pivot, or one at round-off) but not
// every ill-conditioned H; Ceres's sparse QR decides by the rank of R.
constexpr double kMinPivotRatio = 1e-14;

// H^-1 (J^T F J) H^-1 at each of `free` (a vertex's [t; w] block, zero
// where it is held).
Status SandwichCovariances(internal::PreparedPoseGraph* prepared,
                           internal::PoseGraphProblem* pose_graph_problem,
                           const std::vector<FreeBlocks>& free,
                           const std::vector<EdgeNoiseFactors>& factors,
                           std::vector<Matrix6d>* out) {
  ceres::Problem* problem = &pose_graph_problem->problem();
  const TangentColumns columns = FreeColumns(prepared, problem);
  const bool none_free =
      std::all_of(free.begin(), free.end(), [](const FreeBlocks& v) {
        return v.t == nullptr && v.q == nullptr;
      });
  if (columns.count == 0 || none_free) {  // what is held is known
    out->assign(free.size(), Matrix6d::Zero());
    return Status::Ok();
  }
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = columns.blocks;
  evaluate.residual_blocks = pose_graph_problem->edge_blocks();  // edge order
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(evaluate, nullptr, nullptr, nullptr, &crs) ||
      crs.num_rows != 6 * static_cast<int>(factors.size()) ||
      crs.num_cols != columns.count) {
    return Status::Error(
        "pose graph covariance: the Jacobian could not be evaluated");
  }
  const SparseMatrix J = WhitenedJacobian(crs);
  const SparseMatrix JF = RowFactors(factors).asDiagonal() * J;
  const SparseMatrix H = SparseMatrix(J.transpose()) * J;
  const Eigen::SimplicialLDLT<SparseMatrix> ldlt(H);
  const Eigen::VectorXd pivots = ldlt.vectorD();
  if (ldlt.info() != Eigen::Success || pivots.size() == 0 ||
      !(pivots.minCoeff() > kMinPivotRatio * pivots.maxCoeff())) {
    return Status::Error(
        "pose graph covariance: the information is rank deficient (a vertex "
        "is not determined by its edges)");
  }
  std::vector<Matrix6d> covariances;
  covariances.reserve(free.size());
  for (const FreeBlocks& v : free) {
    // E picks the vertex's [t; w] out of the tangent (w = 2 d).
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(columns.count, 6);
    if (v.t != nullptr) {
      E.block<3, 3>(columns.start.at(v.t), 0).setIdentity();
    }
    if (v.q != nullptr) {
      E.block<3, 3>(columns.start.at(v.q), 3) =
          kRotationPerTangent * Eigen::Matrix3d::Identity();
    }
    const Eigen::MatrixXd X = ldlt.solve(E);  // H^-1 E
    const Eigen::MatrixXd Y = JF * X;         // sqrt(F) J H^-1 E
    const Matrix6d c = Y.transpose() * Y;
    covariances.push_back(0.5 * (c + c.transpose()));
  }
  *out = std::move(covariances);
  return Status::Ok();
}

}  // namespace

Status PoseGraphCovariances(const PoseGraph& graph,
                            const std::vector<int64_t>& vertices,
                            const PoseGraphCovarianceOptions& options,
                            std::vector<Matrix6d>* covariances) {
  if (options.num_threads < 1) {
    return Status::Error("pose graph covariance: num_threads = " +
                         std::to_string(options.num_threads) + " is below 1");
  }
  if (!options.noise_factors.empty()) {
    const Status s =
        CheckNoiseFactors(options.noise_factors, graph.edges.size());
    if (!s.ok()) return s;
  }
  internal::PreparedPoseGraph prepared;
  const Status s = internal::PreparePoseGraph(graph, &prepared);
  if (!s.ok()) return s;
  for (const int64_t id : vertices) {
    if (prepared.index_of.count(id) == 0) {
      return Status::Error("pose graph covariance: vertex " +
                           std::to_string(id) + " has no edge");
    }
  }

  internal::PoseGraphProblem pose_graph_problem(options.rotation_error,
                                                &prepared);
  ceres::Problem& problem = pose_graph_problem.problem();
  for (const int64_t id : options.rotation_held) {
    const auto found = prepared.index_of.find(id);
    if (found == prepared.index_of.end()) continue;
    problem.SetParameterBlockConstant(
        prepared.states[found->second].q.coeffs().data());
  }

  std::vector<FreeBlocks> free;
  free.reserve(vertices.size());
  for (const int64_t id : vertices) {
    free.push_back(
        FreeBlocksOf(prepared.states[prepared.index_of.at(id)], &problem));
  }
  if (!options.noise_factors.empty()) {
    return SandwichCovariances(&prepared,
                               &pose_graph_problem,
                               free,
                               options.noise_factors,
                               covariances);
  }
  const std::vector<std::pair<const double*, const double*>> pairs =
      Pairs(free);
  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = options.num_threads;
  ceres::Covariance covariance(covariance_options);
  if (!pairs.empty() && !covariance.Compute(pairs, &problem)) {
    return Status::Error(
        "pose graph covariance: the information is rank deficient (a vertex "
        "is not determined by its edges)");
  }
  std::vector<Matrix6d> out;
  out.reserve(free.size());
  for (const FreeBlocks& v : free)
    out.push_back(VertexCovariance(covariance, v));
  *covariances = std::move(out);
  return Status::Ok();
}

}  // namespace symba
