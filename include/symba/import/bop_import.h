// Import of a detector's BOP results (docs/import.md "symba import bop"):
// the BOP challenge's results CSV, the dataset's scene_camera.json and
// (optionally) models_info.json, and either the camera poses in
// scene_camera.json or a front end's TUM trajectory matched to the images'
// timestamps, into a symba log v1.
//
// Units and frames: the CSV's R, t are model-to-camera (T_co), t in
// millimetres; scene_camera.json's cam_R_w2c, cam_t_w2c are world-to-camera
// (T_cw), t in millimetres; models_info.json lengths are millimetres. The
// log is in metres with camera-to-world keyframe poses (T_wc = T_cw^-1) and
// T_co hypotheses, quaternions [x, y, z, w].
//
// Every image of scene_camera.json (with a pose) is a keyframe; its id is
// the image id, its time the image's timestamp from image_times when given,
// else the image id. Each keyframe carries T_wc (the front end's pose) and
// no odometry. The rows of one image and object id are grouped into
// detections: a row joins the first detection (in the order of their first
// rows) whose first row's translation is within the gate of its own, else
// it starts a new detection. A detection's id is "<im_id>/<j>", j counting
// the image's detections from 0 in the order of their first rows; its
// hypotheses are its rows, weighted by their scores (all 1 when a score is
// not positive); its score is the highest.
#ifndef SYMBA_IMPORT_BOP_IMPORT_H_
#define SYMBA_IMPORT_BOP_IMPORT_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "symba/backend/keyframe_input.h"
#include "symba/common/status.h"
#include "symba/io/log_format.h"

namespace symba {

struct BopImportOptions {
  std::string results;       // the results CSV
  std::string scene_camera;  // scene_camera.json
  std::string models_info;   // models_info.json; empty: no class priors
  // A front end's TUM trajectory (T_wc), which needs the images' timestamps
  // to match it; without it the poses come from scene_camera.json. The
  // timestamps, when given, are the keyframes' times with either source
  // (else t = im_id).
  std::string trajectory;
  std::string image_times;
  // The scene to import; empty: the CSV's only scene (several are an error).
  std::optional<int> scene;
  std::map<int, std::string> class_names;  // obj_id -> name; else obj_<id>
  // Rows of one image and object within this distance (m) are one
  // detection; empty: half the object's diameter from models_info, else
  // kBopDefaultGate.
  std::optional<double> gate;
  // An image without a pose (no w2c in scene_camera.json, or no trajectory
  // pose within time_tolerance) is an error, or skipped when this is set.
  bool skip_images_without_pose = false;
  double time_tolerance = 0.02;  // s, image time to trajectory time
  // Written on every detection when set (> 0).
  std::optional<double> detection_sigma_t;  // m
  std::optional<double> detection_sigma_r;  // rad
};

// The gate when neither the option nor models_info gives one [m].
inline constexpr double kBopDefaultGate = 0.05;

struct BopImportReport {
  int rows = 0;  // CSV rows of the imported scene
  int keyframes = 0;
  int detections = 0;
  int skipped_images = 0;    // without a pose (skip_images_without_pose)
  int skipped_rows = 0;      // rows of skipped images
  int other_scene_rows = 0;  // with `scene`: rows of other scenes, skipped
  // How each object's BOP symmetries were mapped when the three types
  // cannot express them exactly, one sentence each (for stderr).
  std::vector<std::string> symmetry_notes;
};

// Reads every input strictly and builds the log in memory. Errors read
// "FILE:LINE: reason" for a line of the CSV or a text file, "FILE: PATH:
// reason" for a JSON value, "FILE: reason" for a file, "option: reason" for
// an invalid option. `report` may be null.
Status ImportBop(const BopImportOptions& options,
                 LogHeader* header,
                 std::vector<KeyframeInput>* keyframes,
                 BopImportReport* report);

// ImportBop, then WriteLogAtomically to `log_path`: on any error `log_path`
// is left as it was. The keyframes are made and written one at a time.
Status ImportBopToLog(const BopImportOptions& options,
                      const std::string& log_path,
                      BopImportReport* report);

// "1=ape,2=can": obj_id=name pairs, comma-separated (--class-names).
// Errors read `class names "TEXT": reason`.
Status ParseBopClassNames(const std::string& text,
                          std::map<int, std::string>* names);

}  // namespace symba

#endif  // SYMBA_IMPORT_BOP_IMPORT_H_
