// gt_objects.json, the simulator's ground-truth objects (docs/simulation.md,
// docs/evaluation.md): its writer and its strict reader.
//
//   {"objects": [{id, class, symmetry, order, axis_o?, axis?, pose}],
//    "detections": {"<detection id>": <gt object id>}}
//
// axis_o and axis only for symmetric objects; pose is
// {"t": [x, y, z], "q": [qx, qy, qz, qw]}. Numbers are written in the
// shortest form that reads back as the same double (FormatDouble).
#ifndef SYMBA_IO_GROUND_TRUTH_OBJECTS_H_
#define SYMBA_IO_GROUND_TRUTH_OBJECTS_H_

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct GroundTruthObject {
  int id = 0;
  std::string class_name;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  int order = 0;  // discrete: the symmetry order (>= 2); otherwise 0
  // Unit symmetry axis in the object and in the world frame (symmetric
  // objects; zero for asymmetric ones).
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_w = Eigen::Vector3d::Zero();
  Rigid3d T_wo;
};

// The file's text: the objects (pose and axes written as given) and the
// detections in the given order.
std::string FormatGroundTruthObjectsJson(
    const std::vector<GroundTruthObject>& objects,
    const std::vector<std::pair<std::string, int>>& detections);

// Reads gt_objects.json strictly, appending to *objects and filling
// *detection_objects (detection id -> object id). Errors "PATH:LINE: invalid
// JSON: ..." or "PATH: where: reason"; ids are unique, orders consistent
// with the symmetry, axes unit and axis = pose.q * axis_o.
Status ReadGroundTruthObjectsJson(
    const std::string& path,
    std::vector<GroundTruthObject>* objects,
    std::map<std::string, int>* detection_objects);

}  // namespace symba

#endif  // SYMBA_IO_GROUND_TRUTH_OBJECTS_H_
