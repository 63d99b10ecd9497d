#include "symba/pose_graph/chordal_initialization.h"

#include <numeric>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace symba {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Adds w * B to the block (row, col) of size n x n (block indices).
void AddBlock(int row,
              int col,
              int n,
              const Eigen::MatrixXd& B,
              double w,
              Triplets* triplets) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (B(i, j) != 0.0) {
        triplets->emplace_back(n * row + i, n * col + j, w * B(i, j));
      }
    }
  }
}

// Solves H X = rhs (H symmetric positive definite); false if it is not.
bool SolveNormalEquations(int size,
                          const Triplets& triplets,
                          const Eigen::MatrixXd& rhs,
                          Eigen::MatrixXd* x) {
  Eigen::SparseMatrix<double> H(size, size);
  H.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
  if (solver.info() != Eigen::Success) return false;
  *x = solver.solve(rhs);
  return solver.info() == Eigen::Success && x->allFinite();
}

// Dense indices of the free vertices: not held, with an edge (-1 for the
// others, which keep their poses).
std::vector<int> FreeIndices(const std::vector<ChordalEdge>& edges,
                             const std::vector<bool>& held,
                             int* count) {
  std::vector<bool> linked(held.size(), false);
  for (const ChordalEdge& e : edges) linked[e.a] = linked[e.b] = true;
  std::vector<int> index(held.size(), -1);
  *count = 0;
  for (size_t v = 0; v < held.size(); ++v) {
    if (linked[v] && !held[v]) index[v] = (*count)++;
  }
  return index;
}

// Whether every connected component of the edges holds a vertex (else the
// systems are singular: the component could move as a whole).
bool EveryComponentHeld(const std::vector<ChordalEdge>& edges,
                        const std::vector<bool>& held) {
  std::vector<int> parent(held.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const ChordalEdge& e : edges) parent[find(e.a)] = find(e.b);
  std::vector<bool> anchored(held.size(), false);
  for (size_t v = 0; v < held.size(); ++v) {
    if (held[v]) anchored[find(static_cast<int>(v))] = true;
  }
  for (const ChordalEdge& e : edges) {
    if (!anchored[find(e.a)]) return false;
  }
  return true;
}

Eigen::Matrix3d ProjectToSO3(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0
                ? -1.0
                : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// Row r of every M_v stacked: residual u_b - R_ab^T u_a per edge.
bool ChordalRotations(const std::vector<ChordalEdge>& edges,
                      const std::vector<bool>& held,
                      const std::vector<Rigid3d>& poses,
                      std::vector<Eigen::Matrix3d>* rotations) {
  int free = 0;
  const std::vector<int> index = FreeIndices(edges, held, &free);
  Triplets triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(3 * free, 3);  // column r
  const Eigen::MatrixXd I = Eigen::Matrix3d::Identity();
  for (const ChordalEdge& e : edges) {
    const Eigen::Matrix3d R_ab = e.T_ab.q.toRotationMatrix();
    const int a = index[e.a];
    const int b = index[e.b];
    if (a >= 0) AddBlock(a, a, 3, I, e.kappa, &triplets);
    if (b >= 0) AddBlock(b, b, 3, I, e.kappa, &triplets);
    if (a >= 0 && b >= 0) {
      AddBlock(a, b, 3, -R_ab, e.kappa, &triplets);
      AddBlock(b, a, 3, -R_ab.transpose(), e.kappa, &triplets);
    } else if (a >= 0) {  // b held: u_a's target R_ab u_b
      const Eigen::Matrix3d M_b = poses[e.b].q.toRotationMatrix();
      rhs.block<3, 3>(3 * a, 0) += e.kappa * R_ab * M_b.transpose();
    } else if (b >= 0) {  // a held: u_b's target R_ab^T u_a
      const Eigen::Matrix3d M_a = poses[e.a].q.toRotationMatrix();
      rhs.block<3, 3>(3 * b, 0) += e.kappa * R_ab.transpose() * M_a.transpose();
    }
  }
  Eigen::MatrixXd x;
  if (free > 0 && !SolveNormalEquations(3 * free, triplets, rhs, &x)) {
    return false;
  }
  rotations->resize(poses.size());
  for (size_t v = 0; v < poses.size(); ++v) {
    (*rotations)[v] =
        index[v] < 0 ? poses[v].q.toRotationMatrix()
                     : ProjectToSO3(x.block<3, 3>(3 * index[v], 0).transpose());
  }
  return true;
}

// Residual t_b - t_a - R_a t_ab per edge, the rotations given.
bool Translations(const std::vector<ChordalEdge>& edges,
                  const std::vector<bool>& held,
                  const std::vector<Eigen::Matrix3d>& rotations,
                  const std::vector<Rigid3d>& poses,
                  std::vector<Eigen::Vector3d>* translations) {
  int free = 0;
  const std::vector<int> index = FreeIndices(edges, held, &free);
  Triplets triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free, 3);
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  for (const ChordalEdge& e : edges) {
    const Eigen::RowVector3d c = (rotations[e.a] * e.T_ab.t).transpose();
    const int a = index[e.a];
    const int b = index[e.b];
    if (a >= 0) AddBlock(a, a, 1, one, e.tau, &triplets);
    if (b >= 0) AddBlock(b, b, 1, one, e.tau, &triplets);
    if (a >= 0 && b >= 0) {
      AddBlock(a, b, 1, -one, e.tau, &triplets);
      AddBlock(b, a, 1, -one, e.tau, &triplets);
      rhs.row(b) += e.tau * c;
      rhs.row(a) -= e.tau * c;
    } else if (a >= 0) {  // b held: t_a's target t_b - c
      rhs.row(a) += e.tau * (poses[e.b].t.transpose() - c);
    } else if (b >= 0) {  // a held: t_b's target t_a + c
      rhs.row(b) += e.tau * (poses[e.a].t.transpose() + c);
    }
  }
  Eigen::MatrixXd x;
  if (free > 0 && !SolveNormalEquations(free, triplets, rhs, &x)) {
    return false;
  }
  translations->resize(poses.size());
  for (size_t v = 0; v < poses.size(); ++v) {
    (*translations)[v] = index[v] < 0
                             ? poses[v].t
                             : Eigen::Vector3d(x.row(index[v]).transpose());
  }
  return true;
}

}  // namespace

bool ChordalInitialization(const std::vector<ChordalEdge>& edges,
                           const std::vector<bool>& held,
                           std::vector<Rigid3d>* poses) {
  const int n = static_cast<int>(poses->size());
  if (static_cast<int>(held.size()) != n) return false;
  for (const ChordalEdge& e : edges) {
    if (e.a < 0 || e.a >= n || e.b < 0 || e.b >= n || e.a == e.b) {
      return false;
    }
  }
  if (!EveryComponentHeld(edges, held)) return false;
  std::vector<Eigen::Matrix3d> rotations;
  std::vector<Eigen::Vector3d> translations;
  if (!ChordalRotations(edges, held, *poses, &rotations) ||
      !Translations(edges, held, rotations, *poses, &translations)) {
    return false;
  }
  int free = 0;
  const std::vector<int> index = FreeIndices(edges, held, &free);
  for (size_t v = 0; v < poses->size(); ++v) {
    if (index[v] < 0) continue;  // held, or without edges: as it was
    (*poses)[v] =
        Rigid3d(Eigen::Quaterniond(rotations[v]).normalized(), translations[v]);
  }
  return true;
}

}  // namespace symba
