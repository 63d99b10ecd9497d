// Derivatives of the quaternion operations in the object edges, for their
// hand-written Jacobians. Quaternions are Eigen's: coefficients [x, y, z, w]
// in memory, q = [u, w] with u the vector part. Every Jacobian is with respect
// to the four ambient coefficients (Ceres applies the manifold afterwards), and
// each formula is that of the expression the code evaluates, so it is exact
// for a non-unit q too (numeric checks perturb q off the unit sphere).
//
//   RotateByConjugate(q, v): p = conj(q) * v, computed as Eigen computes
//   q * v (a rotation only for unit q), with conj(q) = [-u, w]:
//     p     = v - 2 w (u x v) + 2 u x (u x v)
//     dp/dv = I - 2 w [u]x + 2 [u]x^2
//     dp/du = 2 w [v]x + 2 ((u.v) I + u v^T - 2 v u^T)
//     dp/dw = -2 (u x v)
//
//   Hamilton product c = a b:   c_u = a_w b_u + b_w a_u + a_u x b_u,
//                               c_w = a_w b_w - a_u . b_u
//     dc/db = QuaternionLeftMatrix(a)  = [ a_w I + [a_u]x   a_u ]
//                                        [ -a_u^T           a_w ]
//     dc/da = QuaternionRightMatrix(b) = [ b_w I - [b_u]x   b_u ]
//                                        [ -b_u^T           b_w ]
//   (rows and columns in the order x, y, z, w).
#ifndef SYMBA_FACTORS_QUATERNION_JACOBIANS_H_
#define SYMBA_FACTORS_QUATERNION_JACOBIANS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace symba {

using Matrix34d = Eigen::Matrix<double, 3, 4>;
using Matrix4d = Eigen::Matrix<double, 4, 4>;

inline Eigen::Matrix3d CrossMatrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d A;
  A << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return A;
}

// dp/dv of RotateByConjugate; depends on q only.
inline Eigen::Matrix3d RotateByConjugateVectorJacobian(const double* q) {
  const Eigen::Vector3d u(q[0], q[1], q[2]);
  const Eigen::Matrix3d U = CrossMatrix(u);
  return Eigen::Matrix3d::Identity() - 2.0 * q[3] * U + 2.0 * (U * U);
}

// p = conj(q) * v (Eigen's formula) and, if dp_dq is not null, dp/dq.
inline Eigen::Vector3d RotateByConjugate(const double* q,
                                         const Eigen::Vector3d& v,
                                         Matrix34d* dp_dq = nullptr) {
  const Eigen::Vector3d u(q[0], q[1], q[2]);
  const double w = q[3];
  const Eigen::Vector3d u_x_v = u.cross(v);
  if (dp_dq != nullptr) {
    const double u_dot_v = u.dot(v);
    dp_dq->leftCols<3>() = 2.0 * w * CrossMatrix(v) +
                           2.0 * (u_dot_v * Eigen::Matrix3d::Identity() +
                                  u * v.transpose() - 2.0 * v * u.transpose());
    dp_dq->col(3) = -2.0 * u_x_v;
  }
  return v - 2.0 * w * u_x_v + 2.0 * u.cross(u_x_v);
}

inline Matrix4d QuaternionLeftMatrix(const Eigen::Quaterniond& a) {
  Matrix4d L;
  L.topLeftCorner<3, 3>() =
      a.w() * Eigen::Matrix3d::Identity() + CrossMatrix(a.vec());
  L.topRightCorner<3, 1>() = a.vec();
  L.bottomLeftCorner<1, 3>() = -a.vec().transpose();
  L(3, 3) = a.w();
  return L;
}

inline Matrix4d QuaternionRightMatrix(const Eigen::Quaterniond& b) {
  Matrix4d R;
  R.topLeftCorner<3, 3>() =
      b.w() * Eigen::Matrix3d::Identity() - CrossMatrix(b.vec());
  R.topRightCorner<3, 1>() = b.vec();
  R.bottomLeftCorner<1, 3>() = -b.vec().transpose();
  R(3, 3) = b.w();
  return R;
}

}  // namespace symba

#endif  // SYMBA_FACTORS_QUATERNION_JACOBIANS_H_
