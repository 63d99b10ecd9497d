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
// PoseLogResidual is the template used for the winner's autodiff;
// SquaredNorm is its plain-double twin used to pick the winner (it reuses a
// rotation matrix per hypothesis and never builds Jets).
#ifndef SYMBA_FACTORS_POSE_MIXTURE_H_
#define SYMBA_FACTORS_POSE_MIXTURE_H_

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"

namespace symba {

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

class PoseMixture {
 public:
  // `components` must be valid (ValidatePoseComponents); quaternions are
  // normalised here.
  explicit PoseMixture(std::vector<PoseComponent> components)
      : components_(std::move(components)) {
    rotations_.reserve(components_.size());
    log_det_sqrt_info_.reserve(components_.size());
    for (PoseComponent& c : components_) {
      c.T_co.q.normalize();
      rotations_.push_back(c.T_co.q.toRotationMatrix());
      log_det_sqrt_info_.push_back(
          std::log(std::abs(c.sqrt_info.determinant())));
    }
  }

  int size() const { return static_cast<int>(components_.size()); }
  const PoseComponent& component(int j) const { return components_[j]; }
  double LogDetSqrtInfo(int j) const { return log_det_sqrt_info_[j]; }

  // |L_j LogSE3(T_co^j * T_oc)|^2 in doubles.
  double SquaredNorm(int j, const Rigid3d& T_oc) const {
    const PoseComponent& c = components_[j];
    const Rigid3d product(c.T_co.q * T_oc.q, rotations_[j] * T_oc.t + c.T_co.t);
    return (c.sqrt_info * LogSE3(product)).squaredNorm();
  }

 private:
  std::vector<PoseComponent> components_;
  std::vector<Eigen::Matrix3d> rotations_;
  std::vector<double> log_det_sqrt_info_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_MIXTURE_H_
