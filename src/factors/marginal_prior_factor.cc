#include "symba/factors/marginal_prior_factor.h"

#include <cmath>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "symba/geometry/tangent_basis.h"

namespace symba {
namespace {

constexpr double kUnitNormTolerance = 1e-6;

// f(v, w) = atan2(|v|, w) v / |v| (the logarithm of a unit quaternion [v, w],
// or the geodesic step towards a point whose tangent part is v and whose
// component along the base point is w) and its Jacobian [df/dv | df/dw]:
//
//   df/dv = a I + c v v^T,  a = theta / s,  c = (w / (s^2 + w^2) - a) / s^2
//   df/dw = -v / (s^2 + w^2),                 s = |v|, theta = atan2(s, w)
//
// For s -> 0 (w > 0) the series a = 1/w - s^2/(3 w^3), c = -2/(3 w^3)
// avoids the cancellation. False at s = 0, w <= 0 (the antipode).
template <int N>
bool AtanLog(const Eigen::Matrix<double, N, 1>& v,
             double w,
             Eigen::Matrix<double, N, 1>* f,
             Eigen::Matrix<double, N, N + 1>* jacobian) {
  const double s2 = v.squaredNorm();
  const double s = std::sqrt(s2);
  double a = 0.0;
  double c = 0.0;
  if (s > 1e-6 * std::abs(w) && s > 0.0) {
    a = std::atan2(s, w) / s;
    c = (w / (s2 + w * w) - a) / s2;
  } else if (w > 0.0) {
    const double w3 = w * w * w;
    a = 1.0 / w - s2 / (3.0 * w3);
    c = -2.0 / (3.0 * w3);
  } else {
    return false;
  }
  *f = a * v;
  if (jacobian != nullptr) {
    jacobian->template leftCols<N>() =
        a * Eigen::Matrix<double, N, N>::Identity() + c * v * v.transpose();
    jacobian->col(N) = -v / (s2 + w * w);
  }
  return true;
}

using RowMajor34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
using RowMajor23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// Log(y x0^-1) (EigenQuaternionManifold's Minus) and its derivative in y's
// coefficients [x, y, z, w]: z = y x0^-1 is linear in y, so dz/dy has the
// columns e_i x0^-1 for the unit quaternions e_i.
bool QuaternionDifference(const double* y,
                          const double* x0,
                          double* delta,
                          double* jacobian) {
  const Eigen::Quaterniond x0_inverse =
      Eigen::Map<const Eigen::Quaterniond>(x0).conjugate();
  const Eigen::Quaterniond z =
      Eigen::Map<const Eigen::Quaterniond>(y) * x0_inverse;
  Eigen::Vector3d f;
  Eigen::Matrix<double, 3, 4> df_dz;
  if (!AtanLog<3>(z.vec(), z.w(), &f, jacobian ? &df_dz : nullptr)) {
    return false;
  }
  Eigen::Map<Eigen::Vector3d> delta_map(delta);
  delta_map = f;
  if (jacobian != nullptr) {
    Eigen::Matrix4d dz_dy;
    for (int i = 0; i < 4; ++i) {
      Eigen::Quaterniond e(Eigen::Vector4d::Unit(i));
      dz_dy.col(i) = (e * x0_inverse).coeffs();
    }
    Eigen::Map<RowMajor34> jacobian_map(jacobian);
    jacobian_map = df_dz * dz_dy;
  }
  return true;
}

// AxisManifold's Minus: u = B(x0)^T y, w = x0 . y, d = f(u, w).
bool AxisDifference(const double* y,
                    const double* x0,
                    double* delta,
                    double* jacobian) {
  const Eigen::Map<const Eigen::Vector3d> y_map(y);
  const Eigen::Map<const Eigen::Vector3d> x0_map(x0);
  const Eigen::Matrix<double, 3, 2> B = TangentBasis<double>(x0_map);
  Eigen::Vector2d f;
  Eigen::Matrix<double, 2, 3> df_duw;
  if (!AtanLog<2>(B.transpose() * y_map,
                  x0_map.dot(y_map),
                  &f,
                  jacobian ? &df_duw : nullptr)) {
    return false;
  }
  Eigen::Map<Eigen::Vector2d> delta_map(delta);
  delta_map = f;
  if (jacobian != nullptr) {
    Eigen::Map<RowMajor23> jacobian_map(jacobian);
    jacobian_map = df_duw.leftCols<2>() * B.transpose() +
                   df_duw.col(2) * x0_map.transpose();
  }
  return true;
}

int AmbientSize(const PriorBlock& block) {
  return static_cast<int>(block.x0.size());
}

Status CheckBlock(const PriorBlock& block, size_t index) {
  const std::string where = "prior block " + std::to_string(index) + ": ";
  if (block.x0.size() < 1 || !block.x0.allFinite()) {
    return Status::Error(where + "x0 must be non-empty and finite");
  }
  const int expected = block.kind == PriorBlockKind::kQuaternion ? 4
                       : block.kind == PriorBlockKind::kUnitAxis ? 3
                                                                 : -1;
  if (expected > 0 && (AmbientSize(block) != expected ||
                       std::abs(block.x0.norm() - 1.0) > kUnitNormTolerance)) {
    return Status::Error(where + "x0 must be a unit vector of size " +
                         std::to_string(expected));
  }
  return Status::Ok();
}

}  // namespace

int PriorBlockTangentSize(const PriorBlock& block) {
  switch (block.kind) {
    case PriorBlockKind::kQuaternion:
      return 3;
    case PriorBlockKind::kUnitAxis:
      return 2;
    case PriorBlockKind::kEuclidean:
      break;
  }
  return AmbientSize(block);
}

bool PriorTangentDifference(PriorBlockKind kind,
                            int ambient_size,
                            const double* y,
                            const double* x0,
                            double* delta,
                            double* jacobian) {
  switch (kind) {
    case PriorBlockKind::kQuaternion:
      return QuaternionDifference(y, x0, delta, jacobian);
    case PriorBlockKind::kUnitAxis:
      return AxisDifference(y, x0, delta, jacobian);
    case PriorBlockKind::kEuclidean:
      break;
  }
  for (int i = 0; i < ambient_size; ++i) {
    delta[i] = y[i] - x0[i];
    if (!std::isfinite(delta[i])) return false;
  }
  if (jacobian != nullptr) {
    Eigen::Map<Eigen::MatrixXd> jacobian_map(
        jacobian, ambient_size, ambient_size);
    jacobian_map.setIdentity();
  }
  return true;
}

Status MarginalPriorFactor::Create(
    std::vector<PriorBlock> blocks,
    Eigen::MatrixXd A,
    Eigen::VectorXd e,
    std::unique_ptr<MarginalPriorFactor>* factor) {
  if (blocks.empty()) return Status::Error("a prior needs at least one block");
  int tangent_size = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    Status status = CheckBlock(blocks[b], b);
    if (!status.ok()) return status;
    tangent_size += PriorBlockTangentSize(blocks[b]);
  }
  if (A.rows() < 1 || A.cols() != tangent_size || e.size() != A.rows()) {
    return Status::Error("prior: A must be rows x " +
                         std::to_string(tangent_size) +
                         " (the blocks' tangent sizes) and e of size rows");
  }
  if (!A.allFinite() || !e.allFinite()) {
    return Status::Error("prior: A and e must be finite");
  }
  factor->reset(
      new MarginalPriorFactor(std::move(blocks), std::move(A), std::move(e)));
  return Status::Ok();
}

MarginalPriorFactor::MarginalPriorFactor(std::vector<PriorBlock> blocks,
                                         Eigen::MatrixXd A,
                                         Eigen::VectorXd e)
    : blocks_(std::move(blocks)), A_(std::move(A)), e_(std::move(e)) {
  int offset = 0;
  for (const PriorBlock& block : blocks_) {
    tangent_offsets_.push_back(offset);
    offset += PriorBlockTangentSize(block);
    mutable_parameter_block_sizes()->push_back(AmbientSize(block));
  }
  set_num_residuals(static_cast<int>(A_.rows()));
}

bool MarginalPriorFactor::Evaluate(double const* const* parameters,
                                   double* residuals,
                                   double** jacobians) const {
  // A tangent block is at most 4 wide (a Euclidean block may be larger:
  // those are written straight from A, their Jacobian being the identity).
  constexpr int kMaxFixed = 4;
  const int rows = static_cast<int>(A_.rows());
  Eigen::Map<Eigen::VectorXd> r(residuals, rows);
  r = e_;
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const PriorBlock& block = blocks_[b];
    const int n = AmbientSize(block);
    const int t = PriorBlockTangentSize(block);
    const int offset = tangent_offsets_[b];
    double* jacobian = jacobians != nullptr ? jacobians[b] : nullptr;
    using RowMajorMatrix =
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    if (block.kind == PriorBlockKind::kEuclidean) {
      for (int i = 0; i < n; ++i) {
        const double d = parameters[b][i] - block.x0[i];
        if (!std::isfinite(d)) return false;
        r.noalias() += A_.col(offset + i) * d;
      }
      if (jacobian != nullptr) {
        Eigen::Map<RowMajorMatrix>(jacobian, rows, n) =
            A_.middleCols(offset, n);
      }
      continue;
    }
    double delta[kMaxFixed];
    double d_delta[kMaxFixed * kMaxFixed];
    if (!PriorTangentDifference(block.kind,
                                n,
                                parameters[b],
                                block.x0.data(),
                                delta,
                                jacobian ? d_delta : nullptr)) {
      return false;
    }
    for (int i = 0; i < t; ++i) r.noalias() += A_.col(offset + i) * delta[i];
    if (jacobian != nullptr) {
      const Eigen::Map<const RowMajorMatrix> D(d_delta, t, n);
      Eigen::Map<RowMajorMatrix> J(jacobian, rows, n);
      J.setZero();
      for (int i = 0; i < t; ++i) {
        J.noalias() += A_.col(offset + i) * D.row(i);
      }
    }
  }
  return true;
}

}  // namespace symba
