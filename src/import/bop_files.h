// Internal to symba import bop (symba/import/bop_import.h): the readers of
// the BOP files, each strict and naming FILE:LINE or FILE: PATH in its
// errors, and the mapping of BOP symmetries onto symba's three types.
#ifndef SYMBA_SRC_IMPORT_BOP_FILES_H_
#define SYMBA_SRC_IMPORT_BOP_FILES_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/categorization/categorize.h"
#include "symba/common/status.h"
#include "symba/geometry/pinhole_intrinsics.h"
#include "symba/geometry/rigid3.h"

namespace symba::import_internal {

// One row of a BOP results CSV: scene_id,im_id,obj_id,score,R,t,time.
struct BopResultRow {
  int scene_id = 0;
  int im_id = 0;
  int obj_id = 0;
  double score = 0.0;
  Rigid3d T_co;  // metres
  int line = 0;  // 1-based
};

// Reads the CSV (an optional header line, which starts with "scene_id" and
// must name the seven columns; blank lines skipped). With `scene` set, rows
// of other scenes are skipped and counted in `other_scene_rows` (optional);
// without it every row must be of the first row's scene.
Status ReadBopResults(const std::string& path,
                      const std::optional<int>& scene,
                      std::vector<BopResultRow>* rows,
                      int* other_scene_rows = nullptr);

// One image of scene_camera.json.
struct BopImage {
  int im_id = 0;
  PinholeIntrinsics camera;     // cam_K
  std::optional<Rigid3d> T_cw;  // cam_R_w2c, cam_t_w2c (metres)
};

// Every image of scene_camera.json, by increasing im_id.
Status ReadBopSceneCamera(const std::string& path,
                          std::vector<BopImage>* images);

// One object of models_info.json.
struct BopModel {
  double diameter = 0.0;  // m; 0 when not given
  ClassPrior prior;       // from its symmetries
  std::string note;       // how inexact symmetries were mapped; "" if exact
};

Status ReadBopModelsInfo(const std::string& path,
                         std::map<int, BopModel>* models);

// A continuous symmetry of models_info.json: a rotation axis through
// `offset` (object frame, m).
struct BopContinuousSymmetry {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

// The ClassPrior closest to a BOP symmetry set (docs/import.md has the
// table): none -> asymmetric; one continuous axis -> continuous about it;
// discrete rotations forming the cyclic group of one axis -> discrete of
// that order; anything else as well as the three types allow, said in
// `note` (left empty when the mapping is exact).
ClassPrior MapBopSymmetries(
    const std::vector<Rigid3d>& discrete,
    const std::vector<BopContinuousSymmetry>& continuous,
    std::string* note);

// The images' timestamps: "im_id timestamp" lines, or TUM's rgb.txt
// ("timestamp filename"; im_id = the line's index among the data lines,
// from 0). '#' comments and blank lines are skipped.
struct ImageTime {
  int im_id = 0;
  double timestamp = 0.0;
  int line = 0;
};
Status ReadImageTimes(const std::string& path, std::vector<ImageTime>* times);

}  // namespace symba::import_internal

#endif  // SYMBA_SRC_IMPORT_BOP_FILES_H_
