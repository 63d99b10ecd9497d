// How far each map object can be trusted: the marginal covariance of its
// parameters at the current estimate (docs/backend.md "Covariances").
#ifndef SYMBA_BACKEND_OBJECT_COVARIANCE_H_
#define SYMBA_BACKEND_OBJECT_COVARIANCE_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/ids.h"

namespace symba {

struct MapObjectCovariance {
  ObjectId id = 0;
  // Where it comes from: the last solve (jointly with the cameras, points
  // and objects it held free; what it held constant counts as known), or,
  // for an object no keyframe of the window sees, the prior its
  // marginalised observations left.
  enum class Source { kSolve, kPrior };
  Source source = Source::kSolve;
  // The position t_wo, world frame (m^2).
  Eigen::Matrix3d position = Eigen::Matrix3d::Zero();
  // Asymmetric: the rotation error w (rad^2) of R_wo = Exp(w) R_wo_estimate,
  // a world-frame rotation vector.
  std::optional<Eigen::Matrix3d> rotation;
  // Symmetric: the unit world axis a_w (3x3, rank 2: its error is tangent
  // to the sphere; rad^2 for small errors).
  std::optional<Eigen::Matrix3d> axis;
  // Discrete: each angle theta_i's variance (rad^2), in the order of
  // MapObjectEstimate::angles; nullopt for an angle neither source holds.
  std::vector<std::optional<double>> angle_variances;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_OBJECT_COVARIANCE_H_
