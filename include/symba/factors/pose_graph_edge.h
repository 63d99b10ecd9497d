// Edge of a 3-D pose graph (a g2o EDGE_SE3:QUAT, docs/pose-graphs.md)
// between vertices a and b with measurement T_ab_meas (the pose of b in a's
// frame) and information Omega (6 x 6, symmetric positive definite):
//
//   D    = T_ab_meas^-1 * T_wa^-1 * T_wb        (identity when the estimate
//                                                reproduces the measurement)
//   e    = [D.t; s * vec(D.q)]                  (6: translation m, rotation)
//   r    = U e,  U = L^T, Omega = L L^T         (U upper triangular)
//   cost = 1/2 r^T r = 1/2 e^T Omega e
//
// D.q is taken with a non-negative scalar part (q and -q are one rotation),
// so vec(D.q) = sin(theta/2) n for a rotation error of theta about n. The
// error is g2o's EdgeSE3 error (translation and rotation both expressed in
// the measured frame b) except for the scale s of the rotation rows:
//
//   s = 2 (PoseGraphRotationError::kRadians, the default): 2 sin(theta/2) n,
//     which is theta n to second order, so the rotation rows of Omega are a
//     precision in 1/rad^2. This is how Ceres's pose_graph_3d example,
//     SE-Sync and GTSAM read the information of these files, and it makes the
//     published optima comparable (docs/pose-graphs.md).
//   s = 1 (kG2oHalfAngle): g2o's literal error, sin(theta/2) n; the same
//     Omega then weighs rotation errors four times less.
//
// Whitening: r must satisfy r^T r = e^T Omega e. With the lower Cholesky
// factor L (Omega = L L^T), r = L^T e does; r = L e does not unless Omega is
// diagonal (L e gives e^T L^T L e). UpperCholeskyFactor() returns L^T.
//
// Parameter blocks: q_wa 4, t_wa 3, q_wb 4, t_wb 3. Quaternions in Eigen
// memory order [x, y, z, w] on ceres::EigenQuaternionManifold (tangent size
// 3), translations in metres (Euclidean). 6 residuals, dimensionless.
#ifndef SYMBA_FACTORS_POSE_GRAPH_EDGE_H_
#define SYMBA_FACTORS_POSE_GRAPH_EDGE_H_

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"
#include "symba/geometry/so3.h"

namespace symba {

// How the rotation rows of a pose-graph edge's information are read (see the
// top of this header).
enum class PoseGraphRotationError {
  kRadians,       // e_rot = 2 vec(D.q) ~ rotation vector, radians
  kG2oHalfAngle,  // e_rot = vec(D.q), g2o's EdgeSE3 error
};

inline double RotationErrorScale(PoseGraphRotationError rotation_error) {
  return rotation_error == PoseGraphRotationError::kG2oHalfAngle ? 1.0 : 2.0;
}

// The unwhitened error e of the edge for the estimate (T_wa, T_wb), given
// the inverse of the measurement. Works for double and ceres::Jet.
template <typename T>
Vector6<T> PoseGraphEdgeError(const Rigid3<T>& T_wa,
                              const Rigid3<T>& T_wb,
                              const Rigid3<T>& T_ba_measured,
                              const T& rotation_scale) {
  const Rigid3<T> D = T_ba_measured * (T_wa.Inverse() * T_wb);
  // Same rotation, representative with w >= 0: the rotation rows are then
  // continuous in the estimate for every error angle below pi.
  const T sign = D.q.w() < T(0) ? T(-1) : T(1);
  Vector6<T> e;
  e.template head<3>() = D.t;
  e.template tail<3>() = (sign * rotation_scale) * D.q.vec();
  return e;
}

// U = L^T with Omega = L L^T, the square root that whitens e exactly:
// U^T U = Omega. Returns false (and leaves *upper unchanged) unless Omega is
// symmetric positive definite to Eigen's LLT (only its lower triangle is
// read).
inline bool UpperCholeskyFactor(const Matrix6d& information, Matrix6d* upper) {
  const Eigen::LLT<Matrix6d> llt(information);
  if (llt.info() != Eigen::Success) return false;
  const Matrix6d U = llt.matrixU();
  if (!U.allFinite() || !(U.diagonal().minCoeff() > 0.0)) return false;
  *upper = U;
  return true;
}

class PoseGraphEdgeFactor {
 public:
  // `sqrt_info` is U from UpperCholeskyFactor(information).
  PoseGraphEdgeFactor(const Rigid3d& T_ab_measured,
                      const Matrix6d& sqrt_info,
                      PoseGraphRotationError rotation_error)
      : T_ba_measured_(T_ab_measured.Inverse()),
        sqrt_info_(sqrt_info),
        rotation_scale_(RotationErrorScale(rotation_error)) {}

  template <typename T>
  bool operator()(const T* q_wa,
                  const T* t_wa,
                  const T* q_wb,
                  const T* t_wb,
                  T* residual) const {
    const Rigid3<T> T_wa{Eigen::Map<const Eigen::Quaternion<T>>(q_wa),
                         Eigen::Map<const Vector3<T>>(t_wa)};
    const Rigid3<T> T_wb{Eigen::Map<const Eigen::Quaternion<T>>(q_wb),
                         Eigen::Map<const Vector3<T>>(t_wb)};
    Eigen::Map<Vector6<T>> r(residual);
    r = sqrt_info_.template cast<T>() *
        PoseGraphEdgeError(
            T_wa, T_wb, T_ba_measured_.template Cast<T>(), T(rotation_scale_));
    return true;
  }

  // The edge with analytic Jacobians (PoseGraphEdgeCost), what the pose
  // graph solves use.
  static ceres::CostFunction* Create(
      const Rigid3d& T_ab_measured,
      const Matrix6d& sqrt_info,
      PoseGraphRotationError rotation_error = PoseGraphRotationError::kRadians);
  // The same edge differentiated by Ceres's automatic differentiation (the
  // reference the analytic Jacobians are tested against).
  static ceres::CostFunction* CreateAutoDiff(
      const Rigid3d& T_ab_measured,
      const Matrix6d& sqrt_info,
      PoseGraphRotationError rotation_error =
          PoseGraphRotationError::kRadians) {
    return new ceres::AutoDiffCostFunction<PoseGraphEdgeFactor, 6, 4, 3, 4, 3>(
        new PoseGraphEdgeFactor(T_ab_measured, sqrt_info, rotation_error));
  }

 private:
  Rigid3d T_ba_measured_;
  Matrix6d sqrt_info_;
  double rotation_scale_;
};

// PoseGraphEdgeFactor's residual r = U e with hand-derived Jacobians, in
// doubles (a loop closure solves thousands of these edges; automatic
// differentiation through both poses costs several times more).
//
// With C = q_m q_a^-1 (q_m the inverse measurement's rotation, R_C its
// matrix), d = t_b - t_a and D.q = C q_b = (w, v), for the manifold's
// left perturbations q <- [1, delta] q (a rotation of 2 delta):
//
//   de/dt_a     = [-R_C; 0]               de/dt_b     = [R_C; 0]
//   de/ddelta_a = [2 R_C Hat(d); -B]      de/ddelta_b = [0; B]
//   B = s sign(w) (w I - Hat(v)) R_C
//
// (the rotation error C [1, delta] q_b = [1, R_C delta] D.q moves vec(D.q)
// by (w I - Hat(v)) R_C delta; R_a^-1 <- R_a^-1 (I - 2 Hat(delta_a)) moves
// D.t by 2 R_C Hat(d) delta_a). A quaternion block's ambient Jacobian is
// J_tangent P^T with P = [w_q I - Hat(v_q); -v_q^T] the manifold's plus
// Jacobian at q = (w_q, v_q) (Eigen order x, y, z, w), whose columns are
// orthonormal: J_ambient P = J_tangent exactly.
class PoseGraphEdgeCost final : public ceres::SizedCostFunction<6, 4, 3, 4, 3> {
 public:
  PoseGraphEdgeCost(const Rigid3d& T_ab_measured,
                    const Matrix6d& sqrt_info,
                    PoseGraphRotationError rotation_error)
      : T_ba_measured_(T_ab_measured.Inverse()),
        sqrt_info_(sqrt_info),
        rotation_scale_(RotationErrorScale(rotation_error)) {}

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Quaterniond> q_wa(parameters[0]);
    const Eigen::Map<const Eigen::Vector3d> t_wa(parameters[1]);
    const Eigen::Map<const Eigen::Quaterniond> q_wb(parameters[2]);
    const Eigen::Map<const Eigen::Vector3d> t_wb(parameters[3]);
    const Eigen::Quaterniond C = T_ba_measured_.q * q_wa.conjugate();
    const Eigen::Quaterniond D = C * q_wb;
    const Eigen::Matrix3d R_C = C.toRotationMatrix();
    const Eigen::Vector3d d = t_wb - t_wa;
    const double rotation_scale = (D.w() < 0.0 ? -1.0 : 1.0) * rotation_scale_;
    Vector6<double> e;
    e.head<3>() = R_C * d + T_ba_measured_.t;
    e.tail<3>() = rotation_scale * D.vec();
    Eigen::Map<Vector6<double>> r(residuals);
    r = sqrt_info_ * e;
    if (jacobians == nullptr) return true;

    const Eigen::Matrix3d B =
        rotation_scale *
        (D.w() * Eigen::Matrix3d::Identity() - Hat<double>(D.vec())) * R_C;
    Eigen::Matrix<double, 6, 3> de;
    if (jacobians[0] != nullptr) {
      de.topRows<3>() = 2.0 * R_C * Hat<double>(d);
      de.bottomRows<3>() = -B;
      AmbientJacobian(sqrt_info_ * de, q_wa, jacobians[0]);
    }
    if (jacobians[1] != nullptr) {
      de.topRows<3>() = -R_C;
      de.bottomRows<3>().setZero();
      TranslationJacobian(sqrt_info_ * de, jacobians[1]);
    }
    if (jacobians[2] != nullptr) {
      de.topRows<3>().setZero();
      de.bottomRows<3>() = B;
      AmbientJacobian(sqrt_info_ * de, q_wb, jacobians[2]);
    }
    if (jacobians[3] != nullptr) {
      de.topRows<3>() = R_C;
      de.bottomRows<3>().setZero();
      TranslationJacobian(sqrt_info_ * de, jacobians[3]);
    }
    return true;
  }

 private:
  // J_tangent P^T into a row-major 6 x 4 block (see the class comment).
  static void AmbientJacobian(const Eigen::Matrix<double, 6, 3>& tangent,
                              const Eigen::Quaterniond& q,
                              double* ambient) {
    Eigen::Matrix<double, 4, 3> P;
    P.topRows<3>() = q.w() * Eigen::Matrix3d::Identity() - Hat<double>(q.vec());
    P.row(3) = -q.vec().transpose();
    Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>> J(ambient);
    J = tangent * P.transpose();
  }
  // A translation block's Jacobian into a row-major 6 x 3 block.
  static void TranslationJacobian(const Eigen::Matrix<double, 6, 3>& tangent,
                                  double* out) {
    Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>> J(out);
    J = tangent;
  }

  Rigid3d T_ba_measured_;
  Matrix6d sqrt_info_;
  double rotation_scale_;
};

inline ceres::CostFunction* PoseGraphEdgeFactor::Create(
    const Rigid3d& T_ab_measured,
    const Matrix6d& sqrt_info,
    PoseGraphRotationError rotation_error) {
  return new PoseGraphEdgeCost(T_ab_measured, sqrt_info, rotation_error);
}

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_GRAPH_EDGE_H_
