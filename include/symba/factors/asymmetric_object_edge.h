// Asymmetric object edge: a max-mixture over a detection's pose hypotheses of
// the SE(3) log error between the hypothesis and the estimated object pose
// seen from the camera (paper Eq. 3; docs/method.md, Eq. 15).
//
//   e_j = LogSE3(T_co^j * T_wo^-1 * T_wc)       (6: [rho; omega], m and rad)
//   residual = [ L_j* e_j* ; sqrt(2 (k_j* - k_min)) ]   (7, see max_mixture.h)
//
// Parameter blocks, in order (quaternions with EigenQuaternionManifold):
//   q_wc  4  camera rotation, Eigen order [x, y, z, w]
//   t_wc  3  camera position in the world (m)
//   q_wo  4  object rotation, Eigen order [x, y, z, w]
//   t_wo  3  object position in the world (m)
// The edge owns copies of its components. The winner's Jacobians are
// hand-written (AsymmetricComponentCost); ComponentFunctor is the same
// residual as a template.
#ifndef SYMBA_FACTORS_ASYMMETRIC_OBJECT_EDGE_H_
#define SYMBA_FACTORS_ASYMMETRIC_OBJECT_EDGE_H_

#include <memory>
#include <utility>
#include <vector>

#include <ceres/sized_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/common/status.h"
#include "symba/factors/max_mixture.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/pose_mixture.h"
#include "symba/factors/pose_mixture_model.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// T_oc = T_wo^-1 T_wc from the four parameter blocks.
template <typename T>
Rigid3<T> CameraInObject(const T* q_wc,
                         const T* t_wc,
                         const T* q_wo,
                         const T* t_wo) {
  const Rigid3<T> T_wc{Eigen::Map<const Eigen::Quaternion<T>>(q_wc),
                       Eigen::Map<const Vector3<T>>(t_wc)};
  const Rigid3<T> T_wo{Eigen::Map<const Eigen::Quaternion<T>>(q_wo),
                       Eigen::Map<const Vector3<T>>(t_wo)};
  return T_wo.Inverse() * T_wc;
}

// The winner's residual with hand-written Jacobians (PoseComponentResidual,
// whose blocks are this edge's).
class AsymmetricComponentCost final
    : public ceres::SizedCostFunction<6, 4, 3, 4, 3> {
 public:
  explicit AsymmetricComponentCost(const PoseComponent& component)
      : residual_(component) {}

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    residual_.Evaluate(parameters[0],
                       parameters[1],
                       parameters[2],
                       parameters[3],
                       residuals,
                       jacobians);
    return true;
  }

 private:
  PoseComponentResidual residual_;
};

// The edge's model: T_oc = T_wo^-1 T_wc.
class AsymmetricPoseModel final
    : public PoseMixtureModel<AsymmetricComponentCost> {
 public:
  // One component's residual as a template (what AsymmetricComponentCost
  // evaluates; the tests autodiff it).
  struct ComponentFunctor {
    PoseComponent component;
    template <typename T>
    bool operator()(const T* q_wc,
                    const T* t_wc,
                    const T* q_wo,
                    const T* t_wo,
                    T* residual) const {
      PoseLogResidual(
          component, CameraInObject(q_wc, t_wc, q_wo, t_wo), residual);
      return true;
    }
  };

  explicit AsymmetricPoseModel(std::vector<PoseComponent> components)
      : PoseMixtureModel(std::move(components)) {}

  bool Prepare(double const* const* parameters, Rigid3d* T_oc) const {
    *T_oc = CameraInObject(
        parameters[0], parameters[1], parameters[2], parameters[3]);
    return IsFinite(*T_oc);
  }
};

using AsymmetricObjectEdge =
    MaxMixtureCostFunction<AsymmetricPoseModel, 4, 3, 4, 3>;

// Validates the components and options and builds the edge.
inline Status CreateAsymmetricObjectEdge(
    std::vector<PoseComponent> components,
    const MixtureOptions& options,
    std::unique_ptr<AsymmetricObjectEdge>* edge) {
  Status status = ValidatePoseComponents(components);
  if (!status.ok()) return status;
  if (!options.IsValid()) return Status::Error("invalid mixture options");
  *edge = std::make_unique<AsymmetricObjectEdge>(
      AsymmetricPoseModel(std::move(components)), options);
  return Status::Ok();
}

}  // namespace symba

#endif  // SYMBA_FACTORS_ASYMMETRIC_OBJECT_EDGE_H_
