// libFuzzer target for the log reader (scripts/fuzz builds and runs it).
//
// For every input, taken as a log file:
//   1. Differential parse of each line: when the fast scanner accepts a line,
//      nlohmann must accept it too and build the identical tree (the fast
//      scanner may give up on valid JSON, never accept invalid JSON).
//   2. The reader either fails with "fuzz.jsonl:LINE: ..." or returns
//      keyframes that satisfy the format's invariants (unit quaternions,
//      positive weights, sigmas and depths, increasing ids, ...).
//   3. Whatever it accepted, LogWriter writes and LogReader reads back bit
//      for bit.
// A violated check aborts, which libFuzzer reports as a crash.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/json_tree.h"
#include "symba/io/log_format.h"

namespace symba {
namespace {

using io_internal::JsonError;
using io_internal::JsonTree;
using io_internal::JsonType;

void Check(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "log_reader_fuzzer: check failed: %s\n", what);
    std::abort();
  }
}

bool SameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

bool SameTree(const JsonTree& a, const JsonTree& b) {
  if (a.size() != b.size()) return false;
  for (JsonTree::Index i = 0; i < a.size(); ++i) {
    const JsonTree::Node& x = a.node(i);
    const JsonTree::Node& y = b.node(i);
    if (x.type != y.type || x.size != y.size || x.first != y.first ||
        x.next != y.next || a.Key(i) != b.Key(i)) {
      return false;
    }
    switch (x.type) {
      case JsonType::kInteger:
        if (x.integer != y.integer) return false;
        break;
      case JsonType::kUnsigned:
        if (x.unsigned_integer != y.unsigned_integer) return false;
        break;
      case JsonType::kFloat:
        if (!SameBits(x.number, y.number)) return false;
        break;
      case JsonType::kString:
        if (a.String(i) != b.String(i)) return false;
        break;
      default:
        break;
    }
  }
  return true;
}

void CheckLines(const std::string& text) {
  static JsonTree fast;
  static JsonTree reference;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    if (io_internal::ParseJsonFast(line, &fast)) {
      JsonError error;
      Check(io_internal::ParseJsonNlohmann(line, &reference, &error),
            "the fast scanner accepted what nlohmann rejects");
      Check(SameTree(fast, reference), "the two parsers built different trees");
    }
    start = end + 1;
  }
}

bool Unit(const Eigen::Quaterniond& q) {
  return std::abs(q.squaredNorm() - 1.0) <= 1e-14;
}

void CheckKeyframe(const KeyframeInput& keyframe, const LogHeader& header) {
  Check(std::isfinite(keyframe.timestamp), "finite time");
  if (keyframe.T_wc) {
    Check(Unit(keyframe.T_wc->q), "unit T_wc");
    Check(keyframe.T_wc->t.allFinite(), "finite T_wc");
  }
  if (keyframe.odometry) {
    Check(Unit(keyframe.odometry->T_prev_cur.q), "unit odometry");
    Check(keyframe.odometry->sigma_t > 0 && keyframe.odometry->sigma_r > 0,
          "positive odometry sigmas");
  }
  for (const DetectionInput& detection : keyframe.detections) {
    Check(!detection.id.empty(), "detection id");
    Check(!detection.hypotheses.empty(), "hypotheses");
    Check(std::isfinite(detection.score), "finite score");
    Check(!detection.sigma_t || *detection.sigma_t > 0, "sigma_t");
    Check(!detection.sigma_r || *detection.sigma_r > 0, "sigma_r");
    for (const PoseHypothesis& hypothesis : detection.hypotheses) {
      Check(Unit(hypothesis.T_co.q), "unit hypothesis");
      Check(hypothesis.T_co.t.allFinite(), "finite hypothesis");
      Check(hypothesis.weight > 0 && std::isfinite(hypothesis.weight),
            "positive weight");
    }
  }
  Check(keyframe.points.empty() || header.camera.has_value(), "camera");
  for (const PointObservation& point : keyframe.points) {
    Check(point.uv.allFinite(), "finite uv");
    Check(!point.depth || *point.depth > 0, "positive depth");
  }
}

bool SamePose(const Rigid3d& a, const Rigid3d& b) {
  for (int k = 0; k < 3; ++k) {
    if (!SameBits(a.t[k], b.t[k])) return false;
  }
  for (int k = 0; k < 4; ++k) {
    if (!SameBits(a.q.coeffs()[k], b.q.coeffs()[k])) return false;
  }
  return true;
}

bool SameOptional(const std::optional<double>& a,
                  const std::optional<double>& b) {
  return a.has_value() == b.has_value() && (!a || SameBits(*a, *b));
}

bool SameKeyframe(const KeyframeInput& a, const KeyframeInput& b) {
  if (a.id != b.id || !SameBits(a.timestamp, b.timestamp) ||
      a.T_wc.has_value() != b.T_wc.has_value() ||
      (a.T_wc && !SamePose(*a.T_wc, *b.T_wc)) ||
      a.odometry.has_value() != b.odometry.has_value() ||
      a.detections.size() != b.detections.size() ||
      a.points.size() != b.points.size()) {
    return false;
  }
  if (a.odometry &&
      (!SamePose(a.odometry->T_prev_cur, b.odometry->T_prev_cur) ||
       !SameBits(a.odometry->sigma_t, b.odometry->sigma_t) ||
       !SameBits(a.odometry->sigma_r, b.odometry->sigma_r))) {
    return false;
  }
  for (std::size_t d = 0; d < a.detections.size(); ++d) {
    const DetectionInput& x = a.detections[d];
    const DetectionInput& y = b.detections[d];
    if (x.id != y.id || x.class_name != y.class_name ||
        !SameBits(x.score, y.score) || !SameOptional(x.sigma_t, y.sigma_t) ||
        !SameOptional(x.sigma_r, y.sigma_r) ||
        x.hypotheses.size() != y.hypotheses.size()) {
      return false;
    }
    for (std::size_t h = 0; h < x.hypotheses.size(); ++h) {
      if (!SamePose(x.hypotheses[h].T_co, y.hypotheses[h].T_co) ||
          !SameBits(x.hypotheses[h].weight, y.hypotheses[h].weight)) {
        return false;
      }
    }
  }
  for (std::size_t p = 0; p < a.points.size(); ++p) {
    const PointObservation& x = a.points[p];
    const PointObservation& y = b.points[p];
    if (x.id != y.id || !SameBits(x.uv.x(), y.uv.x()) ||
        !SameBits(x.uv.y(), y.uv.y()) || !SameOptional(x.depth, y.depth)) {
      return false;
    }
  }
  return true;
}

bool SameHeader(const LogHeader& a, const LogHeader& b) {
  if (a.version != b.version || a.camera.has_value() != b.camera.has_value() ||
      a.classes.size() != b.classes.size() ||
      a.bop.has_value() != b.bop.has_value()) {
    return false;
  }
  if (a.bop && (a.bop->scene_id != b.bop->scene_id ||
                a.bop->obj_ids != b.bop->obj_ids)) {
    return false;
  }
  if (a.camera && (!SameBits(a.camera->fx, b.camera->fx) ||
                   !SameBits(a.camera->fy, b.camera->fy) ||
                   !SameBits(a.camera->cx, b.camera->cx) ||
                   !SameBits(a.camera->cy, b.camera->cy))) {
    return false;
  }
  for (auto x = a.classes.begin(), y = b.classes.begin(); x != a.classes.end();
       ++x, ++y) {
    if (x->first != y->first || x->second.symmetry != y->second.symmetry ||
        x->second.order != y->second.order) {
      return false;
    }
    for (int k = 0; k < 3; ++k) {
      if (!SameBits(x->second.axis_o[k], y->second.axis_o[k])) return false;
    }
  }
  return true;
}

// Reads `text`; on success fills header and keyframes.
Status ReadAll(const std::string& text,
               LogHeader* header,
               std::vector<KeyframeInput>* keyframes) {
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::OpenStream(
      std::make_unique<std::istringstream>(text), "fuzz.jsonl", &reader);
  if (!status.ok()) return status;
  *header = reader->header();
  KeyframeInput keyframe;
  while (true) {
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (!status.ok() || end) return status;
    Check(reader->line() >= 2, "line of a keyframe");
    keyframes->push_back(keyframe);
  }
}

void Run(const std::string& text) {
  CheckLines(text);

  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ReadAll(text, &header, &keyframes);
  if (!status.ok()) {
    Check(status.message().rfind("fuzz.jsonl:", 0) == 0, "error prefix");
    const char* line = status.message().c_str() + std::strlen("fuzz.jsonl:");
    Check(*line >= '1' && *line <= '9', "error line number");
    return;
  }
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    CheckKeyframe(keyframes[k], header);
    Check(k == 0 || keyframes[k].id > keyframes[k - 1].id, "increasing ids");
    Check(k == 0 || keyframes[k].timestamp >= keyframes[k - 1].timestamp,
          "non-decreasing time");
    Check(k > 0 || keyframes[k].T_wc.has_value(), "T_wc on the first");
    Check(keyframes[k].T_wc || keyframes[k].odometry, "T_wc or odometry");
  }

  std::ostringstream written;
  std::unique_ptr<LogWriter> writer;
  Check(LogWriter::OpenStream(&written, "out", header, &writer).ok(),
        "the writer takes the header the reader accepted");
  for (const KeyframeInput& keyframe : keyframes) {
    Check(writer->Write(keyframe).ok(),
          "the writer takes the keyframes the reader accepted");
  }
  Check(writer->Close().ok(), "close");

  LogHeader header_again;
  std::vector<KeyframeInput> again;
  Check(ReadAll(written.str(), &header_again, &again).ok(),
        "the reader takes what the writer wrote");
  Check(SameHeader(header, header_again), "the header round trips");
  Check(again.size() == keyframes.size(), "every keyframe round trips");
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    Check(SameKeyframe(keyframes[k], again[k]), "a keyframe round trips");
  }
}

}  // namespace
}  // namespace symba

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  symba::Run(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
