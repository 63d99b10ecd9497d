// PoseMixture: the components shared by the asymmetric and the discrete object
// edges, and the SE(3) log error they share (docs/method.md, Eq. 14):
//
//   e_j(T_oc) = LogSE3(T_co^j * T_oc)     [rho; omega], metres and radians
//   r_j       = L_j e_j
//
// T_oc is the estimated camera pose in the object frame (T_wo^-1 T_wc for an
// asymmetric object); at the true state and a noise-free hypothesis the
// product is the identity and e_j = 0 (paper Eq. 3 and 4).
//
// PoseLogResidual is the residual as a template (the definition, which the
// tests differentiate automatically). PoseMixture::SquaredNorm is its
// plain-double twin that picks the winner, and SquaredNormLowerBound a cheaper
// lower bound of it that lets the selection skip most losers (below).
// PoseComponentResidual evaluates one component with hand-written Jacobians
// with respect to the blocks q_wc, t_wc, q_wo, t_wo (Jets only through
// LogSE3, see its comment).
//
// Lower bound. With P = T_co^j T_oc = (q, t), q = [v, w], s = |v|:
//   |rho| = |V(omega)^-1 t| >= |t|, since every singular value of V is
//           2 sin(theta/2) / theta <= 1 or 1;
//   |omega| = 2 atan2(s, |w|) >= 2 s / |q|   (x >= sin x), used only outside
//           LogSE3's small-angle series branch (s^2 >= kSmallAngleSquared; 0
//           inside it);
//   |L e|^2 >= l_t^2 |rho|^2 + l_r^2 |omega|^2 for a block-diagonal L, with
//           l_t, l_r the smallest singular values of its diagonal blocks
//           (l_t = l_r = that of L otherwise).
// The bound is shrunk by a relative 1e-9 against rounding, so it never exceeds
// the computed SquaredNorm. It needs no transcendental function; only the
// components that can still win are evaluated exactly.
#ifndef SYMBA_FACTORS_POSE_MIXTURE_H_
#define SYMBA_FACTORS_POSE_MIXTURE_H_

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <ceres/jet.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "symba/factors/pose_component.h"
#include "symba/factors/quaternion_jacobians.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"
#include "symba/geometry/so3.h"

namespace symba {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix67d = Eigen::Matrix<double, 6, 7>;

// r = L LogSE3(T_co * T_oc), for double or ceres::Jet.
template <typename T>
void PoseLogResidual(const PoseComponent& component,
                     const Rigid3<T>& T_oc,
                     T* residual) {
  const Rigid3<T> T_co = component.T_co.template Cast<T>();
  const Vector6<T> error = LogSE3(T_co * T_oc);
  Eigen::Map<Vector6<T>> r(residual);
  r = component.sqrt_info.template cast<T>() * error;
}

// LogSE3(P) and its 6 x 7 Jacobian with respect to P's ambient coordinates
// [q_x, q_y, q_z, q_w, t_x, t_y, t_z], by 7-lane Jets through LogSE3.
inline Vector6d LogSE3WithJacobian(const Eigen::Quaterniond& q,
                                   const Eigen::Vector3d& t,
                                   Matrix67d* jacobian) {
  using Jet7 = ceres::Jet<double, 7>;
  Rigid3<Jet7> P;
  for (int k = 0; k < 4; ++k) P.q.coeffs()(k) = Jet7(q.coeffs()(k), k);
  for (int k = 0; k < 3; ++k) P.t(k) = Jet7(t(k), 4 + k);
  const Vector6<Jet7> e = LogSE3(P);
  Vector6d value;
  for (int i = 0; i < 6; ++i) {
    value(i) = e(i).a;
    jacobian->row(i) = e(i).v.transpose();
  }
  return value;
}

// One component's residual r = L LogSE3(T_co (T_wo^-1 T_wc)) in doubles, with
// hand-written Jacobians with respect to the ambient blocks. With
//   q_P = q_co conj(q_wo) q_wc,
//   t_P = R_co (conj(q_wo) * t_wc - conj(q_wo) * t_wo) + t_co,
// E = [E_q E_t] = dLogSE3/d(q_P, t_P) (LogSE3WithJacobian), G = L E,
// K = G_q Lq(q_co), H = G_t R_co, M = d(conj(q_wo) * v)/dv and
// D = diag(-1, -1, -1, 1) (quaternion_jacobians.h for Lq, Rq, dp/dq):
//   dr/dq_wc = K Lq(conj(q_wo))
//   dr/dq_wo = K Rq(q_wc) D + H dp/dq(q_wo, t_wc - t_wo)
//   dr/dt_wc = H M,   dr/dt_wo = -H M
class PoseComponentResidual {
 public:
  // `component.T_co.q` must be unit.
  explicit PoseComponentResidual(const PoseComponent& component)
      : q_co_(component.T_co.q),
        R_co_(component.T_co.q.toRotationMatrix()),
        t_co_(component.T_co.t),
        sqrt_info_(component.sqrt_info),
        diagonal_(sqrt_info_.isDiagonal(0.0)),
        left_q_co_(QuaternionLeftMatrix(q_co_)) {}

  // Writes the 6 residuals and, where the pointer is not null, the row-major
  // Jacobians jacobians[0..3] (6 x 4, 6 x 3, 6 x 4, 6 x 3) with respect to
  // q_wc, t_wc, q_wo, t_wo. `jacobians` itself may be null.
  void Evaluate(const double* q_wc,
                const double* t_wc,
                const double* q_wo,
                const double* t_wo,
                double* residual,
                double* const* jacobians) const {
    const Eigen::Map<const Eigen::Quaterniond> q_c(q_wc);
    const Eigen::Map<const Eigen::Vector3d> t_c(t_wc);
    const Eigen::Map<const Eigen::Vector3d> t_o(t_wo);
    const Eigen::Quaterniond q_o_inverse(q_wo[3], -q_wo[0], -q_wo[1], -q_wo[2]);
    const Eigen::Quaterniond q_P = q_co_ * (q_o_inverse * q_c);
    const Eigen::Vector3d t_oc =
        RotateByConjugate(q_wo, t_c) - RotateByConjugate(q_wo, t_o);
    const Eigen::Vector3d t_P = R_co_ * t_oc + t_co_;
    Eigen::Map<Vector6d> r(residual);
    const bool any = jacobians != nullptr &&
                     (jacobians[0] != nullptr || jacobians[1] != nullptr ||
                      jacobians[2] != nullptr || jacobians[3] != nullptr);
    if (!any) {
      r = Whiten(LogSE3(Rigid3d(q_P, t_P)));
      return;
    }
    Matrix67d G;
    r = Whiten(LogSE3WithJacobian(q_P, t_P, &G));
    G = Whiten(G);
    const Eigen::Matrix<double, 6, 4> K = G.leftCols<4>() * left_q_co_;
    const Eigen::Matrix<double, 6, 3> H = G.rightCols<3>() * R_co_;
    using Jacobian4 = Eigen::Matrix<double, 6, 4, Eigen::RowMajor>;
    using Jacobian3 = Eigen::Matrix<double, 6, 3, Eigen::RowMajor>;
    if (jacobians[0] != nullptr) {
      Eigen::Map<Jacobian4> J(jacobians[0]);
      J = K * QuaternionLeftMatrix(q_o_inverse);
    }
    if (jacobians[1] != nullptr || jacobians[3] != nullptr) {
      const Eigen::Matrix<double, 6, 3> HM =
          H * RotateByConjugateVectorJacobian(q_wo);
      if (jacobians[1] != nullptr) Eigen::Map<Jacobian3>{jacobians[1]} = HM;
      if (jacobians[3] != nullptr) Eigen::Map<Jacobian3>{jacobians[3]} = -HM;
    }
    if (jacobians[2] != nullptr) {
      Matrix34d dp_dq;
      RotateByConjugate(q_wo, t_c - t_o, &dp_dq);
      Matrix4d right_q_wc_conj = QuaternionRightMatrix(q_c);
      right_q_wc_conj.leftCols<3>() *= -1.0;
      Eigen::Map<Jacobian4> J(jacobians[2]);
      J = K * right_q_wc_conj + H * dp_dq;
    }
  }

 private:
  Vector6d Whiten(const Vector6d& e) const {
    if (diagonal_) return sqrt_info_.diagonal().cwiseProduct(e);
    return sqrt_info_ * e;
  }
  Matrix67d Whiten(const Matrix67d& E) const {
    if (diagonal_) return sqrt_info_.diagonal().asDiagonal() * E;
    return sqrt_info_ * E;
  }

  Eigen::Quaterniond q_co_;
  Eigen::Matrix3d R_co_;
  Eigen::Vector3d t_co_;
  Matrix6d sqrt_info_;
  bool diagonal_;
  Matrix4d left_q_co_;
};

class PoseMixture {
 public:
  // `components` must be valid (ValidatePoseComponents); quaternions are
  // normalised here.
  explicit PoseMixture(std::vector<PoseComponent> components)
      : components_(std::move(components)) {
    hypotheses_.reserve(components_.size());
    log_det_sqrt_info_.reserve(components_.size());
    diagonal_ = true;
    for (PoseComponent& c : components_) {
      c.T_co.q.normalize();
      diagonal_ = diagonal_ && c.sqrt_info.isDiagonal(0.0);
      Hypothesis h;
      h.q = c.T_co.q;
      h.R = c.T_co.q.toRotationMatrix();
      h.t = c.T_co.t;
      h.sqrt_info_diagonal = c.sqrt_info.diagonal();
      SmallestSquaredSingularValues(c.sqrt_info, &h.bound_t, &h.bound_r);
      hypotheses_.push_back(h);
      log_det_sqrt_info_.push_back(
          std::log(std::abs(c.sqrt_info.determinant())));
    }
  }

  int size() const { return static_cast<int>(components_.size()); }
  const PoseComponent& component(int j) const { return components_[j]; }
  double LogDetSqrtInfo(int j) const { return log_det_sqrt_info_[j]; }

  // |L_j LogSE3(T_co^j * T_oc)|^2 in doubles.
  double SquaredNorm(int j, const Rigid3d& T_oc) const {
    const Hypothesis& h = hypotheses_[j];
    const Vector6d e = LogSE3(Rigid3d(h.q * T_oc.q, h.R * T_oc.t + h.t));
    if (diagonal_) return h.sqrt_info_diagonal.cwiseProduct(e).squaredNorm();
    return (components_[j].sqrt_info * e).squaredNorm();
  }

  // A lower bound of SquaredNorm(j, T_oc) (see the top of this file).
  double SquaredNormLowerBound(int j, const Rigid3d& T_oc) const {
    const Hypothesis& h = hypotheses_[j];
    const Eigen::Quaterniond q = h.q * T_oc.q;
    const Eigen::Vector3d t = h.R * T_oc.t + h.t;
    const double s_sq = q.vec().squaredNorm();
    const double omega_sq =
        s_sq < kSmallAngleSquared ? 0.0 : 4.0 * s_sq / (s_sq + q.w() * q.w());
    return (1.0 - 1e-9) * (h.bound_t * t.squaredNorm() + h.bound_r * omega_sq);
  }

 private:
  struct Hypothesis {
    Eigen::Quaterniond q;  // T_co^j
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    Vector6d sqrt_info_diagonal;  // used when every L_j is diagonal
    double bound_t = 0.0;         // l_t^2 of the lower bound
    double bound_r = 0.0;         // l_r^2
  };

  // l_t^2 and l_r^2 of the lower bound, less a margin for the error of the
  // singular values (exact for a diagonal L).
  static void SmallestSquaredSingularValues(const Matrix6d& L,
                                            double* l_t_sq,
                                            double* l_r_sq) {
    if (L.isDiagonal(0.0)) {
      const Vector6d d = L.diagonal().cwiseAbs2();
      *l_t_sq = d.head<3>().minCoeff();
      *l_r_sq = d.tail<3>().minCoeff();
      return;
    }
    const auto smallest = [](const auto& A) {
      const auto sigma = A.jacobiSvd().singularValues();
      const double largest = sigma(0);
      const double least = sigma(sigma.size() - 1);
      return std::max(0.0, least * least - 1e-10 * largest * largest);
    };
    if (L.topRightCorner<3, 3>().isZero(0.0) &&
        L.bottomLeftCorner<3, 3>().isZero(0.0)) {
      *l_t_sq = smallest(Eigen::Matrix3d(L.topLeftCorner<3, 3>()));
      *l_r_sq = smallest(Eigen::Matrix3d(L.bottomRightCorner<3, 3>()));
    } else {
      *l_t_sq = *l_r_sq = smallest(L);
    }
  }

  std::vector<PoseComponent> components_;
  std::vector<Hypothesis> hypotheses_;
  std::vector<double> log_det_sqrt_info_;
  bool diagonal_ = true;  // every L_j is diagonal
};

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_MIXTURE_H_
