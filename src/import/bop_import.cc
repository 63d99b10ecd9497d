#include "symba/import/bop_import.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "import/bop_files.h"
#include "import/bop_source.h"
#include "io/text_file.h"
#include "symba/io/log_file.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace import_internal {

Status ReadImageTimes(const std::string& path, std::vector<ImageTime>* times) {
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  times->clear();
  const std::vector<std::string_view> lines = internal::SplitLines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int line = static_cast<int>(i) + 1;
    if (internal::IsBlank(lines[i]) ||
        lines[i].find_first_not_of(" \t") == lines[i].find('#')) {
      continue;
    }
    const std::vector<std::string_view> f = internal::SplitFields(lines[i]);
    ImageTime time;
    time.line = line;
    double second = 0.0;
    if (f.size() == 2 && internal::ParseDouble(f[1], &second)) {
      // "im_id timestamp"
      time.timestamp = second;
      if (!internal::ParseInteger(f[0], &time.im_id) || time.im_id < 0) {
        return Status::Error(internal::At(path, line) +
                             ": expected \"im_id timestamp\" with a "
                             "non-negative integer im_id");
      }
    } else if (f.size() == 2 && internal::ParseDouble(f[0], &time.timestamp)) {
      // rgb.txt: "timestamp filename"
      time.im_id = static_cast<int>(times->size());
    } else {
      return Status::Error(internal::At(path, line) +
                           ": expected \"im_id timestamp\" or \"timestamp "
                           "filename\" (TUM rgb.txt)");
    }
    for (const ImageTime& other : *times) {
      if (other.im_id == time.im_id) {
        return Status::Error(internal::At(path, line) + ": image " +
                             std::to_string(time.im_id) + " already at line " +
                             std::to_string(other.line));
      }
    }
    times->push_back(time);
  }
  if (times->empty()) return Status::Error(path + ": no image times");
  return Status::Ok();
}

}  // namespace import_internal

namespace {

using import_internal::BopImage;
using import_internal::BopModel;
using import_internal::BopResultRow;
using import_internal::ImageTime;

Status CheckOptions(const BopImportOptions& o) {
  if (o.results.empty() || o.scene_camera.empty()) {
    return Status::Error(
        "options: the results CSV and scene_camera.json are "
        "required");
  }
  if (o.trajectory.empty() != o.image_times.empty()) {
    return Status::Error(
        "options: a trajectory needs the image times and "
        "the image times need a trajectory");
  }
  if (o.gate && !(*o.gate > 0.0 && std::isfinite(*o.gate))) {
    return Status::Error("gate: must be positive");
  }
  if (!(o.time_tolerance >= 0.0 && std::isfinite(o.time_tolerance))) {
    return Status::Error("time tolerance: must be finite and >= 0");
  }
  for (const std::optional<double>& sigma :
       {o.detection_sigma_t, o.detection_sigma_r}) {
    if (sigma && !(*sigma > 0.0 && std::isfinite(*sigma))) {
      return Status::Error("detection sigma: must be positive");
    }
  }
  return Status::Ok();
}

// The trajectory pose nearest to `timestamp` within `tolerance`, or null.
const TrajectoryPose* Nearest(const std::vector<TrajectoryPose>& poses,
                              double timestamp,
                              double tolerance) {
  const auto it = std::lower_bound(
      poses.begin(),
      poses.end(),
      timestamp,
      [](const TrajectoryPose& p, double t) { return p.timestamp < t; });
  const TrajectoryPose* best = nullptr;
  for (auto c : {it, it == poses.begin() ? poses.end() : it - 1}) {
    if (c == poses.end()) continue;
    const double d = std::abs(c->timestamp - timestamp);
    if (d <= tolerance &&
        (best == nullptr || d < std::abs(best->timestamp - timestamp))) {
      best = &*c;
    }
  }
  return best;
}

// A keyframe per image with a pose: T_wc and the timestamp.
struct ImagePose {
  int im_id = 0;
  double timestamp = 0.0;
  Rigid3d T_wc;
};

Status PosesFromSceneCamera(const BopImportOptions& o,
                            const std::vector<BopImage>& images,
                            std::vector<ImagePose>* poses,
                            BopImportReport* report) {
  for (const BopImage& image : images) {
    if (!image.T_cw) {
      if (o.skip_images_without_pose) {
        ++report->skipped_images;
        continue;
      }
      return Status::Error(
          o.scene_camera + ": [\"" + std::to_string(image.im_id) +
          "\"]: no cam_R_w2c/cam_t_w2c; give the front end's poses with "
          "--trajectory and --image-times, or skip such images");
    }
    poses->push_back(
        {image.im_id, static_cast<double>(image.im_id), image.T_cw->Inverse()});
  }
  return Status::Ok();
}

Status PosesFromTrajectory(const BopImportOptions& o,
                           const std::vector<BopImage>& images,
                           const std::vector<ImageTime>& times,
                           std::vector<ImagePose>* poses,
                           BopImportReport* report) {
  std::vector<TrajectoryPose> trajectory;
  Status status = ReadTumTrajectory(o.trajectory, &trajectory);
  if (!status.ok()) return status;
  std::map<int, const ImageTime*> time_of;
  for (const ImageTime& t : times) time_of[t.im_id] = &t;
  for (const BopImage& image : images) {
    const auto t = time_of.find(image.im_id);
    if (t == time_of.end()) {
      return Status::Error(o.image_times + ": no time for image " +
                           std::to_string(image.im_id) + " of " +
                           o.scene_camera);
    }
    const TrajectoryPose* pose =
        Nearest(trajectory, t->second->timestamp, o.time_tolerance);
    if (pose == nullptr) {
      if (o.skip_images_without_pose) {
        ++report->skipped_images;
        continue;
      }
      return Status::Error(internal::At(o.image_times, t->second->line) +
                           ": image " + std::to_string(image.im_id) +
                           " has no pose in " + o.trajectory + " within " +
                           internal::Approx(o.time_tolerance) + " s");
    }
    poses->push_back({image.im_id, t->second->timestamp, pose->T_wc});
  }
  return Status::Ok();
}

std::string ClassName(const BopImportOptions& o, int obj_id) {
  const auto it = o.class_names.find(obj_id);
  return it != o.class_names.end() ? it->second
                                   : "obj_" + std::to_string(obj_id);
}

double Gate(const BopImportOptions& o,
            const std::map<int, BopModel>& models,
            int obj_id) {
  if (o.gate) return *o.gate;
  const auto it = models.find(obj_id);
  if (it != models.end() && it->second.diameter > 0.0) {
    return 0.5 * it->second.diameter;
  }
  return kBopDefaultGate;
}

// The detections of one image from its rows (in file order).
std::vector<DetectionInput> Detections(const BopImportOptions& o,
                                       const std::map<int, BopModel>& models,
                                       int im_id,
                                       const std::vector<BopResultRow>& rows,
                                       const std::vector<int>& image_rows) {
  std::vector<DetectionInput> detections;
  std::vector<const BopResultRow*> first;  // each detection's first row
  std::vector<bool> positive;
  for (int index : image_rows) {
    const BopResultRow& row = rows[index];
    const double gate = Gate(o, models, row.obj_id);
    std::size_t d = 0;
    while (d < first.size() &&
           !(first[d]->obj_id == row.obj_id &&
             (first[d]->T_co.t - row.T_co.t).norm() <= gate)) {
      ++d;
    }
    if (d == first.size()) {
      DetectionInput detection;
      detection.id = std::to_string(im_id) + "/" + std::to_string(d);
      detection.class_name = ClassName(o, row.obj_id);
      detection.score = row.score;
      detection.sigma_t = o.detection_sigma_t;
      detection.sigma_r = o.detection_sigma_r;
      detections.push_back(std::move(detection));
      first.push_back(&row);
      positive.push_back(true);
    }
    DetectionInput& detection = detections[d];
    detection.hypotheses.push_back({row.T_co, row.score});
    detection.score = std::max(detection.score, row.score);
    positive[d] = positive[d] && row.score > 0.0;
  }
  for (std::size_t d = 0; d < detections.size(); ++d) {
    if (positive[d]) continue;
    for (PoseHypothesis& h : detections[d].hypotheses) h.weight = 1.0;
  }
  return detections;
}

// The header's "bop" key: the scene imported and the obj_id of every class
// (the rows' objects and models_info's).
Status BopSourceOfImport(const BopImportOptions& o,
                         const std::vector<BopResultRow>& rows,
                         const std::map<int, BopModel>& models,
                         std::optional<BopSource>* source) {
  std::map<int, std::string> names;
  for (const BopResultRow& row : rows)
    names[row.obj_id] = ClassName(o, row.obj_id);
  for (const auto& model : models)
    names[model.first] = ClassName(o, model.first);
  std::vector<int> obj_ids;
  for (const auto& name : names) obj_ids.push_back(name.first);
  std::optional<int> row_scene;
  if (!rows.empty()) row_scene = rows.front().scene_id;
  return import_internal::MakeBopSource(
      o.scene, row_scene, obj_ids, names, source);
}

}  // namespace

Status ParseBopClassNames(const std::string& text,
                          std::map<int, std::string>* names) {
  const std::string where = "class names \"" + text + "\": ";
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string pair = text.substr(start, end - start);
    const std::size_t equals = pair.find('=');
    int id = 0;
    if (equals == std::string::npos || equals + 1 == pair.size() ||
        !internal::ParseInteger(std::string_view(pair).substr(0, equals),
                                &id) ||
        id < 0) {
      return Status::Error(where + "expected obj_id=name pairs, got \"" + pair +
                           "\"");
    }
    if (names->count(id) != 0) {
      return Status::Error(where + "obj_id " + std::to_string(id) +
                           " named twice");
    }
    (*names)[id] = pair.substr(equals + 1);
    start = end + 1;
  }
  return Status::Ok();
}

Status ImportBop(const BopImportOptions& options,
                 LogHeader* header,
                 std::vector<KeyframeInput>* keyframes,
                 BopImportReport* report) {
  BopImportReport local;
  BopImportReport& r = report != nullptr ? *report : local;
  r = BopImportReport();
  Status status = CheckOptions(options);
  std::vector<BopImage> images;
  if (status.ok()) {
    status = import_internal::ReadBopSceneCamera(options.scene_camera, &images);
  }
  std::map<int, BopModel> models;
  if (status.ok() && !options.models_info.empty()) {
    status = import_internal::ReadBopModelsInfo(options.models_info, &models);
  }
  std::vector<BopResultRow> rows;
  if (status.ok()) {
    status =
        import_internal::ReadBopResults(options.results, options.scene, &rows);
  }
  std::vector<ImagePose> poses;
  if (status.ok() && options.trajectory.empty()) {
    status = PosesFromSceneCamera(options, images, &poses, &r);
  } else if (status.ok()) {
    std::vector<ImageTime> times;
    status = import_internal::ReadImageTimes(options.image_times, &times);
    if (status.ok()) {
      status = PosesFromTrajectory(options, images, times, &poses, &r);
    }
  }
  if (!status.ok()) return status;
  if (poses.empty()) {
    return Status::Error(options.scene_camera + ": no image with a pose");
  }

  // Rows by image (file order within an image).
  std::vector<int> image_ids;
  for (const BopImage& image : images) image_ids.push_back(image.im_id);
  std::map<int, std::vector<int>> rows_of;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const BopResultRow& row = rows[i];
    if (!std::binary_search(image_ids.begin(), image_ids.end(), row.im_id)) {
      return Status::Error(internal::At(options.results, row.line) +
                           ": image " + std::to_string(row.im_id) +
                           " is not in " + options.scene_camera);
    }
    rows_of[row.im_id].push_back(static_cast<int>(i));
  }
  r.rows = static_cast<int>(rows.size());

  header->version = kLogFormatVersion;
  header->camera = images.front().camera;
  header->classes.clear();
  for (const auto& [obj_id, model] : models) {
    header->classes[ClassName(options, obj_id)] = model.prior;
    if (!model.note.empty()) {
      r.symmetry_notes.push_back("obj " + std::to_string(obj_id) + " (" +
                                 ClassName(options, obj_id) +
                                 "): " + model.note);
    }
  }
  status = BopSourceOfImport(options, rows, models, &header->bop);
  if (!status.ok()) return status;
  keyframes->clear();
  std::size_t posed = 0;
  for (const ImagePose& pose : poses) {
    KeyframeInput kf;
    kf.id = pose.im_id;
    kf.timestamp = pose.timestamp;
    kf.T_wc = pose.T_wc;
    const auto it = rows_of.find(pose.im_id);
    if (it != rows_of.end()) {
      kf.detections = Detections(options, models, pose.im_id, rows, it->second);
      posed += it->second.size();
    }
    r.detections += static_cast<int>(kf.detections.size());
    keyframes->push_back(std::move(kf));
  }
  for (std::size_t k = 1; k < keyframes->size(); ++k) {
    if (!((*keyframes)[k].timestamp > (*keyframes)[k - 1].timestamp)) {
      return Status::Error(options.image_times + ": the times of images " +
                           std::to_string((*keyframes)[k - 1].id) + " and " +
                           std::to_string((*keyframes)[k].id) +
                           " do not increase with the image id");
    }
  }
  r.keyframes = static_cast<int>(keyframes->size());
  r.skipped_rows = static_cast<int>(rows.size() - posed);
  return Status::Ok();
}

Status ImportBopToLog(const BopImportOptions& options,
                      const std::string& log_path,
                      BopImportReport* report) {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ImportBop(options, &header, &keyframes, report);
  if (!status.ok()) return status;
  return WriteLogAtomically(log_path, header, keyframes);
}

}  // namespace symba
