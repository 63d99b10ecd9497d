// Export of a log v1 to the files `symba import bop` reads (`symba export
// bop`, docs/import.md "Export"): a detector's BOP results and the
// dataset's camera and model files, plus the front end as a TUM trajectory,
// so that a simulated sequence can go through the BOP import and back.
//
// Files (every keyframe is an image, im_id = keyframe id):
//   results.csv         every hypothesis a row (bop_results_csv.h): obj_id
//                       of the detection's class, score = the hypothesis'
//                       weight, R, t = T_co (mm), time -1; a detection's
//                       best (highest-weight, the first of equal ones)
//                       hypothesis first, the others in the log's order, so
//                       that the importer's gate, which groups rows around
//                       a detection's first row, groups them around it
//   scene_camera.json   per image: cam_K (the header camera), cam_R_w2c,
//                       cam_t_w2c = T_cw = T_wc^-1 of the front end (mm)
//   models_info.json    per obj_id: diameter (options.diameter, mm) and the
//                       class's symmetry: discrete of order n about a ->
//                       symmetries_discrete, the n - 1 rotations
//                       Rot(a, 2 pi m / n), m = 1..n-1, as 4x4 row-major
//                       transforms with zero translation; continuous about
//                       a -> symmetries_continuous [{axis a, offset 0}];
//                       asymmetric or unknown -> no symmetry key
//   image_times.txt     "im_id timestamp" per image (the keyframe's time)
//   frontend.tum        the front end's T_wc per image, a TUM trajectory;
//                       not written (a note says why) when two keyframes
//                       share a time, which a log allows and TUM does not
//   class_names.txt     "1=table,2=mug": the --class-names of the import;
//                       not written (a note says why) when a class name
//                       has a comma, which --class-names cannot carry
// The front end's pose of a keyframe is its T_wc, else the previous one's
// composed with its odometry (T_wc(k) = T_wc(k-1) T_{k-1,k}). Object ids
// are 1, 2, ... over the class names in byte order (the header's classes
// and the detections' classes). Point observations, odometry noise and the
// detections' sigma_t/sigma_r have no place in these files and are dropped.
#ifndef SYMBA_EXPORT_BOP_EXPORT_H_
#define SYMBA_EXPORT_BOP_EXPORT_H_

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "symba/categorization/categorize.h"
#include "symba/common/status.h"

namespace symba {

// The objects of the simulator have no extent; 1 m makes the importer's
// gate (half the diameter) 0.5 m: far beyond the spread of one detection's
// hypotheses (outliers: 0.1 m per axis) and below the 1.3 m between the
// two round tables of the `room` scene.
inline constexpr double kBopExportDefaultDiameter = 1.0;  // m

struct BopExportOptions {
  int scene_id = 1;                             // >= 0
  double diameter = kBopExportDefaultDiameter;  // m, > 0, every object's
  // Each class's symmetry for models_info.json (a symmetric one needs its
  // axis); a class not listed takes the log header's class prior.
  std::map<std::string, ClassPrior> symmetries;
};

struct BopExportReport {
  int images = 0;
  int rows = 0;
  std::map<std::string, int> obj_ids;  // class name -> obj_id
  // Classes whose symmetry is unknown or lacks its axis, one sentence each
  // (written without symmetries, which BOP reads as asymmetric), and
  // frontend.tum left out when keyframe times repeat, class_names.txt when
  // a class name has a comma.
  std::vector<std::string> notes;
};

// Reads `log_path` (strictly, LogReader) and formats the files above
// as (name, content). Errors: the log's ("FILE:LINE: reason"), no camera in
// the header ("LOG: header: no camera; ..."), a keyframe id that is no
// im_id ("LOG:LINE: keyframe -1: ..."), invalid options ("options: ...").
Status ExportLogToBop(const std::string& log_path,
                      const BopExportOptions& options,
                      std::vector<std::pair<std::string, std::string>>* files,
                      BopExportReport* report);

// ExportLogToBop written as the directory `out_dir`, atomically
// (WriteDirectoryAtomically: complete or not at all).
Status ExportLogToBopDirectory(const std::string& log_path,
                               const BopExportOptions& options,
                               const std::string& out_dir,
                               BopExportReport* report);

// Each class's true symmetry from a simulation's gt_objects.json
// (symmetry, order, axis_o). Two objects of one class with different
// symmetries are an error ("PATH: class "x": ...").
Status ClassSymmetriesFromGroundTruth(
    const std::string& gt_objects_path,
    std::map<std::string, ClassPrior>* symmetries);

}  // namespace symba

#endif  // SYMBA_EXPORT_BOP_EXPORT_H_
