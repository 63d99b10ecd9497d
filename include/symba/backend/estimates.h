// What the backend reports back: camera poses, map objects and, for every
// detection, the map object it went to and the type it was given.
#ifndef SYMBA_BACKEND_ESTIMATES_H_
#define SYMBA_BACKEND_ESTIMATES_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/categorization/symmetry_type.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct KeyframeEstimate {
  int64_t id = 0;
  double timestamp = 0.0;
  Rigid3d T_wc;
};

struct MapObjectEstimate {
  int id = 0;
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
};

struct DetectionAssignment {
  int64_t keyframe = 0;
  std::string detection;
  int object = -1;                                    // map object id
  SymmetryType symmetry = SymmetryType::kAsymmetric;  // as categorised
};

}  // namespace symba

#endif  // SYMBA_BACKEND_ESTIMATES_H_
