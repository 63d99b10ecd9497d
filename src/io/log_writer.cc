// LogWriter: the log format v1 (docs/log-format.md). One line per call,
// built in a reused buffer and written in one piece, after the keyframe has
// passed the same checks the reader makes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/json_writer.h"
#include "io/text_file.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/io/format_double.h"
#include "symba/io/log_format.h"

namespace symba {
namespace {

using internal::Approx;
using io_internal::JsonWriter;

// Well-formed UTF-8 (no overlong forms, surrogates or code points above
// U+10FFFF), as the reader's JSON parser requires.
bool IsUtf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    int extra = 0;
    uint32_t code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      extra = 1;
      code = c & 0x1F;
    } else if (c >= 0xE0 && c <= 0xEF) {
      extra = 2;
      code = c & 0x0F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      extra = 3;
      code = c & 0x07;
    } else {
      return false;
    }
    if (text.size() - i <= static_cast<std::size_t>(extra)) return false;
    for (int k = 1; k <= extra; ++k) {
      const unsigned char next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xC0) != 0x80) return false;
      code = (code << 6) | (next & 0x3F);
    }
    if ((extra == 2 && (code < 0x800 || (code >= 0xD800 && code <= 0xDFFF))) ||
        (extra == 3 && (code < 0x10000 || code > 0x10FFFF))) {
      return false;
    }
    i += extra + 1;
  }
  return true;
}

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// The path of a checked value, e.g. "detections[3].hypotheses[0].w",
// made into text only for a message: building it for every hypothesis of
// every keyframe cost an allocation each. Only for arguments: it refers to
// its name and parent.
class MemberPath {
 public:
  // A top-level name, e.g. "T_wc" (implicit, as the checks take names).
  MemberPath(const char* name) : name_(name) {}
  MemberPath(const std::string& name) : name_(name) {}
  MemberPath(const MemberPath* parent,
             std::string_view name,
             std::size_t index = kNoIndex)
      : parent_(parent), name_(name), index_(index) {}

  std::string Text() const {
    std::string text = parent_ != nullptr ? parent_->Text() + "." : "";
    text += name_;
    if (index_ != kNoIndex) text += "[" + std::to_string(index_) + "]";
    return text;
  }

 private:
  static constexpr std::size_t kNoIndex = static_cast<std::size_t>(-1);
  const MemberPath* parent_ = nullptr;
  std::string_view name_;
  std::size_t index_ = kNoIndex;
};

// Checks what the reader checks; `fail` turns (path, reason) into a Status.
template <typename Fail>
Status CheckPose(const Rigid3d& pose, const MemberPath& path, Fail fail) {
  if (!Finite(pose.t)) return fail(path.Text() + ".t", "non-finite number");
  if (!pose.q.coeffs().allFinite())
    return fail(path.Text() + ".q", "non-finite number");
  const double norm = pose.q.norm();
  if (!(std::abs(norm - 1.0) <= 1e-3)) {
    return fail(path.Text() + ".q",
                "quaternion norm " + Approx(norm) + " is not within 1e-3 of 1");
  }
  return Status::Ok();
}

template <typename Fail>
Status CheckPositive(double value, const MemberPath& path, Fail fail) {
  if (!std::isfinite(value)) return fail(path.Text(), "non-finite number");
  if (!(value > 0.0))
    return fail(path.Text(), "must be positive, got " + FormatDouble(value));
  return Status::Ok();
}

// The members of a pose object: "t":[x,y,z],"q":[qx,qy,qz,qw].
void PoseMembers(const Rigid3d& pose, JsonWriter* json) {
  const double q[4] = {pose.q.x(), pose.q.y(), pose.q.z(), pose.q.w()};
  json->Key("t").Doubles(pose.t.data(), 3);
  json->Key("q").Doubles(q, 4);
}

void Pose(const Rigid3d& pose, JsonWriter* json) {
  json->BeginObject();
  PoseMembers(pose, json);
  json->EndObject();
}

// The header's "bop" member, after the reader's checks (ids >= 0, class
// names UTF-8).
template <typename Fail>
Status FormatBopSource(const BopSource& bop, Fail fail, JsonWriter* json) {
  if (bop.scene_id < 0) {
    return fail(
        "bop.scene_id",
        "must be a non-negative integer, got " + std::to_string(bop.scene_id));
  }
  for (const auto& [name, obj_id] : bop.obj_ids) {
    const std::string path = "bop.obj_ids." + name;
    if (!IsUtf8(name)) return fail(path, "class name is not UTF-8");
    if (obj_id < 0) {
      return fail(
          path,
          "must be a non-negative integer, got " + std::to_string(obj_id));
    }
  }
  json->Key("bop").BeginObject().Member("scene_id", bop.scene_id);
  json->Key("obj_ids").BeginObject();
  for (const auto& [name, obj_id] : bop.obj_ids) json->Member(name, obj_id);
  json->EndObject().EndObject();
  return Status::Ok();
}

}  // namespace

class LogWriter::Impl {
 public:
  Impl(std::unique_ptr<std::ofstream> file,
       std::ostream* stream,
       std::string name)
      : file_(std::move(file)), out_(stream), name_(std::move(name)) {}

  ~Impl() {
    if (file_) file_->close();
  }

  Status WriteHeader(const LogHeader& header) {
    auto fail = [this](const std::string& path, const std::string& what) {
      return Status::Error(name_ + ": header: " + path + ": " + what);
    };
    if (header.version != kLogFormatVersion) {
      return Status::Error(name_ + ": header: version " +
                           std::to_string(header.version) +
                           " is not supported (this writer writes version " +
                           std::to_string(kLogFormatVersion) + ")");
    }
    has_camera_ = header.camera.has_value();
    line_.clear();
    JsonWriter json(&line_);
    json.BeginObject()
        .Member("format", "symba-log")
        .Member("version", kLogFormatVersion);
    if (header.camera) {
      const PinholeIntrinsics& camera = *header.camera;
      Status status = CheckPositive(camera.fx, "camera.fx", fail);
      if (status.ok()) status = CheckPositive(camera.fy, "camera.fy", fail);
      if (!status.ok()) return status;
      if (!std::isfinite(camera.cx) || !std::isfinite(camera.cy)) {
        return fail("camera", "non-finite number");
      }
      json.Key("camera")
          .BeginObject()
          .Member("fx", camera.fx)
          .Member("fy", camera.fy)
          .Member("cx", camera.cx)
          .Member("cy", camera.cy)
          .EndObject();
    }
    if (!header.classes.empty()) {
      json.Key("classes").BeginObject();
      for (const auto& [name, prior] : header.classes) {
        const std::string path = "classes." + name;
        if (!IsUtf8(name)) return fail(path, "class name is not UTF-8");
        const bool discrete = prior.symmetry == SymmetryType::kDiscrete;
        if (discrete && (prior.order < 2 || prior.order > 1000000)) {
          return fail(path + ".order",
                      "must be an integer from 2 to 1000000, got " +
                          std::to_string(prior.order));
        }
        if (!discrete && prior.order != 0) {
          return fail(path + ".order", "only a discrete class has an order");
        }
        if (!Finite(prior.axis_o)) {
          return fail(path + ".axis", "non-finite number");
        }
        const bool has_axis = !prior.axis_o.isZero(0.0);
        if (has_axis && prior.symmetry == SymmetryType::kAsymmetric) {
          return fail(path + ".axis",
                      "an asymmetric class has no symmetry axis");
        }
        if (!IsUsablePriorAxis(prior.axis_o)) {
          return fail(path + ".axis", "must have a norm in [1e-100, 1e100]");
        }
        json.Key(name).BeginObject().Member("symmetry",
                                            ToString(prior.symmetry));
        if (discrete) json.Member("order", prior.order);
        if (has_axis) json.Key("axis").Doubles(prior.axis_o.data(), 3);
        json.EndObject();
      }
      json.EndObject();
    }
    if (header.bop) {
      const Status status = FormatBopSource(*header.bop, fail, &json);
      if (!status.ok()) return status;
    }
    json.EndObject();
    line_.push_back('\n');
    return Emit();
  }

  Status Write(const KeyframeInput& keyframe) {
    if (closed_) return Status::Error(name_ + ": write after Close");
    if (!error_.ok()) return error_;
    Status status = Check(keyframe);
    if (!status.ok()) return status;
    Format(keyframe);
    status = Emit();
    if (!status.ok()) return status;
    has_previous_ = true;
    previous_id_ = keyframe.id;
    previous_timestamp_ = keyframe.timestamp;
    ids_.push_back(keyframe.id);
    return Status::Ok();
  }

  Status Close() {
    if (closed_) return error_;
    closed_ = true;
    if (error_.ok()) {
      out_->flush();
      if (file_) file_->close();
      if (out_->fail()) error_ = Status::Error(name_ + ": write error");
    } else if (file_) {
      file_->close();
    }
    return error_;
  }

 private:
  Status Emit() {
    out_->write(line_.data(), static_cast<std::streamsize>(line_.size()));
    if (out_->fail()) error_ = Status::Error(name_ + ": write error");
    return error_;
  }

  Status Check(const KeyframeInput& keyframe) const {
    const std::string where =
        name_ + ": keyframe " + std::to_string(keyframe.id) + ": ";
    auto fail = [&where](const std::string& path, const std::string& what) {
      return Status::Error(where + path + ": " + what);
    };
    if (has_previous_ && keyframe.id <= previous_id_) {
      return fail("keyframe",
                  "id is not greater than the previous id " +
                      std::to_string(previous_id_));
    }
    if (!std::isfinite(keyframe.timestamp)) {
      return fail("t", "non-finite number");
    }
    if (has_previous_ && keyframe.timestamp < previous_timestamp_) {
      return fail("t",
                  FormatDouble(keyframe.timestamp) +
                      " is before the previous keyframe's time " +
                      FormatDouble(previous_timestamp_));
    }
    if (!has_previous_ && !keyframe.T_wc) {
      return fail("T_wc", "missing (the first keyframe needs T_wc)");
    }
    if (!keyframe.T_wc && !keyframe.odometry) {
      return fail("T_wc", "neither T_wc nor odometry");
    }
    Status status;
    if (keyframe.T_wc) status = CheckPose(*keyframe.T_wc, "T_wc", fail);
    if (!status.ok()) return status;
    if (keyframe.odometry) {
      const Odometry& odometry = *keyframe.odometry;
      status = CheckPose(odometry.T_prev_cur, "odometry.T", fail);
      if (status.ok()) {
        status = CheckPositive(odometry.sigma_t, "odometry.sigma_t", fail);
      }
      if (status.ok()) {
        status = CheckPositive(odometry.sigma_r, "odometry.sigma_r", fail);
      }
      if (!status.ok()) return status;
    }
    for (std::size_t d = 0; d < keyframe.detections.size(); ++d) {
      const DetectionInput& detection = keyframe.detections[d];
      const MemberPath path(nullptr, "detections", d);
      if (!IsUtf8(detection.id)) return fail(path.Text() + ".id", "not UTF-8");
      if (!IsUtf8(detection.class_name)) {
        return fail(path.Text() + ".class", "not UTF-8");
      }
      if (!std::isfinite(detection.score)) {
        return fail(path.Text() + ".score", "non-finite number");
      }
      if (detection.sigma_t) {
        status = CheckPositive(*detection.sigma_t, {&path, "sigma_t"}, fail);
        if (!status.ok()) return status;
      }
      if (detection.sigma_r) {
        status = CheckPositive(*detection.sigma_r, {&path, "sigma_r"}, fail);
        if (!status.ok()) return status;
      }
      if (detection.hypotheses.empty()) {
        return fail(path.Text() + ".hypotheses",
                    "empty; a detection needs at least one hypothesis");
      }
      for (std::size_t h = 0; h < detection.hypotheses.size(); ++h) {
        const MemberPath h_path(&path, "hypotheses", h);
        status = CheckPose(detection.hypotheses[h].T_co, h_path, fail);
        if (status.ok()) {
          status = CheckPositive(
              detection.hypotheses[h].weight, {&h_path, "w"}, fail);
        }
        if (!status.ok()) return status;
      }
    }
    if (!keyframe.points.empty() && !has_camera_) {
      return fail("points", "the header has no camera");
    }
    for (std::size_t p = 0; p < keyframe.points.size(); ++p) {
      const PointObservation& point = keyframe.points[p];
      const MemberPath path(nullptr, "points", p);
      if (!point.uv.allFinite()) {
        return fail(path.Text() + ".uv", "non-finite number");
      }
      if (point.depth) {
        status = CheckPositive(*point.depth, {&path, "depth"}, fail);
        if (!status.ok()) return status;
      }
    }
    for (std::size_t c = 0; c < keyframe.loop_closures.size(); ++c) {
      const LoopClosureInput& closure = keyframe.loop_closures[c];
      const MemberPath path(nullptr, "loop_closures", c);
      if (!std::binary_search(ids_.begin(), ids_.end(), closure.keyframe)) {
        return fail(path.Text() + ".keyframe",
                    std::to_string(closure.keyframe) +
                        " is not the id of an earlier keyframe of this log");
      }
      status = CheckPose(closure.T, {&path, "T"}, fail);
      if (status.ok()) {
        status = CheckPositive(closure.sigma_t, {&path, "sigma_t"}, fail);
      }
      if (status.ok()) {
        status = CheckPositive(closure.sigma_r, {&path, "sigma_r"}, fail);
      }
      if (!status.ok()) return status;
    }
    return Status::Ok();
  }

  void Format(const KeyframeInput& keyframe) {
    line_.clear();
    JsonWriter json(&line_);
    json.BeginObject()
        .Member("keyframe", keyframe.id)
        .Member("t", keyframe.timestamp);
    if (keyframe.T_wc) {
      json.Key("T_wc");
      Pose(*keyframe.T_wc, &json);
    }
    if (keyframe.odometry) {
      json.Key("odometry").BeginObject().Key("T");
      Pose(keyframe.odometry->T_prev_cur, &json);
      json.Member("sigma_t", keyframe.odometry->sigma_t)
          .Member("sigma_r", keyframe.odometry->sigma_r)
          .EndObject();
    }
    if (!keyframe.detections.empty()) {
      json.Key("detections").BeginArray();
      for (const DetectionInput& detection : keyframe.detections) {
        FormatDetection(detection, &json);
      }
      json.EndArray();
    }
    if (!keyframe.points.empty()) {
      json.Key("points").BeginArray();
      for (const PointObservation& point : keyframe.points) {
        json.BeginObject().Member("id", point.id);
        json.Key("uv").Doubles(point.uv.data(), 2);
        if (point.depth) json.Member("depth", *point.depth);
        json.EndObject();
      }
      json.EndArray();
    }
    if (!keyframe.loop_closures.empty()) {
      json.Key("loop_closures").BeginArray();
      for (const LoopClosureInput& closure : keyframe.loop_closures) {
        json.BeginObject().Member("keyframe", closure.keyframe).Key("T");
        Pose(closure.T, &json);
        json.Member("sigma_t", closure.sigma_t)
            .Member("sigma_r", closure.sigma_r)
            .EndObject();
      }
      json.EndArray();
    }
    json.EndObject();
    line_.push_back('\n');
  }

  // Optional members are left out at their defaults (no id, score 1, no
  // claimed sigma, weight 1).
  static void FormatDetection(const DetectionInput& detection,
                              JsonWriter* json) {
    json->BeginObject();
    if (!detection.id.empty()) json->Member("id", detection.id);
    json->Member("class", detection.class_name);
    if (detection.score != 1.0) json->Member("score", detection.score);
    if (detection.sigma_t) json->Member("sigma_t", *detection.sigma_t);
    if (detection.sigma_r) json->Member("sigma_r", *detection.sigma_r);
    json->Key("hypotheses").BeginArray();
    for (const PoseHypothesis& hypothesis : detection.hypotheses) {
      json->BeginObject();
      PoseMembers(hypothesis.T_co, json);
      if (hypothesis.weight != 1.0) json->Member("w", hypothesis.weight);
      json->EndObject();
    }
    json->EndArray().EndObject();
  }

  std::unique_ptr<std::ofstream> file_;  // null when writing to a stream
  std::ostream* out_;
  std::string name_;
  std::string line_;
  bool has_camera_ = false;
  bool has_previous_ = false;
  int64_t previous_id_ = 0;
  double previous_timestamp_ = 0.0;
  std::vector<int64_t> ids_;  // every keyframe written, increasing
  bool closed_ = false;
  Status error_;
};

LogWriter::LogWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LogWriter::~LogWriter() = default;

Status LogWriter::Open(const std::string& path,
                       const LogHeader& header,
                       std::unique_ptr<LogWriter>* writer) {
  writer->reset();
  auto file = std::make_unique<std::ofstream>(
      path, std::ios::binary | std::ios::out | std::ios::trunc);
  if (!file->is_open()) return Status::Error(path + ": cannot open");
  std::ostream* stream = file.get();
  auto impl = std::make_unique<Impl>(std::move(file), stream, path);
  Status status = impl->WriteHeader(header);
  if (!status.ok()) return status;
  writer->reset(new LogWriter(std::move(impl)));
  return Status::Ok();
}

Status LogWriter::OpenStream(std::ostream* stream,
                             const std::string& name,
                             const LogHeader& header,
                             std::unique_ptr<LogWriter>* writer) {
  writer->reset();
  auto impl = std::make_unique<Impl>(nullptr, stream, name);
  Status status = impl->WriteHeader(header);
  if (!status.ok()) return status;
  writer->reset(new LogWriter(std::move(impl)));
  return Status::Ok();
}

Status LogWriter::Write(const KeyframeInput& keyframe) {
  return impl_->Write(keyframe);
}

Status LogWriter::Close() { return impl_->Close(); }

}  // namespace symba
