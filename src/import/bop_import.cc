#include "symba/import/bop_import.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "import/bop_files.h"
#include "import/bop_source.h"
#include "io/text_file.h"
#include "symba/backend/backend_options.h"
#include "symba/io/file_output.h"
#include "symba/io/log_file.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace import_internal {

namespace {

// The two forms of an image times file; the first data line decides.
enum class TimesForm { kUnknown, kIdTime, kRgbTxt };

// A TUM rgb.txt file name ("rgb/1305031102.175304.png"): it has an
// extension or a directory, which a misread number ("0,033") has not.
bool LooksLikeFileName(std::string_view field) {
  return field.find_first_of("./") != std::string_view::npos;
}

// One data line in `form` (decided from it when unknown); the error names
// the line and the form that the first data line set.
Status ParseTimeLine(const std::string& path,
                     int line,
                     const std::vector<std::string_view>& f,
                     int form_line,
                     TimesForm* form,
                     ImageTime* time) {
  double number = 0.0;
  const bool id_time = f.size() == 2 && internal::ParseDouble(f[1], &number) &&
                       internal::ParseInteger(f[0], &time->im_id) &&
                       time->im_id >= 0;
  const bool rgb_txt = f.size() == 2 &&
                       internal::ParseDouble(f[0], &time->timestamp) &&
                       LooksLikeFileName(f[1]);
  if (*form == TimesForm::kUnknown) {
    if (id_time) *form = TimesForm::kIdTime;
    if (!id_time && rgb_txt) *form = TimesForm::kRgbTxt;
  }
  if (*form == TimesForm::kIdTime && id_time) {
    time->timestamp = number;
    return Status::Ok();
  }
  if (*form == TimesForm::kRgbTxt && rgb_txt) return Status::Ok();
  const std::string at = internal::At(path, line);
  switch (*form) {
    case TimesForm::kIdTime:
      return Status::Error(at + ": expected \"im_id timestamp\" as on line " +
                           std::to_string(form_line) +
                           " (a non-negative integer and a number)");
    case TimesForm::kRgbTxt:
      return Status::Error(at + ": expected \"timestamp filename\" (TUM " +
                           "rgb.txt) as on line " + std::to_string(form_line));
    case TimesForm::kUnknown:
      break;
  }
  return Status::Error(at +
                       ": expected \"im_id timestamp\" or \"timestamp "
                       "filename\" (TUM rgb.txt)");
}

}  // namespace

Status ReadImageTimes(const std::string& path, std::vector<ImageTime>* times) {
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  times->clear();
  TimesForm form = TimesForm::kUnknown;
  int form_line = 0;
  std::unordered_map<int, int> line_of_image;
  const std::vector<std::string_view> lines = internal::SplitLines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int line = static_cast<int>(i) + 1;
    if (internal::IsBlank(lines[i]) ||
        lines[i].find_first_not_of(" \t") == lines[i].find('#')) {
      continue;
    }
    ImageTime time;
    time.line = line;
    if (form_line == 0) form_line = line;
    status = ParseTimeLine(
        path, line, internal::SplitFields(lines[i]), form_line, &form, &time);
    if (!status.ok()) return status;
    if (form == TimesForm::kRgbTxt) {
      time.im_id = static_cast<int>(times->size());
    }
    const auto [it, inserted] = line_of_image.emplace(time.im_id, line);
    if (!inserted) {
      return Status::Error(internal::At(path, line) + ": image " +
                           std::to_string(time.im_id) + " already at line " +
                           std::to_string(it->second));
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
  if (!o.trajectory.empty() && o.image_times.empty()) {
    return Status::Error("options: a trajectory needs the image times");
  }
  if (o.gate && !(*o.gate > 0.0 && std::isfinite(*o.gate))) {
    return Status::Error("options: gate: must be positive and finite, got " +
                         internal::Approx(*o.gate));
  }
  if (!(o.time_tolerance >= 0.0 && std::isfinite(o.time_tolerance))) {
    return Status::Error(
        "options: time tolerance: must be finite and >= 0, got " +
        internal::Approx(o.time_tolerance));
  }
  const std::pair<const char*, std::optional<double>> sigmas[] = {
      {"detection sigma_t", o.detection_sigma_t},
      {"detection sigma_r", o.detection_sigma_r}};
  for (const auto& [name, sigma] : sigmas) {
    if (sigma && !IsUsableNoiseSigma(*sigma)) {
      return Status::Error(std::string("options: ") + name +
                           ": must be in [1e-9, 1e9], got " +
                           internal::Approx(*sigma));
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

// The images' times by image id (from --image-times), or none.
using TimesById = std::map<int, const ImageTime*>;

TimesById IndexTimes(const std::vector<ImageTime>& times) {
  TimesById time_of;
  for (const ImageTime& t : times) time_of[t.im_id] = &t;
  return time_of;
}

Status MissingTime(const BopImportOptions& o, int im_id) {
  return Status::Error(o.image_times + ": no time for image " +
                       std::to_string(im_id) + " of " + o.scene_camera);
}

// The w2c poses; an image's time from --image-times when given, else its id.
Status PosesFromSceneCamera(const BopImportOptions& o,
                            const std::vector<BopImage>& images,
                            const std::vector<ImageTime>& times,
                            std::vector<ImagePose>* poses,
                            BopImportReport* report) {
  const TimesById time_of = IndexTimes(times);
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
    double timestamp = static_cast<double>(image.im_id);
    if (!o.image_times.empty()) {
      const auto t = time_of.find(image.im_id);
      if (t == time_of.end()) return MissingTime(o, image.im_id);
      timestamp = t->second->timestamp;
    }
    poses->push_back({image.im_id, timestamp, image.T_cw->Inverse()});
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
  const TimesById time_of = IndexTimes(times);
  for (const BopImage& image : images) {
    const auto t = time_of.find(image.im_id);
    if (t == time_of.end()) return MissingTime(o, image.im_id);
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

// The rows of each image, in file order within an image: rows
// order[begin[k]] to order[begin[k + 1] - 1] are those of the image
// image_ids[k].
struct RowsByImage {
  std::vector<int> image_ids;  // increasing
  std::vector<std::size_t> begin;
  std::vector<int> order;

  // The index of an image of scene_camera.json.
  std::size_t Image(int im_id) const {
    return static_cast<std::size_t>(
        std::lower_bound(image_ids.begin(), image_ids.end(), im_id) -
        image_ids.begin());
  }
  // How many rows an image of scene_camera.json has.
  std::size_t Count(int im_id) const {
    const std::size_t k = Image(im_id);
    return begin[k + 1] - begin[k];
  }
};

// Sorts the rows by image (a counting sort: no container per image); a row
// of an image not in scene_camera.json is an error.
Status SortRowsByImage(const BopImportOptions& o,
                       const std::vector<BopImage>& images,
                       const std::vector<BopResultRow>& rows,
                       RowsByImage* by) {
  for (const BopImage& image : images) by->image_ids.push_back(image.im_id);
  std::vector<std::size_t> image_of(rows.size());
  by->begin.assign(images.size() + 1, 0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t k = by->Image(rows[i].im_id);
    if (k == images.size() || by->image_ids[k] != rows[i].im_id) {
      return Status::Error(internal::At(o.results, rows[i].line) + ": image " +
                           std::to_string(rows[i].im_id) + " is not in " +
                           o.scene_camera);
    }
    image_of[i] = k;
    ++by->begin[k + 1];
  }
  for (std::size_t k = 0; k < images.size(); ++k) {
    by->begin[k + 1] += by->begin[k];
  }
  std::vector<std::size_t> next(by->begin.begin(), by->begin.end() - 1);
  by->order.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    by->order[next[image_of[i]]++] = static_cast<int>(i);
  }
  return Status::Ok();
}

// An object seen in the image being grouped: its class name, gate and its
// first and last detections (the detections of one object are chained in
// order, so a row is compared only with the first rows of its object's).
struct ImageObject {
  int obj_id = 0;
  std::string class_name;
  double gate = 0.0;
  int first = -1;
  int last = -1;
};

// A detection being grouped: its first row's translation and the next
// detection of the same object (-1: none).
struct OpenDetection {
  Eigen::Vector3d t;
  int next = -1;
};

ImageObject* FindObject(const BopImportOptions& o,
                        const std::map<int, BopModel>& models,
                        int obj_id,
                        std::vector<ImageObject>* objects) {
  for (ImageObject& object : *objects) {
    if (object.obj_id == obj_id) return &object;
  }
  objects->push_back({obj_id, ClassName(o, obj_id), Gate(o, models, obj_id)});
  return &objects->back();
}

// The first detection of `object` whose first row is within the gate of
// `t`, or -1.
int Match(const ImageObject& object,
          const std::vector<OpenDetection>& open,
          const Eigen::Vector3d& t) {
  for (int d = object.first; d >= 0; d = open[d].next) {
    if ((open[d].t - t).norm() <= object.gate) return d;
  }
  return -1;
}

// The detections of one image from its rows `indices[0..count)` (in file
// order).
std::vector<DetectionInput> Detections(const BopImportOptions& o,
                                       const std::map<int, BopModel>& models,
                                       int im_id,
                                       const std::vector<BopResultRow>& rows,
                                       const int* indices,
                                       std::size_t count) {
  std::vector<DetectionInput> detections;
  detections.reserve(count);
  std::vector<ImageObject> objects;
  std::vector<OpenDetection> open;
  std::vector<bool> positive;
  for (std::size_t i = 0; i < count; ++i) {
    const BopResultRow& row = rows[indices[i]];
    ImageObject* object = FindObject(o, models, row.obj_id, &objects);
    int d = Match(*object, open, row.T_co.t);
    if (d < 0) {
      d = static_cast<int>(detections.size());
      DetectionInput detection;
      detection.id = std::to_string(im_id) + "/" + std::to_string(d);
      detection.class_name = object->class_name;
      detection.score = row.score;
      detection.sigma_t = o.detection_sigma_t;
      detection.sigma_r = o.detection_sigma_r;
      detections.push_back(std::move(detection));
      open.push_back({row.T_co.t, -1});
      if (object->last >= 0) open[object->last].next = d;
      if (object->first < 0) object->first = d;
      object->last = d;
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

// What ImportBop has read and checked; the keyframes are made from it one
// at a time (MakeKeyframe), so the log can be written without holding them
// all.
struct BopScene {
  std::vector<BopImage> images;
  std::map<int, BopModel> models;
  std::vector<BopResultRow> rows;
  std::vector<ImagePose> poses;
  RowsByImage rows_of;
};

// The keyframes' times must not decrease with the image id (a log's rule:
// equal times are allowed, as two keyframes of one time are).
Status CheckTimesDoNotDecrease(const BopImportOptions& options,
                               const std::vector<ImagePose>& poses) {
  for (std::size_t k = 1; k < poses.size(); ++k) {
    if (poses[k].timestamp < poses[k - 1].timestamp) {
      return Status::Error(
          options.image_times + ": image " + std::to_string(poses[k].im_id) +
          " is earlier than image " + std::to_string(poses[k - 1].im_id) +
          ": the times must not decrease with the image id");
    }
  }
  return Status::Ok();
}

// Reads and checks every input; fills every count of the report but the
// detections.
Status ReadScene(const BopImportOptions& options,
                 BopScene* scene,
                 BopImportReport* report) {
  BopImportReport& r = *report;
  Status status = CheckOptions(options);
  std::vector<BopImage>& images = scene->images;
  if (status.ok()) {
    status = import_internal::ReadBopSceneCamera(options.scene_camera, &images);
  }
  std::map<int, BopModel>& models = scene->models;
  if (status.ok() && !options.models_info.empty()) {
    status = import_internal::ReadBopModelsInfo(options.models_info, &models);
  }
  std::vector<BopResultRow>& rows = scene->rows;
  if (status.ok()) {
    status = import_internal::ReadBopResults(
        options.results, options.scene, &rows, &r.other_scene_rows);
  }
  std::vector<ImageTime> times;
  if (status.ok() && !options.image_times.empty()) {
    status = import_internal::ReadImageTimes(options.image_times, &times);
  }
  std::vector<ImagePose>& poses = scene->poses;
  if (status.ok() && options.trajectory.empty()) {
    status = PosesFromSceneCamera(options, images, times, &poses, &r);
  } else if (status.ok()) {
    status = PosesFromTrajectory(options, images, times, &poses, &r);
  }
  if (!status.ok()) return status;
  if (poses.empty()) {
    return Status::Error(options.scene_camera + ": no image with a pose");
  }

  status = SortRowsByImage(options, images, rows, &scene->rows_of);
  if (status.ok()) status = CheckTimesDoNotDecrease(options, poses);
  if (!status.ok()) return status;
  r.rows = static_cast<int>(rows.size());
  r.keyframes = static_cast<int>(poses.size());
  std::size_t posed = 0;
  for (const ImagePose& pose : poses) posed += scene->rows_of.Count(pose.im_id);
  r.skipped_rows = static_cast<int>(rows.size() - posed);
  return Status::Ok();
}

Status MakeHeader(const BopImportOptions& options,
                  const BopScene& scene,
                  LogHeader* header,
                  BopImportReport* report) {
  header->version = kLogFormatVersion;
  header->camera = scene.images.front().camera;
  header->classes.clear();
  for (const auto& [obj_id, model] : scene.models) {
    header->classes[ClassName(options, obj_id)] = model.prior;
    if (!model.note.empty()) {
      report->symmetry_notes.push_back("obj " + std::to_string(obj_id) + " (" +
                                       ClassName(options, obj_id) +
                                       "): " + model.note);
    }
  }
  return BopSourceOfImport(options, scene.rows, scene.models, &header->bop);
}

// The keyframe of scene.poses[p], counting its detections in the report.
void MakeKeyframe(const BopImportOptions& options,
                  const BopScene& scene,
                  std::size_t p,
                  KeyframeInput* kf,
                  BopImportReport* report) {
  const ImagePose& pose = scene.poses[p];
  kf->id = pose.im_id;
  kf->timestamp = pose.timestamp;
  kf->T_wc = pose.T_wc;
  kf->detections.clear();
  const RowsByImage& rows_of = scene.rows_of;
  const std::size_t k = rows_of.Image(pose.im_id);
  const std::size_t count = rows_of.begin[k + 1] - rows_of.begin[k];
  if (count > 0) {
    kf->detections = Detections(options,
                                scene.models,
                                pose.im_id,
                                scene.rows,
                                &rows_of.order[rows_of.begin[k]],
                                count);
  }
  report->detections += static_cast<int>(kf->detections.size());
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
  BopScene scene;
  Status status = ReadScene(options, &scene, &r);
  if (status.ok()) status = MakeHeader(options, scene, header, &r);
  if (!status.ok()) return status;
  keyframes->assign(scene.poses.size(), KeyframeInput());
  for (std::size_t p = 0; p < scene.poses.size(); ++p) {
    MakeKeyframe(options, scene, p, &(*keyframes)[p], &r);
  }
  return Status::Ok();
}

Status ImportBopToLog(const BopImportOptions& options,
                      const std::string& log_path,
                      BopImportReport* report) {
  BopImportReport local;
  BopImportReport& r = report != nullptr ? *report : local;
  r = BopImportReport();
  Status status = CheckOutputSparesInputs(log_path,
                                          {options.results,
                                           options.scene_camera,
                                           options.models_info,
                                           options.trajectory,
                                           options.image_times});
  if (!status.ok()) return status;
  BopScene scene;
  status = ReadScene(options, &scene, &r);
  LogHeader header;
  if (status.ok()) status = MakeHeader(options, scene, &header, &r);
  if (!status.ok()) return status;
  // One keyframe at a time: the 683,304 detections of the benchmark's
  // 100 MB CSV held at once cost more in allocation than writing them.
  KeyframeInput keyframe;
  std::size_t p = 0;
  return WriteLogAtomically(log_path, header, [&]() -> const KeyframeInput* {
    if (p == scene.poses.size()) return nullptr;
    MakeKeyframe(options, scene, p++, &keyframe, &r);
    return &keyframe;
  });
}

}  // namespace symba
