#include "symba/export/bop_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "export/bop_units.h"
#include "io/json_writer.h"
#include "symba/export/bop_results_csv.h"
#include "symba/geometry/angle.h"
#include "symba/io/file_output.h"
#include "symba/io/format_double.h"
#include "symba/io/ground_truth_objects.h"
#include "symba/io/log_format.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

using internal::kMillimetresPerMetre;
using io_internal::JsonWriter;

struct ExportInput {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
};

Status CheckOptions(const BopExportOptions& o) {
  if (o.scene_id < 0) {
    return Status::Error(
        "options: scene id: must be a non-negative integer, "
        "got " +
        std::to_string(o.scene_id));
  }
  // Written in millimetres, so 1000 times it must be finite too.
  if (!(o.diameter > 0.0) || !std::isfinite(1000.0 * o.diameter)) {
    return Status::Error("options: diameter: must be positive, got " +
                         FormatDouble(o.diameter));
  }
  return Status::Ok();
}

// The whole log; every keyframe id must be an im_id (an int >= 0).
Status ReadExportInput(const std::string& path, ExportInput* input) {
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::Open(path, &reader);
  if (!status.ok()) return status;
  input->header = reader->header();
  if (!input->header.camera) {
    return Status::Error(path +
                         ": header: no camera; scene_camera.json needs cam_K "
                         "(the intrinsics)");
  }
  for (;;) {
    KeyframeInput keyframe;
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (!status.ok() || end) return status;
    if (keyframe.id < 0 || keyframe.id > std::numeric_limits<int>::max()) {
      return Status::Error(path + ":" + std::to_string(reader->line()) +
                           ": keyframe " + std::to_string(keyframe.id) +
                           ": not a BOP im_id (an integer from 0 to " +
                           std::to_string(std::numeric_limits<int>::max()) +
                           ")");
    }
    input->keyframes.push_back(std::move(keyframe));
  }
}

// 1, 2, ... over the class names (the header's and the detections') in
// byte order.
std::map<std::string, int> ObjIds(const ExportInput& input) {
  std::map<std::string, int> ids;
  for (const auto& entry : input.header.classes) ids[entry.first] = 0;
  for (const KeyframeInput& keyframe : input.keyframes) {
    for (const DetectionInput& d : keyframe.detections) ids[d.class_name] = 0;
  }
  int next = 1;
  for (auto& entry : ids) entry.second = next++;
  return ids;
}

// The front end's T_wc per keyframe: its own, else the previous keyframe's
// composed with its odometry, T_wc(k) = T_wc(k-1) T_{k-1,k} (the log
// format guarantees T_wc on the first keyframe and one of the two later).
std::vector<Rigid3d> FrontEndPoses(
    const std::vector<KeyframeInput>& keyframes) {
  std::vector<Rigid3d> poses;
  for (const KeyframeInput& keyframe : keyframes) {
    if (keyframe.T_wc) {
      poses.push_back(*keyframe.T_wc);
    } else {
      poses.push_back(poses.back() * keyframe.odometry->T_prev_cur);
    }
  }
  return poses;
}

// Where a detection's hypotheses go in the CSV: the best first, the others
// in their order.
std::vector<std::size_t> RowOrder(const DetectionInput& detection) {
  std::size_t best = 0;
  for (std::size_t h = 1; h < detection.hypotheses.size(); ++h) {
    if (detection.hypotheses[h].weight > detection.hypotheses[best].weight) {
      best = h;
    }
  }
  std::vector<std::size_t> order = {best};
  for (std::size_t h = 0; h < detection.hypotheses.size(); ++h) {
    if (h != best) order.push_back(h);
  }
  return order;
}

std::vector<BopResult> Results(const std::vector<KeyframeInput>& keyframes,
                               const std::map<std::string, int>& obj_ids,
                               int scene_id) {
  std::vector<BopResult> rows;
  for (const KeyframeInput& keyframe : keyframes) {
    for (const DetectionInput& detection : keyframe.detections) {
      for (std::size_t h : RowOrder(detection)) {
        BopResult row;
        row.scene_id = scene_id;
        row.im_id = static_cast<int>(keyframe.id);
        row.obj_id = obj_ids.at(detection.class_name);
        row.score = detection.hypotheses[h].weight;
        row.T_co = detection.hypotheses[h].T_co;
        rows.push_back(row);
      }
    }
  }
  return rows;
}

// A 3x3 matrix as nine numbers, row-major.
void RowMajor(const Eigen::Matrix3d& m, double out[9]) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[3 * r + c] = m(r, c);
  }
}

// {"<im_id>": {"cam_K": [...], "cam_R_w2c": [...], "cam_t_w2c": [...]}}:
// cam_R_w2c, cam_t_w2c are T_cw = T_wc^-1, the translation in mm.
std::string SceneCameraJson(const PinholeIntrinsics& camera,
                            const std::vector<KeyframeInput>& keyframes,
                            const std::vector<Rigid3d>& T_wc) {
  const double K[9] = {
      camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  std::string text;
  JsonWriter json(&text, 1);
  json.BeginObject();
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const Rigid3d T_cw = T_wc[k].Inverse();
    double R[9];
    RowMajor(T_cw.RotationMatrix(), R);
    const Eigen::Vector3d t_mm = kMillimetresPerMetre * T_cw.t;
    json.Key(std::to_string(keyframes[k].id)).BeginObject();
    json.Key("cam_K").Doubles(K, 9);
    json.Key("cam_R_w2c").Doubles(R, 9);
    json.Key("cam_t_w2c").Doubles(t_mm.data(), 3);
    json.EndObject();
  }
  json.EndObject();
  text.push_back('\n');
  return text;
}

// The 4x4 row-major transform of a rotation about an axis through the
// origin.
void RotationTransform(const Eigen::Vector3d& axis,
                       double angle,
                       double out[16]) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      out[4 * r + c] = (r < 3 && c < 3) ? R(r, c) : (r == c ? 1.0 : 0.0);
    }
  }
}

// The symmetry keys of one model; false (nothing written) when the symmetry
// is unknown or has no axis.
bool WriteSymmetries(const std::optional<ClassPrior>& prior, JsonWriter* json) {
  if (!prior || prior->symmetry == SymmetryType::kAsymmetric)
    return prior.has_value();
  if (prior->axis_o.isZero(0.0)) return false;
  if (prior->symmetry == SymmetryType::kDiscrete && prior->order < 2) {
    return false;
  }
  const Eigen::Vector3d axis = prior->axis_o.normalized();
  if (prior->symmetry == SymmetryType::kContinuous) {
    const double offset[3] = {0.0, 0.0, 0.0};
    json->Key("symmetries_continuous").BeginArray().BeginObject();
    json->Key("axis").Doubles(axis.data(), 3);
    json->Key("offset").Doubles(offset, 3);
    json->EndObject().EndArray();
    return true;
  }
  json->Key("symmetries_discrete").BeginArray();
  for (int m = 1; m < prior->order; ++m) {
    double transform[16];
    RotationTransform(axis, 2.0 * kPi * m / prior->order, transform);
    json->Doubles(transform, 16);
  }
  json->EndArray();
  return true;
}

std::optional<ClassPrior> SymmetryOf(const std::string& name,
                                     const BopExportOptions& options,
                                     const LogHeader& header) {
  if (const auto it = options.symmetries.find(name);
      it != options.symmetries.end()) {
    return it->second;
  }
  if (const auto it = header.classes.find(name); it != header.classes.end()) {
    return it->second;
  }
  return std::nullopt;
}

std::string ModelsInfoJson(const std::map<std::string, int>& obj_ids,
                           const BopExportOptions& options,
                           const LogHeader& header,
                           std::vector<std::string>* notes) {
  std::string text;
  JsonWriter json(&text, 1);
  json.BeginObject();
  for (const auto& [name, obj_id] : obj_ids) {
    json.Key(std::to_string(obj_id)).BeginObject();
    json.Member("diameter", kMillimetresPerMetre * options.diameter);
    if (!WriteSymmetries(SymmetryOf(name, options, header), &json)) {
      notes->push_back("class \"" + name + "\" (obj_id " +
                       std::to_string(obj_id) +
                       "): symmetry or axis unknown, written without "
                       "symmetries (BOP reads that as asymmetric)");
    }
    json.EndObject();
  }
  json.EndObject();
  text.push_back('\n');
  return text;
}

std::string ImageTimes(const std::vector<KeyframeInput>& keyframes) {
  std::string text;
  for (const KeyframeInput& keyframe : keyframes) {
    text += std::to_string(keyframe.id) + " ";
    AppendDouble(keyframe.timestamp, &text);
    text.push_back('\n');
  }
  return text;
}

// A TUM trajectory needs strictly increasing times (the importer, like every
// TUM reader, refuses a repeated one); a log only needs non-decreasing ones.
// The first keyframe whose time does not follow its predecessor's, or -1.
int FirstRepeatedTime(const std::vector<KeyframeInput>& keyframes) {
  for (std::size_t k = 1; k < keyframes.size(); ++k) {
    if (!(keyframes[k].timestamp > keyframes[k - 1].timestamp)) {
      return static_cast<int>(k);
    }
  }
  return -1;
}

std::string FrontEndTum(const std::vector<KeyframeInput>& keyframes,
                        const std::vector<Rigid3d>& T_wc) {
  std::vector<std::pair<double, Rigid3d>> trajectory;
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    trajectory.emplace_back(keyframes[k].timestamp, T_wc[k]);
  }
  return FormatTumTrajectory(trajectory);
}

std::string ClassNames(const std::map<std::string, int>& obj_ids) {
  std::string text;
  for (const auto& [name, obj_id] : obj_ids) {
    if (!text.empty()) text.push_back(',');
    text += std::to_string(obj_id) + "=" + name;
  }
  text.push_back('\n');
  return text;
}

}  // namespace

Status ExportLogToBop(const std::string& log_path,
                      const BopExportOptions& options,
                      std::vector<std::pair<std::string, std::string>>* files,
                      BopExportReport* report) {
  BopExportReport local;
  BopExportReport& r = report != nullptr ? *report : local;
  r = BopExportReport();
  Status status = CheckOptions(options);
  ExportInput input;
  if (status.ok()) status = ReadExportInput(log_path, &input);
  if (!status.ok()) return status;
  r.obj_ids = ObjIds(input);
  const std::vector<Rigid3d> T_wc = FrontEndPoses(input.keyframes);
  const std::vector<BopResult> rows =
      Results(input.keyframes, r.obj_ids, options.scene_id);
  r.images = static_cast<int>(input.keyframes.size());
  r.rows = static_cast<int>(rows.size());
  files->clear();
  files->emplace_back("results.csv", FormatBopResultsCsv(rows));
  files->emplace_back(
      "scene_camera.json",
      SceneCameraJson(*input.header.camera, input.keyframes, T_wc));
  files->emplace_back(
      "models_info.json",
      ModelsInfoJson(r.obj_ids, options, input.header, &r.notes));
  files->emplace_back("image_times.txt", ImageTimes(input.keyframes));
  const int repeated = FirstRepeatedTime(input.keyframes);
  if (repeated < 0) {
    files->emplace_back("frontend.tum", FrontEndTum(input.keyframes, T_wc));
  } else {
    const KeyframeInput& keyframe = input.keyframes[repeated];
    std::string time;
    AppendDouble(keyframe.timestamp, &time);
    r.notes.push_back("frontend.tum not written: keyframe " +
                      std::to_string(keyframe.id) + " has the time " + time +
                      " of the keyframe before it, and a TUM trajectory "
                      "needs increasing times (scene_camera.json carries "
                      "the same poses)");
  }
  const auto comma =
      std::find_if(r.obj_ids.begin(), r.obj_ids.end(), [](const auto& entry) {
        return entry.first.find(',') != std::string::npos;
      });
  if (comma == r.obj_ids.end()) {
    files->emplace_back("class_names.txt", ClassNames(r.obj_ids));
  } else {
    r.notes.push_back("class_names.txt not written: the class \"" +
                      comma->first +
                      "\" has a comma, which --class-names separates "
                      "pairs with (the import names the classes obj_<id>)");
  }
  return Status::Ok();
}

Status ExportLogToBopDirectory(const std::string& log_path,
                               const BopExportOptions& options,
                               const std::string& out_dir,
                               BopExportReport* report) {
  Status status = CheckOutputSparesInputs(out_dir, {log_path});
  if (!status.ok()) return status;
  std::vector<std::pair<std::string, std::string>> files;
  status = ExportLogToBop(log_path, options, &files, report);
  if (!status.ok()) return status;
  return WriteDirectoryAtomically(out_dir, files);
}

Status ClassSymmetriesFromGroundTruth(
    const std::string& gt_objects_path,
    std::map<std::string, ClassPrior>* symmetries) {
  std::vector<GroundTruthObject> objects;
  std::map<std::string, int> detections;
  Status status =
      ReadGroundTruthObjectsJson(gt_objects_path, &objects, &detections);
  if (!status.ok()) return status;
  for (const GroundTruthObject& object : objects) {
    ClassPrior prior;
    prior.symmetry = object.symmetry;
    prior.order = object.symmetry == SymmetryType::kDiscrete ? object.order : 0;
    prior.axis_o = object.axis_o;
    const auto [it, inserted] = symmetries->emplace(object.class_name, prior);
    const ClassPrior& known = it->second;
    if (!inserted &&
        (known.symmetry != prior.symmetry || known.order != prior.order ||
         !known.axis_o.isApprox(prior.axis_o, 1e-9))) {
      return Status::Error(gt_objects_path + ": class \"" + object.class_name +
                           "\": object " + std::to_string(object.id) +
                           "'s symmetry differs from an earlier object of "
                           "its class");
    }
  }
  return Status::Ok();
}

}  // namespace symba
