// Discrete object edge: one max-mixture per symmetry angle of a discrete
// symmetric object, over the hypotheses of that angle's cluster (paper Eq. 4,
// generalised to any axis; docs/method.md, Eq. 16-17).
//
//   R_wo_i = Swing(a_w0 -> a_w) * R_base * Rot(a_o, theta_i)
//   T_wo_i = (R_wo_i, t_wo)
//   e_j    = LogSE3(T_co^j * T_wo_i^-1 * T_wc)      (6: [rho; omega])
//   residual = [ L_j* e_j* ; sqrt(2 (k_j* - k_min)) ]   (7, see max_mixture.h)
//
// Swing(u -> v) is MinimalRotation(u, v) (singular only at v = -u) and
// Rot(a, theta) = ExpSO3(theta a). The anchor (a_o, R_base, a_w0) is fixed per
// map object: a_o the symmetry axis in the object frame, R_base a rotation
// with R_base a_o = a_w0, a_w0 the world axis when the object was created.
// With R_base = I and a_o = a_w0 this is the paper's exp(theta a_w).
//
// Parameter blocks, in order:
//   q_wc   4  camera rotation, Eigen order [x, y, z, w]
//   t_wc   3  camera position (m)
//   t_wo   3  object position (m), shared by all angles of the object
//   a_w    3  unit symmetry axis in the world (AxisManifold), shared
//   theta  1  this edge's symmetry angle (rad)
//
// The winner's Jacobians are hand-written (DiscreteComponentCost, Jets only
// through LogSE3 and SymmetricObjectRotation); ComponentFunctor is the same
// residual as a template.
#ifndef SYMBA_FACTORS_DISCRETE_OBJECT_EDGE_H_
#define SYMBA_FACTORS_DISCRETE_OBJECT_EDGE_H_

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include <ceres/jet.h>
#include <ceres/sized_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/common/status.h"
#include "symba/factors/max_mixture.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/pose_mixture.h"
#include "symba/factors/pose_mixture_model.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/swing_twist.h"

namespace symba {

// The fixed frame of a symmetric map object's rotation (see above).
struct SymmetryAnchor {
  Eigen::Vector3d a_o = Eigen::Vector3d::UnitZ();  // axis, object frame
  Eigen::Quaterniond q_base = Eigen::Quaterniond::Identity();
  Eigen::Vector3d a_w0 = Eigen::Vector3d::UnitZ();  // = q_base * a_o

  // The anchor that makes theta = 0, a_w = a_w0 reproduce R_wo.
  static SymmetryAnchor FromObjectRotation(const Eigen::Quaterniond& q_wo,
                                           const Eigen::Vector3d& a_o) {
    SymmetryAnchor anchor;
    anchor.a_o = a_o.normalized();
    anchor.q_base = q_wo.normalized();
    anchor.a_w0 = anchor.q_base * anchor.a_o;
    return anchor;
  }
};

// R_wo_i of the model above, for double or ceres::Jet.
template <typename T>
Eigen::Quaternion<T> SymmetricObjectRotation(const SymmetryAnchor& anchor,
                                             const Vector3<T>& a_w,
                                             const T& theta) {
  const Vector3<T> a_w0 = anchor.a_w0.template cast<T>();
  const Vector3<T> a_o = anchor.a_o.template cast<T>();
  return MinimalRotation(a_w0, a_w) * anchor.q_base.template cast<T>() *
         ExpSO3(Vector3<T>(theta * a_o));
}

template <typename T>
Rigid3<T> CameraInSymmetricObject(const SymmetryAnchor& anchor,
                                  const T* q_wc,
                                  const T* t_wc,
                                  const T* t_wo,
                                  const T* a_w,
                                  const T* theta) {
  const Rigid3<T> T_wc{Eigen::Map<const Eigen::Quaternion<T>>(q_wc),
                       Eigen::Map<const Vector3<T>>(t_wc)};
  const Rigid3<T> T_wo{
      SymmetricObjectRotation(
          anchor, Vector3<T>(Eigen::Map<const Vector3<T>>(a_w)), theta[0]),
      Eigen::Map<const Vector3<T>>(t_wo)};
  return T_wo.Inverse() * T_wc;
}

// The winner's residual with hand-written Jacobians: PoseComponentResidual
// at q_wo = SymmetricObjectRotation(anchor, a_w, theta), with
//   dr/da_w = dr/dq_wo dq_wo/da_w,   dr/dtheta = dr/dq_wo dq_wo/dtheta,
// where the 4 x 4 Jacobian dq_wo/d(a_w, theta) comes from 4-lane Jets through
// SymmetricObjectRotation.
class DiscreteComponentCost final
    : public ceres::SizedCostFunction<6, 4, 3, 3, 3, 1> {
 public:
  DiscreteComponentCost(const PoseComponent& component,
                        const SymmetryAnchor& anchor)
      : residual_(component), anchor_(anchor) {}

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const double* a_w = parameters[3];
    const double theta = parameters[4][0];
    const bool want_rotation =
        jacobians != nullptr &&
        (jacobians[3] != nullptr || jacobians[4] != nullptr);
    double q_wo[4];
    Eigen::Matrix<double, 4, 4> dq_wo;  // columns: a_w (3), theta
    if (want_rotation) {
      using Jet4 = ceres::Jet<double, 4>;
      const Vector3<Jet4> a(Jet4(a_w[0], 0), Jet4(a_w[1], 1), Jet4(a_w[2], 2));
      const Eigen::Quaternion<Jet4> q =
          SymmetricObjectRotation(anchor_, a, Jet4(theta, 3));
      for (int k = 0; k < 4; ++k) {
        q_wo[k] = q.coeffs()(k).a;
        dq_wo.row(k) = q.coeffs()(k).v.transpose();
      }
    } else {
      Eigen::Map<Eigen::Quaterniond>{q_wo} = SymmetricObjectRotation(
          anchor_,
          Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(a_w)),
          theta);
    }
    Eigen::Matrix<double, 6, 4, Eigen::RowMajor> dr_dq_wo;
    double* pose_jacobians[4] = {nullptr, nullptr, nullptr, nullptr};
    if (jacobians != nullptr) {
      pose_jacobians[0] = jacobians[0];
      pose_jacobians[1] = jacobians[1];
      pose_jacobians[2] = want_rotation ? dr_dq_wo.data() : nullptr;
      pose_jacobians[3] = jacobians[2];
    }
    residual_.Evaluate(parameters[0],
                       parameters[1],
                       q_wo,
                       parameters[2],
                       residuals,
                       pose_jacobians);
    if (!want_rotation) return true;
    if (jacobians[3] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>>{jacobians[3]} =
          dr_dq_wo * dq_wo.leftCols<3>();
    }
    if (jacobians[4] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 6, 1>>{jacobians[4]} =
          dr_dq_wo * dq_wo.col(3);
    }
    return true;
  }

 private:
  PoseComponentResidual residual_;
  SymmetryAnchor anchor_;
};

// The edge's model: T_oc from the camera, the object position, its axis and
// its angle about the axis (CameraInSymmetricObject).
class DiscretePoseModel final : public PoseMixtureModel<DiscreteComponentCost> {
 public:
  // One component's residual as a template (what DiscreteComponentCost
  // evaluates; the tests autodiff it).
  struct ComponentFunctor {
    PoseComponent component;
    SymmetryAnchor anchor;
    template <typename T>
    bool operator()(const T* q_wc,
                    const T* t_wc,
                    const T* t_wo,
                    const T* a_w,
                    const T* theta,
                    T* residual) const {
      PoseLogResidual(
          component,
          CameraInSymmetricObject(anchor, q_wc, t_wc, t_wo, a_w, theta),
          residual);
      return true;
    }
  };

  DiscretePoseModel(std::vector<PoseComponent> components,
                    const SymmetryAnchor& anchor)
      : PoseMixtureModel(std::move(components), anchor), anchor_(anchor) {}

  bool Prepare(double const* const* parameters, Rigid3d* T_oc) const {
    *T_oc = CameraInSymmetricObject(anchor_,
                                    parameters[0],
                                    parameters[1],
                                    parameters[2],
                                    parameters[3],
                                    parameters[4]);
    return IsFinite(*T_oc);
  }

 private:
  SymmetryAnchor anchor_;
};

using DiscreteObjectEdge =
    MaxMixtureCostFunction<DiscretePoseModel, 4, 3, 3, 3, 1>;

inline Status ValidateSymmetryAnchor(const SymmetryAnchor& anchor) {
  if (!anchor.a_o.allFinite() || !anchor.a_w0.allFinite() ||
      !anchor.q_base.coeffs().allFinite()) {
    return Status::Error("symmetry anchor is not finite");
  }
  if (std::abs(anchor.a_o.norm() - 1.0) > 1e-6 ||
      std::abs(anchor.a_w0.norm() - 1.0) > 1e-6 ||
      std::abs(anchor.q_base.norm() - 1.0) > 1e-6) {
    return Status::Error("symmetry anchor axes and rotation must be unit");
  }
  if ((anchor.q_base * anchor.a_o - anchor.a_w0).norm() > 1e-6) {
    return Status::Error("symmetry anchor: R_base a_o must equal a_w0");
  }
  return Status::Ok();
}

inline Status CreateDiscreteObjectEdge(
    std::vector<PoseComponent> components,
    const SymmetryAnchor& anchor,
    const MixtureOptions& options,
    std::unique_ptr<DiscreteObjectEdge>* edge) {
  Status status = ValidatePoseComponents(components);
  if (!status.ok()) return status;
  status = ValidateSymmetryAnchor(anchor);
  if (!status.ok()) return status;
  if (!options.IsValid()) return Status::Error("invalid mixture options");
  *edge = std::make_unique<DiscreteObjectEdge>(
      DiscretePoseModel(std::move(components), anchor), options);
  return Status::Ok();
}

}  // namespace symba

#endif  // SYMBA_FACTORS_DISCRETE_OBJECT_EDGE_H_
