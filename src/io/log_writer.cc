// LogWriter: the log format v1 (docs/log-format.md). One line per call,
// built in a reused buffer and written in one piece, after the keyframe has
// passed the same checks the reader makes.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "io/json_text.h"
#include "io/text_file.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/io/log_format.h"

namespace symba {
namespace {

using internal::Approx;
using io_internal::AppendJsonDouble;
using io_internal::AppendJsonString;

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

// Checks what the reader checks; `fail` turns (path, reason) into a Status.
template <typename Fail>
Status CheckPose(const Rigid3d& pose, const std::string& path, Fail fail) {
  if (!Finite(pose.t)) return fail(path + ".t", "non-finite number");
  if (!pose.q.coeffs().allFinite())
    return fail(path + ".q", "non-finite number");
  const double norm = pose.q.norm();
  if (!(std::abs(norm - 1.0) <= 1e-3)) {
    return fail(path + ".q",
                "quaternion norm " + Approx(norm) + " is not within 1e-3 of 1");
  }
  return Status::Ok();
}

template <typename Fail>
Status CheckPositive(double value, const std::string& path, Fail fail) {
  if (!std::isfinite(value)) return fail(path, "non-finite number");
  if (!(value > 0.0))
    return fail(path, "must be positive, got " + FormatDouble(value));
  return Status::Ok();
}

void AppendPose(const Rigid3d& pose, std::string* out) {
  out->append("{\"t\":[");
  for (int k = 0; k < 3; ++k) {
    if (k > 0) out->push_back(',');
    AppendJsonDouble(pose.t[k], out);
  }
  out->append("],\"q\":[");
  const double q[4] = {pose.q.x(), pose.q.y(), pose.q.z(), pose.q.w()};
  for (int k = 0; k < 4; ++k) {
    if (k > 0) out->push_back(',');
    AppendJsonDouble(q[k], out);
  }
  out->append("]}");
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
    line_.assign("{\"format\":\"symba-log\",\"version\":");
    line_.append(std::to_string(kLogFormatVersion));
    if (header.camera) {
      const PinholeIntrinsics& camera = *header.camera;
      Status status = CheckPositive(camera.fx, "camera.fx", fail);
      if (status.ok()) status = CheckPositive(camera.fy, "camera.fy", fail);
      if (!status.ok()) return status;
      if (!std::isfinite(camera.cx) || !std::isfinite(camera.cy)) {
        return fail("camera", "non-finite number");
      }
      line_.append(",\"camera\":{\"fx\":");
      AppendJsonDouble(camera.fx, &line_);
      line_.append(",\"fy\":");
      AppendJsonDouble(camera.fy, &line_);
      line_.append(",\"cx\":");
      AppendJsonDouble(camera.cx, &line_);
      line_.append(",\"cy\":");
      AppendJsonDouble(camera.cy, &line_);
      line_.push_back('}');
    }
    if (!header.classes.empty()) {
      line_.append(",\"classes\":{");
      bool first = true;
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
        if (!first) line_.push_back(',');
        first = false;
        AppendJsonString(name, &line_);
        line_.append(":{\"symmetry\":");
        AppendJsonString(ToString(prior.symmetry), &line_);
        if (discrete) {
          line_.append(",\"order\":").append(std::to_string(prior.order));
        }
        if (has_axis) {
          line_.append(",\"axis\":[");
          for (int k = 0; k < 3; ++k) {
            if (k > 0) line_.push_back(',');
            AppendJsonDouble(prior.axis_o[k], &line_);
          }
          line_.push_back(']');
        }
        line_.push_back('}');
      }
      line_.push_back('}');
    }
    line_.append("}\n");
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
      const std::string path = "detections[" + std::to_string(d) + "]";
      if (!IsUtf8(detection.id)) return fail(path + ".id", "not UTF-8");
      if (!IsUtf8(detection.class_name)) {
        return fail(path + ".class", "not UTF-8");
      }
      if (!std::isfinite(detection.score)) {
        return fail(path + ".score", "non-finite number");
      }
      if (detection.sigma_t) {
        status = CheckPositive(*detection.sigma_t, path + ".sigma_t", fail);
        if (!status.ok()) return status;
      }
      if (detection.sigma_r) {
        status = CheckPositive(*detection.sigma_r, path + ".sigma_r", fail);
        if (!status.ok()) return status;
      }
      if (detection.hypotheses.empty()) {
        return fail(path + ".hypotheses",
                    "empty; a detection needs at least one hypothesis");
      }
      for (std::size_t h = 0; h < detection.hypotheses.size(); ++h) {
        const std::string h_path =
            path + ".hypotheses[" + std::to_string(h) + "]";
        status = CheckPose(detection.hypotheses[h].T_co, h_path, fail);
        if (status.ok()) {
          status = CheckPositive(
              detection.hypotheses[h].weight, h_path + ".w", fail);
        }
        if (!status.ok()) return status;
      }
    }
    if (!keyframe.points.empty() && !has_camera_) {
      return fail("points", "the header has no camera");
    }
    for (std::size_t p = 0; p < keyframe.points.size(); ++p) {
      const PointObservation& point = keyframe.points[p];
      const std::string path = "points[" + std::to_string(p) + "]";
      if (!point.uv.allFinite()) return fail(path + ".uv", "non-finite number");
      if (point.depth) {
        status = CheckPositive(*point.depth, path + ".depth", fail);
        if (!status.ok()) return status;
      }
    }
    return Status::Ok();
  }

  void Format(const KeyframeInput& keyframe) {
    line_.assign("{\"keyframe\":");
    line_.append(std::to_string(keyframe.id));
    line_.append(",\"t\":");
    AppendJsonDouble(keyframe.timestamp, &line_);
    if (keyframe.T_wc) {
      line_.append(",\"T_wc\":");
      AppendPose(*keyframe.T_wc, &line_);
    }
    if (keyframe.odometry) {
      line_.append(",\"odometry\":{\"T\":");
      AppendPose(keyframe.odometry->T_prev_cur, &line_);
      line_.append(",\"sigma_t\":");
      AppendJsonDouble(keyframe.odometry->sigma_t, &line_);
      line_.append(",\"sigma_r\":");
      AppendJsonDouble(keyframe.odometry->sigma_r, &line_);
      line_.push_back('}');
    }
    if (!keyframe.detections.empty()) {
      line_.append(",\"detections\":[");
      for (std::size_t d = 0; d < keyframe.detections.size(); ++d) {
        const DetectionInput& detection = keyframe.detections[d];
        if (d > 0) line_.push_back(',');
        line_.push_back('{');
        if (!detection.id.empty()) {
          line_.append("\"id\":");
          AppendJsonString(detection.id, &line_);
          line_.push_back(',');
        }
        line_.append("\"class\":");
        AppendJsonString(detection.class_name, &line_);
        if (detection.score != 1.0) {
          line_.append(",\"score\":");
          AppendJsonDouble(detection.score, &line_);
        }
        if (detection.sigma_t) {
          line_.append(",\"sigma_t\":");
          AppendJsonDouble(*detection.sigma_t, &line_);
        }
        if (detection.sigma_r) {
          line_.append(",\"sigma_r\":");
          AppendJsonDouble(*detection.sigma_r, &line_);
        }
        line_.append(",\"hypotheses\":[");
        for (std::size_t h = 0; h < detection.hypotheses.size(); ++h) {
          const PoseHypothesis& hypothesis = detection.hypotheses[h];
          if (h > 0) line_.push_back(',');
          AppendPose(hypothesis.T_co, &line_);
          if (hypothesis.weight != 1.0) {
            line_.pop_back();  // the pose's '}'
            line_.append(",\"w\":");
            AppendJsonDouble(hypothesis.weight, &line_);
            line_.push_back('}');
          }
        }
        line_.append("]}");
      }
      line_.push_back(']');
    }
    if (!keyframe.points.empty()) {
      line_.append(",\"points\":[");
      for (std::size_t p = 0; p < keyframe.points.size(); ++p) {
        const PointObservation& point = keyframe.points[p];
        if (p > 0) line_.push_back(',');
        line_.append("{\"id\":");
        line_.append(std::to_string(point.id));
        line_.append(",\"uv\":[");
        AppendJsonDouble(point.uv.x(), &line_);
        line_.push_back(',');
        AppendJsonDouble(point.uv.y(), &line_);
        line_.push_back(']');
        if (point.depth) {
          line_.append(",\"depth\":");
          AppendJsonDouble(*point.depth, &line_);
        }
        line_.push_back('}');
      }
      line_.push_back(']');
    }
    line_.append("}\n");
  }

  std::unique_ptr<std::ofstream> file_;  // null when writing to a stream
  std::ostream* out_;
  std::string name_;
  std::string line_;
  bool has_camera_ = false;
  bool has_previous_ = false;
  int64_t previous_id_ = 0;
  double previous_timestamp_ = 0.0;
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
