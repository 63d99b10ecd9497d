// PoseMixtureModel: what the asymmetric and the discrete object edges' models
// (the Model of MaxMixtureCostFunction, max_mixture.h) have in common. Both
// compare the estimated camera pose in the object frame, T_oc, with each
// hypothesis through the SE(3) log error of PoseMixture (pose_mixture.h):
//
//   r_j = L_j LogSE3(T_co^j * T_oc)     6 rows, all of them mixture rows
//
// They differ only in how T_oc is made from their parameter blocks (Prepare,
// in the derived model) and in the hand-written cost of one component
// (ComponentCost, built from the component and the `cost_args` given to the
// constructor).
#ifndef SYMBA_FACTORS_POSE_MIXTURE_MODEL_H_
#define SYMBA_FACTORS_POSE_MIXTURE_MODEL_H_

#include <memory>
#include <utility>
#include <vector>

#include <ceres/cost_function.h>

#include "symba/factors/pose_component.h"
#include "symba/factors/pose_mixture.h"
#include "symba/geometry/rigid3.h"

namespace symba {

template <typename ComponentCost>
class PoseMixtureModel {
 public:
  static constexpr int kNumResiduals = 6;
  static constexpr int kMixtureRows = 6;
  using Prepared = Rigid3d;  // T_oc

  int NumComponents() const { return mixture_.size(); }
  double Weight(int j) const { return mixture_.component(j).weight; }
  double LogDetSqrtInfo(int j) const { return mixture_.LogDetSqrtInfo(j); }
  double MixtureSquaredNorm(const Rigid3d& T_oc, int j) const {
    return mixture_.SquaredNorm(j, T_oc);
  }
  double MixtureSquaredNormLowerBound(const Rigid3d& T_oc, int j) const {
    return mixture_.SquaredNormLowerBound(j, T_oc);
  }
  // Component j's residual with hand-written Jacobians.
  const ceres::CostFunction& Component(int j) const {
    return *component_costs_[j];
  }

 protected:
  // `components` must be valid (ValidatePoseComponents).
  template <typename... CostArgs>
  explicit PoseMixtureModel(std::vector<PoseComponent> components,
                            const CostArgs&... cost_args)
      : mixture_(std::move(components)) {
    component_costs_.reserve(mixture_.size());
    for (int j = 0; j < mixture_.size(); ++j) {
      component_costs_.push_back(
          std::make_unique<ComponentCost>(mixture_.component(j), cost_args...));
    }
  }

  // Whether a T_oc computed by Prepare can be compared (no NaN or Inf).
  static bool IsFinite(const Rigid3d& T_oc) {
    return T_oc.q.coeffs().allFinite() && T_oc.t.allFinite();
  }

 private:
  PoseMixture mixture_;
  std::vector<std::unique_ptr<ComponentCost>> component_costs_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_MIXTURE_MODEL_H_
