// What the backend reports back: camera poses, map objects and, for every
// detection, the map object it went to and the type it was given.
#ifndef SYMBA_BACKEND_ESTIMATES_H_
#define SYMBA_BACKEND_ESTIMATES_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/ids.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct KeyframeEstimate {
  KeyframeId id = 0;
  double timestamp = 0.0;
  Rigid3d T_wc;
};

struct MapObjectEstimate {
  ObjectId id = 0;
  std::string class_name;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  Eigen::Vector3d t_wo = Eigen::Vector3d::Zero();
  // Unit world axis and object-frame axis (symmetric objects; zero otherwise).
  Eigen::Vector3d axis_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();
  std::vector<double> angles;  // discrete: theta_i (rad)
  // One pose (asymmetric), one per angle (discrete), or the representative
  // angle-0 pose (continuous).
  std::vector<Rigid3d> poses;
  int observations = 0;  // detections associated with it
  // An asymmetric object that became symmetric: when and on what evidence.
  struct Upgrade {
    KeyframeId keyframe = 0;  // the keyframe of the upgrade
    int evidence = 0;         // agreeing flips, or 1 symmetric detection
    int order = 0;            // the order the flips' angle fits (0: none)
    double angle = 0.0;       // the flips' mean angle (rad; 0 without flips)
  };
  std::optional<Upgrade> upgrade;
};

struct DetectionAssignment {
  KeyframeId keyframe = 0;
  std::string detection;
  // The map object's id; -1 if the detection made a tentative object that
  // was dropped (an outlier). A tentative object's id while it waits for
  // confirmation (it is not in Backend::Objects() until then).
  ObjectId object = -1;
  SymmetryType symmetry = SymmetryType::kAsymmetric;  // as categorised
};

}  // namespace symba

#endif  // SYMBA_BACKEND_ESTIMATES_H_
