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

#include <ceres/autodiff_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/common/status.h"
#include "symba/factors/max_mixture.h"
#include "symba/factors/pose_component.h"
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
          std::make_unique<
              ceres::AutoDiffCostFunction<ComponentFunctor, 5, 4, 3, 3, 3>>(
              new ComponentFunctor{c, axis_, basis}));
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
  const ceres::CostFunction& Component(int j) const {
    return *component_costs_[j];
  }

 private:
  std::vector<TranslationComponent> components_;
  AxisMeasurement axis_;
  std::vector<double> log_det_sqrt_info_;
  std::vector<std::unique_ptr<ceres::CostFunction>> component_costs_;
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
