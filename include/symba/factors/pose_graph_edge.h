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
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"

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

  static ceres::CostFunction* Create(const Rigid3d& T_ab_measured,
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

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_GRAPH_EDGE_H_
