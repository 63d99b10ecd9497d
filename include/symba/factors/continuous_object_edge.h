// Continuous object edge: a translation max-mixture over a detection's
// hypotheses plus gamma times the symmetry-axis error on the tangent plane
// (paper Eq. 5, with the axis error on the sphere instead of in (phi, psi);
// docs/method.md, Eq. 18-19).
//
//   t_co_pred = R_wc^T (t_wo - t_wc)                  object in camera (m)
//   r_t,j     = L_t,j (t_co^j - t_co_pred)             3 rows, mixture
//   r_axis    = gamma L_a SphereLog(a_c, R_wc^T a_w)   2 rows, shared
//   residual  = [ r_t,j* ; r_axis ; sqrt(2 (k_j* - k_min)) ]   (6)
//
// a_c is the measured unit axis in the camera frame (from categorisation, its
// sign aligned with the map axis by the caller); SphereLog is in radians on
// the tangent plane at a_c. The axis rows are the same for every component,
// so only the translation rows take part in choosing the winner and in the
// null hypothesis. The paper's sign t_wc - t_wo is a typo: the object's
// position in the camera is R_wc^T (t_wo - t_wc).
//
// ContinuousModel::ComponentFunctor is the component residual as a template
// (the definition); the winner is evaluated by ContinuousComponentCost, the
// same residual with a hand-written Jacobian (a test checks it against
// autodiff of the functor).
//
// Parameter blocks, in order:
//   q_wc  4  camera rotation, Eigen order [x, y, z, w]
//   t_wc  3  camera position (m)
//   t_wo  3  object position (m)
//   a_w   3  unit symmetry axis in the world (AxisManifold)
#ifndef SYMBA_FACTORS_CONTINUOUS_OBJECT_EDGE_H_
#define SYMBA_FACTORS_CONTINUOUS_OBJECT_EDGE_H_

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ceres/sized_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/common/status.h"
#include "symba/factors/max_mixture.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/quaternion_jacobians.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/sphere_log.h"
#include "symba/geometry/tangent_basis.h"

namespace symba {

// One translation hypothesis t_co^j with its square-root information (3 x 3,
// 1/m) and weight.
struct TranslationComponent {
  Eigen::Vector3d t_co = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sqrt_info = Eigen::Matrix3d::Identity();
  double weight = 1.0;
};

// The measured axis term shared by every component.
struct AxisMeasurement {
  Eigen::Vector3d a_c = Eigen::Vector3d::UnitZ();  // unit, camera frame
  Eigen::Matrix2d sqrt_info = Eigen::Matrix2d::Identity();  // 1/rad
  double gamma = 1.0;  // the paper's balance weight (>= 0)
};

// The tangent coordinates SphereLog(x, B, y) of sphere_log.h and their
// Jacobian with respect to y, branch by branch as SphereLog evaluates them.
// With w = B^T y, c = x.y, s^2 = |w|^2 and out = f w:
//   d out/dy = w (df/dc x + 2 df/d(s^2) B w)^T + f B^T
//   series (c > 0, s^2 < eps c^2): f = (1 - s^2/(3c^2)) / c,
//     df/dc = 2 s^2/(3 c^4) - (1 - s^2/(3c^2)) / c^2,  df/d(s^2) = -1/(3c^3)
//   s^2 = 0 otherwise: out = (pi, 0), Jacobian 0
//   else: f = atan2(s, c) / s,
//     df/dc = -1/(s^2 + c^2),
//     df/d(s^2) = (c / (s^2 + c^2) - f) / (2 s^2)
inline Eigen::Vector2d SphereLogWithJacobian(
    const Eigen::Vector3d& x,
    const Eigen::Matrix<double, 3, 2>& basis_at_x,
    const Eigen::Vector3d& y,
    Eigen::Matrix<double, 2, 3>* d_out_dy) {
  const Eigen::Vector2d w = basis_at_x.transpose() * y;
  const double c = x.dot(y);
  const double s_sq = w.squaredNorm();
  double f;
  double df_dc;
  double df_ds_sq;
  if (c > 0.0 && s_sq < kSmallAngleSquared * c * c) {
    const double c_sq = c * c;
    const double g = 1.0 - s_sq / (3.0 * c_sq);
    f = g / c;
    df_dc = 2.0 * s_sq / (3.0 * c_sq * c_sq) - g / c_sq;
    df_ds_sq = -1.0 / (3.0 * c_sq * c);
  } else if (s_sq <= 0.0) {
    if (d_out_dy != nullptr) d_out_dy->setZero();
    return Eigen::Vector2d(kPi, 0.0);
  } else {
    const double s = std::sqrt(s_sq);
    const double r_sq = s_sq + c * c;
    f = std::atan2(s, c) / s;
    df_dc = -1.0 / r_sq;
    df_ds_sq = (c / r_sq - f) / (2.0 * s_sq);
  }
  if (d_out_dy != nullptr) {
    const Eigen::Vector3d df_dy =
        df_dc * x + (2.0 * df_ds_sq) * (basis_at_x * w);
    *d_out_dy = w * df_dy.transpose() + f * basis_at_x.transpose();
  }
  return f * w;
}

// The continuous edge's component residual (ContinuousModel::ComponentFunctor)
// with a hand-written Jacobian. With d = t_wo - t_wc, p = conj(q_wc) * d and
// y = conj(q_wc) * a_w (quaternion_jacobians.h, M = dp/dd = dy/da_w):
//   r_t = L_t (t_co - p)                     r_a = G SphereLog(a_c, B, y)
//   dr_t/dq_wc = -L_t dp/dq                  dr_a/dq_wc = G S dy/dq
//   dr_t/dt_wc =  L_t M                      dr_a/dt_wc = 0
//   dr_t/dt_wo = -L_t M                      dr_a/dt_wo = 0
//   dr_t/da_w  =  0                          dr_a/da_w  = G S M
// with G = gamma L_a and S = dSphereLog/dy (SphereLogWithJacobian).
class ContinuousComponentCost final
    : public ceres::SizedCostFunction<5, 4, 3, 3, 3> {
 public:
  ContinuousComponentCost(const TranslationComponent& component,
                          const AxisMeasurement& axis,
                          const Eigen::Matrix<double, 3, 2>& basis_at_a_c)
      : sqrt_info_t_(component.sqrt_info),
        t_co_(component.t_co),
        sqrt_info_a_(axis.gamma * axis.sqrt_info),
        a_c_(axis.a_c),
        basis_at_a_c_(basis_at_a_c) {}

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const double* q_wc = parameters[0];
    const Eigen::Map<const Eigen::Vector3d> t_wc(parameters[1]);
    const Eigen::Map<const Eigen::Vector3d> t_wo(parameters[2]);
    const Eigen::Map<const Eigen::Vector3d> a_w(parameters[3]);
    const bool want_q = jacobians != nullptr && jacobians[0] != nullptr;
    Matrix34d dp_dq;
    Matrix34d dy_dq;
    const Eigen::Vector3d p =
        RotateByConjugate(q_wc, t_wo - t_wc, want_q ? &dp_dq : nullptr);
    const Eigen::Vector3d y =
        RotateByConjugate(q_wc, a_w, want_q ? &dy_dq : nullptr);
    Eigen::Matrix<double, 2, 3> dlog_dy;
    const Eigen::Vector2d log = SphereLogWithJacobian(
        a_c_, basis_at_a_c_, y, jacobians != nullptr ? &dlog_dy : nullptr);
    Eigen::Map<Eigen::Matrix<double, 5, 1>> r(residuals);
    r.head<3>() = sqrt_info_t_ * (t_co_ - p);
    r.tail<2>() = sqrt_info_a_ * log;
    if (jacobians == nullptr) return true;

    const Eigen::Matrix<double, 2, 3> axis_rows = sqrt_info_a_ * dlog_dy;
    const Eigen::Matrix3d M = RotateByConjugateVectorJacobian(q_wc);
    if (want_q) {
      Eigen::Map<Eigen::Matrix<double, 5, 4, Eigen::RowMajor>> J(jacobians[0]);
      J.topRows<3>() = -sqrt_info_t_ * dp_dq;
      J.bottomRows<2>() = axis_rows * dy_dq;
    }
    const bool want_t = jacobians[1] != nullptr || jacobians[2] != nullptr;
    const Eigen::Matrix3d translation_rows =
        want_t ? Eigen::Matrix3d(sqrt_info_t_ * M) : Eigen::Matrix3d::Zero();
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 5, 3, Eigen::RowMajor>> J(jacobians[1]);
      J.topRows<3>() = translation_rows;
      J.bottomRows<2>().setZero();
    }
    if (jacobians[2] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 5, 3, Eigen::RowMajor>> J(jacobians[2]);
      J.topRows<3>() = -translation_rows;
      J.bottomRows<2>().setZero();
    }
    if (jacobians[3] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 5, 3, Eigen::RowMajor>> J(jacobians[3]);
      J.topRows<3>().setZero();
      J.bottomRows<2>() = axis_rows * M;
    }
    return true;
  }

 private:
  Eigen::Matrix3d sqrt_info_t_;
  Eigen::Vector3d t_co_;
  Eigen::Matrix2d sqrt_info_a_;  // gamma L_a
  Eigen::Vector3d a_c_;
  Eigen::Matrix<double, 3, 2> basis_at_a_c_;
};

class ContinuousModel {
 public:
  static constexpr int kNumResiduals = 5;
  static constexpr int kMixtureRows = 3;
  using Prepared = Eigen::Vector3d;  // t_co_pred

  struct ComponentFunctor {
    TranslationComponent component;
    AxisMeasurement axis;
    Eigen::Matrix<double, 3, 2> basis_at_a_c;
    template <typename T>
    bool operator()(const T* q_wc,
                    const T* t_wc,
                    const T* t_wo,
                    const T* a_w,
                    T* residual) const {
      const Eigen::Map<const Eigen::Quaternion<T>> R_wc(q_wc);
      const Eigen::Quaternion<T> R_cw = R_wc.conjugate();
      const Vector3<T> t_co_pred = R_cw * (Eigen::Map<const Vector3<T>>(t_wo) -
                                           Eigen::Map<const Vector3<T>>(t_wc));
      Eigen::Map<Eigen::Matrix<T, 5, 1>> r(residual);
      r.template head<3>() = component.sqrt_info.template cast<T>() *
                             (component.t_co.template cast<T>() - t_co_pred);
      const Vector3<T> a_c_pred = R_cw * Eigen::Map<const Vector3<T>>(a_w);
      r.template tail<2>() =
          T(axis.gamma) *
          (axis.sqrt_info.template cast<T>() *
           SphereLog(Vector3<T>(axis.a_c.template cast<T>()),
                     Eigen::Matrix<T, 3, 2>(basis_at_a_c.template cast<T>()),
                     a_c_pred));
      return true;
    }
  };

  ContinuousModel(std::vector<TranslationComponent> components,
                  AxisMeasurement axis)
      : components_(std::move(components)), axis_(std::move(axis)) {
    axis_.a_c.normalize();
    const Eigen::Matrix<double, 3, 2> basis = TangentBasis(axis_.a_c);
    for (const TranslationComponent& c : components_) {
      log_det_sqrt_info_.push_back(
          std::log(std::abs(c.sqrt_info.determinant())));
      component_costs_.push_back(
          std::make_unique<ContinuousComponentCost>(c, axis_, basis));
    }
  }

  int NumComponents() const { return static_cast<int>(components_.size()); }
  double Weight(int j) const { return components_[j].weight; }
  double LogDetSqrtInfo(int j) const { return log_det_sqrt_info_[j]; }

  bool Prepare(double const* const* parameters,
               Eigen::Vector3d* t_co_pred) const {
    const Eigen::Map<const Eigen::Quaterniond> R_wc(parameters[0]);
    *t_co_pred =
        R_wc.conjugate() * (Eigen::Map<const Eigen::Vector3d>(parameters[2]) -
                            Eigen::Map<const Eigen::Vector3d>(parameters[1]));
    return t_co_pred->allFinite();
  }
  double MixtureSquaredNorm(const Eigen::Vector3d& t_co_pred, int j) const {
    return (components_[j].sqrt_info * (components_[j].t_co - t_co_pred))
        .squaredNorm();
  }
  // Component j's residual with hand-written Jacobians.
  const ceres::CostFunction& Component(int j) const {
    return *component_costs_[j];
  }

 private:
  std::vector<TranslationComponent> components_;
  AxisMeasurement axis_;
  std::vector<double> log_det_sqrt_info_;
  std::vector<std::unique_ptr<ContinuousComponentCost>> component_costs_;
};

using ContinuousObjectEdge =
    MaxMixtureCostFunction<ContinuousModel, 4, 3, 3, 3>;

inline Status CreateContinuousObjectEdge(
    std::vector<TranslationComponent> components,
    const AxisMeasurement& axis,
    const MixtureOptions& options,
    std::unique_ptr<ContinuousObjectEdge>* edge) {
  if (components.empty()) {
    return Status::Error("a continuous edge needs at least one hypothesis");
  }
  for (size_t j = 0; j < components.size(); ++j) {
    const std::string what = "hypothesis " + std::to_string(j);
    if (!components[j].t_co.allFinite()) {
      return Status::Error(what + ": translation is not finite");
    }
    Status status = ValidateSqrtInfoAndWeight<3>(
        components[j].sqrt_info, components[j].weight, what);
    if (!status.ok()) return status;
  }
  if (!axis.a_c.allFinite() || std::abs(axis.a_c.norm() - 1.0) > 1e-6) {
    return Status::Error("axis: a_c must be a finite unit vector");
  }
  if (!axis.sqrt_info.allFinite() || !std::isfinite(axis.gamma) ||
      axis.gamma < 0.0) {
    return Status::Error(
        "axis: square-root information must be finite and gamma >= 0");
  }
  if (!options.IsValid()) return Status::Error("invalid mixture options");
  *edge = std::make_unique<ContinuousObjectEdge>(
      ContinuousModel(std::move(components), axis), options);
  return Status::Ok();
}

}  // namespace symba

#endif  // SYMBA_FACTORS_CONTINUOUS_OBJECT_EDGE_H_
