// LogReader: the log format v1 (docs/log-format.md), one line at a time.
//
// Each line is parsed into a reused JsonTree (io/json_tree.h) and then
// validated and converted in one pass. Error paths are only turned into
// text when an error is reported, so a valid line costs no string building.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "io/json_tree.h"
#include "io/json_tree_reader.h"
#include "io/text_file.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/io/format_double.h"
#include "symba/io/log_format.h"

namespace symba {
namespace {

using io_internal::JsonError;
using io_internal::JsonTree;
using io_internal::JsonType;
using Index = JsonTree::Index;

constexpr char kHeaderExample[] =
    "{\"format\": \"symba-log\", \"version\": 1, ...}";

// Validates and converts the JSON of one line; every error names the file,
// the line and the path (io/json_tree_reader.h).
using LineReader = io_internal::JsonTreeReader;
using Path = io_internal::JsonPath;
using io_internal::QuoteForMessage;

// An integer >= 0 that fits an int (a BOP id).
Status NonNegativeInt(const LineReader& in,
                      Index i,
                      const Path& path,
                      int* out) {
  Status status = in.Int(i, path, out);
  if (!status.ok()) return status;
  if (*out < 0) {
    return in.Fail(path,
                   "must be a non-negative integer, got " + in.Describe(i));
  }
  return Status::Ok();
}

// The optional "bop" key: {"scene_id": N, "obj_ids": {"<class>": id, ...}}.
Status ReadBopSource(const LineReader& in, Index bop, BopSource* source) {
  const Path root;
  const Path path = root.Member("bop");
  Status status = in.Object(bop, path);
  if (!status.ok()) return status;
  Index scene = 0;
  status = in.Require(
      bop, path, "scene_id", "the BOP scene id, an integer >= 0", &scene);
  if (!status.ok()) return status;
  status =
      NonNegativeInt(in, scene, path.Member("scene_id"), &source->scene_id);
  if (!status.ok()) return status;
  Index ids = 0;
  status = in.Require(bop,
                      path,
                      "obj_ids",
                      "the BOP obj_id of each class, {\"<class>\": id, ...}",
                      &ids);
  if (!status.ok()) return status;
  const Path ids_path = path.Member("obj_ids");
  status = in.Object(ids, ids_path);
  if (!status.ok()) return status;
  source->obj_ids.clear();
  for (Index c = in.tree().node(ids).first; c != 0;
       c = in.tree().node(c).next) {
    const std::string_view name = in.tree().Key(c);
    if (in.Find(ids, name) != c) continue;  // a later one counts
    int obj_id = 0;
    status = NonNegativeInt(in, c, ids_path.Member(name), &obj_id);
    if (!status.ok()) return status;
    source->obj_ids[std::string(name)] = obj_id;
  }
  return Status::Ok();
}

Status ReadHeader(const LineReader& in, LogHeader* header) {
  const Path root;
  if (in.Type(0) != JsonType::kObject) {
    return in.Fail(root,
                   "the header must be a JSON object " +
                       std::string(kHeaderExample) + ", got " + in.Describe(0));
  }
  Index format = 0;
  Status status =
      in.Require(0,
                 root,
                 "format",
                 "line 1 must be the header " + std::string(kHeaderExample),
                 &format);
  if (!status.ok()) return status;
  if (in.Type(format) != JsonType::kString ||
      in.tree().String(format) != "symba-log") {
    return in.Fail(root.Member("format"),
                   "expected \"symba-log\", got " + in.Describe(format));
  }
  Index version = 0;
  status = in.Require(0, root, "version", "", &version);
  if (!status.ok()) return status;
  int64_t version_number = 0;
  status = in.Integer(version, root.Member("version"), &version_number);
  if (!status.ok()) return status;
  if (version_number != kLogFormatVersion) {
    return in.Fail(root,
                   "version " + in.Describe(version) +
                       " is not supported (this reader reads version " +
                       std::to_string(kLogFormatVersion) + ")");
  }
  header->version = kLogFormatVersion;

  header->camera.reset();
  if (const Index camera = in.Find(0, "camera"); camera != 0) {
    const Path path = root.Member("camera");
    status = in.Object(camera, path);
    if (!status.ok()) return status;
    PinholeIntrinsics intrinsics;
    struct Field {
      const char* key;
      double* value;
      bool positive;
    };
    const Field fields[] = {{"fx", &intrinsics.fx, true},
                            {"fy", &intrinsics.fy, true},
                            {"cx", &intrinsics.cx, false},
                            {"cy", &intrinsics.cy, false}};
    for (const Field& field : fields) {
      Index value = 0;
      status = in.Require(camera, path, field.key, "", &value);
      if (!status.ok()) return status;
      const Path field_path = path.Member(field.key);
      status = field.positive ? in.Positive(value, field_path, field.value)
                              : in.Number(value, field_path, field.value);
      if (!status.ok()) return status;
    }
    header->camera = intrinsics;
  }

  header->classes.clear();
  if (const Index classes = in.Find(0, "classes"); classes != 0) {
    const Path path = root.Member("classes");
    status = in.Object(classes, path);
    if (!status.ok()) return status;
    for (Index c = in.tree().node(classes).first; c != 0;
         c = in.tree().node(c).next) {
      const std::string_view name = in.tree().Key(c);
      if (in.Find(classes, name) != c) continue;  // a later one counts
      const Path class_path = path.Member(name);
      status = in.Object(c, class_path);
      if (!status.ok()) return status;
      ClassPrior prior;
      Index symmetry = 0;
      status = in.Require(c,
                          class_path,
                          "symmetry",
                          "\"asymmetric\", \"discrete\" or \"continuous\"",
                          &symmetry);
      if (!status.ok()) return status;
      std::string_view symmetry_name;
      status =
          in.String(symmetry, class_path.Member("symmetry"), &symmetry_name);
      if (!status.ok()) return status;
      const std::optional<SymmetryType> type = ParseSymmetryType(symmetry_name);
      if (!type) {
        return in.Fail(class_path.Member("symmetry"),
                       "unknown symmetry " + QuoteForMessage(symmetry_name) +
                           " (expected \"asymmetric\", \"discrete\" or "
                           "\"continuous\")");
      }
      prior.symmetry = *type;
      const Index order = in.Find(c, "order");
      const Path order_path = class_path.Member("order");
      if (prior.symmetry == SymmetryType::kDiscrete) {
        if (order == 0) {
          return in.Fail(order_path,
                         "missing (a discrete class needs its symmetry order, "
                         "an integer >= 2)");
        }
        int64_t order_value = 0;
        status = in.Integer(order, order_path, &order_value);
        if (!status.ok()) return status;
        if (order_value < 2 || order_value > 1000000) {
          return in.Fail(order_path,
                         "must be an integer from 2 to 1000000, got " +
                             in.Describe(order));
        }
        prior.order = static_cast<int>(order_value);
      } else if (order != 0) {
        return in.Fail(order_path, "only a discrete class has an order");
      }
      if (const Index axis = in.Find(c, "axis"); axis != 0) {
        const Path axis_path = class_path.Member("axis");
        if (prior.symmetry == SymmetryType::kAsymmetric) {
          return in.Fail(axis_path, "an asymmetric class has no symmetry axis");
        }
        status = in.Numbers(axis, axis_path, 3, prior.axis_o.data());
        if (!status.ok()) return status;
        if (prior.axis_o.isZero(0.0)) {
          return in.Fail(axis_path, "must not be the zero vector");
        }
        if (!IsUsablePriorAxis(prior.axis_o)) {
          return in.Fail(axis_path, "must have a norm in [1e-100, 1e100]");
        }
      }
      header->classes[std::string(name)] = prior;
    }
  }

  header->bop.reset();
  if (const Index bop = in.Find(0, "bop"); bop != 0) {
    BopSource source;
    status = ReadBopSource(in, bop, &source);
    if (!status.ok()) return status;
    header->bop = std::move(source);
  }
  return Status::Ok();
}

// What the checks across keyframes need to know about the previous one.
struct Previous {
  bool exists = false;
  int64_t id = 0;
  double timestamp = 0.0;
  int line = 0;
  std::vector<int64_t> ids;  // every keyframe id so far, increasing
};

// A keyframe's loop closures (the optional key "loop_closures").
Status ReadLoopClosures(const LineReader& in,
                        Index closures,
                        const Path& path,
                        const Previous& previous,
                        std::vector<LoopClosureInput>* out) {
  Status status = in.Array(closures, path);
  if (!status.ok()) return status;
  out->resize(in.tree().node(closures).size);
  int64_t k = 0;
  for (Index c = in.tree().node(closures).first; c != 0;
       c = in.tree().node(c).next, ++k) {
    const Path c_path = path.Element(k);
    LoopClosureInput& closure = (*out)[k];
    status = in.Object(c, c_path);
    if (!status.ok()) return status;
    Index field = 0;
    status = in.Require(
        c, c_path, "keyframe", "the id of an earlier keyframe", &field);
    if (!status.ok()) return status;
    status = in.Integer(field, c_path.Member("keyframe"), &closure.keyframe);
    if (!status.ok()) return status;
    if (!std::binary_search(
            previous.ids.begin(), previous.ids.end(), closure.keyframe)) {
      return in.Fail(c_path.Member("keyframe"),
                     std::to_string(closure.keyframe) +
                         " is not the id of an earlier keyframe of this log");
    }
    status = in.Require(
        c, c_path, "T", "this keyframe's pose in that one's frame", &field);
    if (!status.ok()) return status;
    status = in.Pose(field, c_path.Member("T"), &closure.T);
    if (!status.ok()) return status;
    status = in.Require(c, c_path, "sigma_t", "in metres", &field);
    if (!status.ok()) return status;
    status = in.Positive(field, c_path.Member("sigma_t"), &closure.sigma_t);
    if (!status.ok()) return status;
    status = in.Require(c, c_path, "sigma_r", "in radians", &field);
    if (!status.ok()) return status;
    status = in.Positive(field, c_path.Member("sigma_r"), &closure.sigma_r);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

Status ReadDetection(const LineReader& in,
                     Index d,
                     const Path& path,
                     int64_t keyframe_id,
                     int64_t index,
                     DetectionInput* detection) {
  Status status = in.Object(d, path);
  if (!status.ok()) return status;
  std::string_view text;
  detection->id.clear();
  if (const Index id = in.Find(d, "id"); id != 0) {
    status = in.String(id, path.Member("id"), &text);
    if (!status.ok()) return status;
    detection->id.assign(text);
  }
  if (detection->id.empty()) {
    detection->id = std::to_string(keyframe_id);
    detection->id.push_back('/');
    detection->id.append(std::to_string(index));
  }
  Index class_name = 0;
  status =
      in.Require(d, path, "class", "the object class, a string", &class_name);
  if (!status.ok()) return status;
  status = in.String(class_name, path.Member("class"), &text);
  if (!status.ok()) return status;
  detection->class_name.assign(text);

  detection->score = 1.0;
  if (const Index score = in.Find(d, "score"); score != 0) {
    status = in.Number(score, path.Member("score"), &detection->score);
    if (!status.ok()) return status;
  }
  struct Sigma {
    const char* key;
    std::optional<double>* value;
  };
  for (const Sigma& sigma : {Sigma{"sigma_t", &detection->sigma_t},
                             Sigma{"sigma_r", &detection->sigma_r}}) {
    sigma.value->reset();
    if (const Index s = in.Find(d, sigma.key); s != 0) {
      double value = 0.0;
      status = in.Positive(s, path.Member(sigma.key), &value);
      if (!status.ok()) return status;
      *sigma.value = value;
    }
  }

  Index hypotheses = 0;
  status =
      in.Require(d, path, "hypotheses", "at least one pose T_co", &hypotheses);
  if (!status.ok()) return status;
  const Path hypotheses_path = path.Member("hypotheses");
  status = in.Array(hypotheses, hypotheses_path);
  if (!status.ok()) return status;
  const uint32_t count = in.tree().node(hypotheses).size;
  if (count == 0) {
    return in.Fail(hypotheses_path,
                   "empty; a detection needs at least one hypothesis");
  }
  detection->hypotheses.resize(count);
  int64_t k = 0;
  for (Index h = in.tree().node(hypotheses).first; h != 0;
       h = in.tree().node(h).next, ++k) {
    const Path h_path = hypotheses_path.Element(k);
    PoseHypothesis& hypothesis = detection->hypotheses[k];
    status = in.Pose(h, h_path, &hypothesis.T_co);
    if (!status.ok()) return status;
    hypothesis.weight = 1.0;
    if (const Index w = in.Find(h, "w"); w != 0) {
      status = in.Positive(w, h_path.Member("w"), &hypothesis.weight);
      if (!status.ok()) return status;
    }
  }
  return Status::Ok();
}

Status ReadKeyframe(const LineReader& in,
                    const LogHeader& header,
                    const Previous& previous,
                    KeyframeInput* keyframe) {
  const Path root;
  if (in.Type(0) != JsonType::kObject) {
    return in.Fail(root,
                   "a keyframe must be a JSON object, got " + in.Describe(0));
  }
  Index id = 0;
  Status status =
      in.Require(0, root, "keyframe", "the keyframe id, an integer", &id);
  if (!status.ok()) return status;
  status = in.Integer(id, root.Member("keyframe"), &keyframe->id);
  if (!status.ok()) return status;
  if (previous.exists && keyframe->id <= previous.id) {
    return in.Fail(root.Member("keyframe"),
                   "id " + std::to_string(keyframe->id) +
                       " is not greater than the previous keyframe's id " +
                       std::to_string(previous.id) + " (line " +
                       std::to_string(previous.line) + ")");
  }
  Index t = 0;
  status = in.Require(0, root, "t", "the timestamp in seconds", &t);
  if (!status.ok()) return status;
  status = in.Number(t, root.Member("t"), &keyframe->timestamp);
  if (!status.ok()) return status;
  if (previous.exists && keyframe->timestamp < previous.timestamp) {
    return in.Fail(root.Member("t"),
                   FormatDouble(keyframe->timestamp) +
                       " is before the previous keyframe's time " +
                       FormatDouble(previous.timestamp) + " (line " +
                       std::to_string(previous.line) + ")");
  }

  keyframe->T_wc.reset();
  if (const Index pose = in.Find(0, "T_wc"); pose != 0) {
    Rigid3d T_wc;
    status = in.Pose(pose, root.Member("T_wc"), &T_wc);
    if (!status.ok()) return status;
    keyframe->T_wc = T_wc;
  }
  keyframe->odometry.reset();
  if (const Index odometry = in.Find(0, "odometry"); odometry != 0) {
    const Path path = root.Member("odometry");
    status = in.Object(odometry, path);
    if (!status.ok()) return status;
    Odometry value;
    Index field = 0;
    status = in.Require(odometry, path, "T", "the pose T_{prev,cur}", &field);
    if (!status.ok()) return status;
    status = in.Pose(field, path.Member("T"), &value.T_prev_cur);
    if (!status.ok()) return status;
    status = in.Require(odometry, path, "sigma_t", "in metres", &field);
    if (!status.ok()) return status;
    status = in.Positive(field, path.Member("sigma_t"), &value.sigma_t);
    if (!status.ok()) return status;
    status = in.Require(odometry, path, "sigma_r", "in radians", &field);
    if (!status.ok()) return status;
    status = in.Positive(field, path.Member("sigma_r"), &value.sigma_r);
    if (!status.ok()) return status;
    keyframe->odometry = value;
  }
  if (!previous.exists && !keyframe->T_wc) {
    return in.Fail(root.Member("T_wc"),
                   "missing (the first keyframe needs the camera pose T_wc)");
  }
  if (!keyframe->T_wc && !keyframe->odometry) {
    return in.Fail(root,
                   "neither T_wc nor odometry (every keyframe after the first "
                   "needs at least one of them)");
  }

  keyframe->detections.clear();
  if (const Index detections = in.Find(0, "detections"); detections != 0) {
    const Path path = root.Member("detections");
    status = in.Array(detections, path);
    if (!status.ok()) return status;
    keyframe->detections.resize(in.tree().node(detections).size);
    int64_t k = 0;
    for (Index d = in.tree().node(detections).first; d != 0;
         d = in.tree().node(d).next, ++k) {
      status = ReadDetection(
          in, d, path.Element(k), keyframe->id, k, &keyframe->detections[k]);
      if (!status.ok()) return status;
    }
  }

  keyframe->points.clear();
  if (const Index points = in.Find(0, "points"); points != 0) {
    const Path path = root.Member("points");
    status = in.Array(points, path);
    if (!status.ok()) return status;
    const uint32_t count = in.tree().node(points).size;
    if (count > 0 && !header.camera) {
      return in.Fail(path,
                     "the header (line 1) has no camera; point observations "
                     "need its intrinsics");
    }
    keyframe->points.resize(count);
    int64_t k = 0;
    for (Index p = in.tree().node(points).first; p != 0;
         p = in.tree().node(p).next, ++k) {
      const Path p_path = path.Element(k);
      PointObservation& point = keyframe->points[k];
      status = in.Object(p, p_path);
      if (!status.ok()) return status;
      Index field = 0;
      status =
          in.Require(p, p_path, "id", "the map point id, an integer", &field);
      if (!status.ok()) return status;
      status = in.Integer(field, p_path.Member("id"), &point.id);
      if (!status.ok()) return status;
      status = in.Require(p, p_path, "uv", "pixel coordinates [u, v]", &field);
      if (!status.ok()) return status;
      status = in.Numbers(field, p_path.Member("uv"), 2, point.uv.data());
      if (!status.ok()) return status;
      point.depth.reset();
      if (const Index depth = in.Find(p, "depth"); depth != 0) {
        double value = 0.0;
        status = in.Positive(depth, p_path.Member("depth"), &value);
        if (!status.ok()) return status;
        point.depth = value;
      }
    }
  }

  keyframe->loop_closures.clear();
  if (const Index closures = in.Find(0, "loop_closures"); closures != 0) {
    status = ReadLoopClosures(in,
                              closures,
                              root.Member("loop_closures"),
                              previous,
                              &keyframe->loop_closures);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

bool IsBlank(const std::string& line) {
  return line.find_first_not_of(" \t\r\n") == std::string::npos;
}

}  // namespace

class LogReader::Impl {
 public:
  Impl(std::unique_ptr<std::istream> stream, std::string name)
      : stream_(std::move(stream)), name_(std::move(name)) {}

  Status ReadHeaderLine() {
    if (!std::getline(*stream_, text_)) {
      if (stream_->bad()) return Fail(1, "read error");
      return Fail(1,
                  "empty file; line 1 must be the header " +
                      std::string(kHeaderExample));
    }
    line_ = 1;
    if (IsBlank(text_)) {
      return Fail(1,
                  "line 1 is blank; it must be the header " +
                      std::string(kHeaderExample));
    }
    Status status = Parse();
    if (!status.ok()) return status;
    return ReadHeader(LineReader(name_, line_, tree_), &header_);
  }

  Status Next(KeyframeInput* keyframe, bool* end) {
    *end = false;
    if (!error_.ok()) return error_;
    if (finished_) {
      *end = true;
      return Status::Ok();
    }
    while (true) {
      if (!std::getline(*stream_, text_)) {
        if (stream_->bad()) {
          error_ = Fail(line_ + 1, "read error");
          return error_;
        }
        finished_ = true;
        *end = true;
        return Status::Ok();
      }
      ++line_;
      if (!IsBlank(text_)) break;
    }
    error_ = Parse();
    if (!error_.ok()) return error_;
    error_ = ReadKeyframe(
        LineReader(name_, line_, tree_), header_, previous_, keyframe);
    if (!error_.ok()) return error_;
    previous_.exists = true;
    previous_.id = keyframe->id;
    previous_.timestamp = keyframe->timestamp;
    previous_.line = line_;
    previous_.ids.push_back(keyframe->id);
    return Status::Ok();
  }

  const LogHeader& header() const { return header_; }
  int line() const { return previous_.line; }

 private:
  Status Fail(int line, std::string_view what) const {
    return Status::Error(name_ + ":" + std::to_string(line) + ": " +
                         std::string(what));
  }

  Status Parse() {
    JsonError error;
    if (io_internal::ParseJson(text_, &tree_, &error)) return Status::Ok();
    std::string what = "invalid JSON";
    if (error.column > 0) what += " at column " + std::to_string(error.column);
    return Fail(line_, what + ": " + error.message);
  }

  std::unique_ptr<std::istream> stream_;
  std::string name_;
  std::string text_;  // the current line
  JsonTree tree_;
  LogHeader header_;
  Previous previous_;
  int line_ = 0;
  bool finished_ = false;
  Status error_;
};

LogReader::LogReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LogReader::~LogReader() = default;

Status LogReader::Open(const std::string& path,
                       std::unique_ptr<LogReader>* reader) {
  auto file = std::make_unique<std::ifstream>();
  Status status = internal::OpenForReading(path, file.get());
  if (!status.ok()) return status;
  return OpenStream(std::move(file), path, reader);
}

Status LogReader::OpenStream(std::unique_ptr<std::istream> stream,
                             const std::string& name,
                             std::unique_ptr<LogReader>* reader) {
  reader->reset();
  auto impl = std::make_unique<Impl>(std::move(stream), name);
  Status status = impl->ReadHeaderLine();
  if (!status.ok()) return status;
  reader->reset(new LogReader(std::move(impl)));
  return Status::Ok();
}

const LogHeader& LogReader::header() const { return impl_->header(); }

Status LogReader::Next(KeyframeInput* keyframe, bool* end) {
  return impl_->Next(keyframe, end);
}

int LogReader::line() const { return impl_->line(); }

}  // namespace symba
