// How far each map object can be trusted: the marginal covariance of its
// parameters at the current estimate (docs/backend.md "Covariances").
#ifndef SYMBA_BACKEND_OBJECT_COVARIANCE_H_
#define SYMBA_BACKEND_OBJECT_COVARIANCE_H_

#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/ids.h"

namespace symba {

struct MapObjectCovariance {
  ObjectId id = 0;
  // Where it comes from: the last solve (jointly with the cameras, points
  // and objects it held free; what it held constant counts as known), or,
  // for an object no keyframe of the window sees, the prior its
  // marginalised observations left; or, once keyframes have left the
  // window, the keyframe graph (every keyframe since the first, its camera
  // motion and the objects' detections), so that the cameras' uncertainty
  // since the first keyframe is in it.
  enum class Source { kSolve, kPrior, kKeyframeGraph };
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

// The source's name in objects.json and map files: "solve", "prior",
// "keyframe_graph".
inline const char* CovarianceSourceName(MapObjectCovariance::Source source) {
  switch (source) {
    case MapObjectCovariance::Source::kSolve:
      return "solve";
    case MapObjectCovariance::Source::kPrior:
      return "prior";
    case MapObjectCovariance::Source::kKeyframeGraph:
      return "keyframe_graph";
  }
  return "solve";
}

// The source named `name`; false for another name.
inline bool CovarianceSourceFromName(std::string_view name,
                                     MapObjectCovariance::Source* source) {
  for (const MapObjectCovariance::Source s :
       {MapObjectCovariance::Source::kSolve,
        MapObjectCovariance::Source::kPrior,
        MapObjectCovariance::Source::kKeyframeGraph}) {
    if (name == CovarianceSourceName(s)) {
      *source = s;
      return true;
    }
  }
  return false;
}

}  // namespace symba

#endif  // SYMBA_BACKEND_OBJECT_COVARIANCE_H_
