// The BOP results CSV reader. One pass over the file's bytes, read in
// chunks into one reused buffer, no allocation per row beyond the rows
// vector: detectors write millions of rows.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <Eigen/Geometry>

#include "import/bop_files.h"
#include "io/json_tree_reader.h"
#include "io/text_file.h"

namespace symba::import_internal {
namespace {

using internal::Approx;
using internal::At;

// R^T R may differ from I by this much (Frobenius norm): detectors write R
// with about six significant digits. The quaternion is normalised.
constexpr double kRotationTolerance = 1e-2;

constexpr std::string_view kColumns = "scene_id,im_id,obj_id,score,R,t,time";

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) {
    s.remove_suffix(1);
  }
  return s;
}

// Splits `line` at commas into at most 8 fields (8: too many).
int SplitCsv(std::string_view line, std::string_view fields[8]) {
  int n = 0;
  for (;;) {
    const std::size_t comma = line.find(',');
    fields[n++] = Trim(line.substr(0, comma));
    if (comma == std::string_view::npos || n == 8) return n;
    line.remove_prefix(comma + 1);
  }
}

// Exactly `n` whitespace-separated finite numbers.
bool ParseNumbers(std::string_view field, int n, double* out) {
  int count = 0;
  for (;;) {
    field = Trim(field);
    if (field.empty()) return count == n;
    if (count == n) return false;
    std::size_t end = 0;
    while (end < field.size() && field[end] != ' ' && field[end] != '\t') {
      ++end;
    }
    if (!internal::ParseDouble(field.substr(0, end), &out[count++])) {
      return false;
    }
    field.remove_prefix(end);
  }
}

bool ParseId(std::string_view field, int* id) {
  return internal::ParseInteger(field, id) && *id >= 0;
}

Status ParseRow(const std::string& path,
                int line,
                std::string_view text,
                BopResultRow* row) {
  std::string_view f[8];
  const int n = SplitCsv(text, f);
  if (n != 7) {
    return Status::Error(At(path, line) + ": expected 7 comma-separated " +
                         "fields (" + std::string(kColumns) + "), got " +
                         (n == 8 ? std::string("more") : std::to_string(n)));
  }
  const char* names[3] = {"scene_id", "im_id", "obj_id"};
  int* ids[3] = {&row->scene_id, &row->im_id, &row->obj_id};
  for (int i = 0; i < 3; ++i) {
    if (!ParseId(f[i], ids[i])) {
      return Status::Error(At(path, line) + ": " + names[i] +
                           ": expected a non-negative integer, got " +
                           io_internal::QuoteForMessage(f[i]));
    }
  }
  if (!internal::ParseDouble(f[3], &row->score)) {
    return Status::Error(At(path, line) + ": score: expected a number, got " +
                         io_internal::QuoteForMessage(f[3]));
  }
  double r[9];
  double t[3];
  double time = 0.0;
  if (!ParseNumbers(f[4], 9, r)) {
    return Status::Error(At(path, line) +
                         ": R: expected 9 space-separated numbers (row-major)");
  }
  if (!ParseNumbers(f[5], 3, t)) {
    return Status::Error(At(path, line) +
                         ": t: expected 3 space-separated numbers (mm)");
  }
  if (!internal::ParseDouble(f[6], &time)) {
    return Status::Error(At(path, line) + ": time: expected a number, got " +
                         io_internal::QuoteForMessage(f[6]));
  }
  const Eigen::Matrix3d R =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r);
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  const double det = R.determinant();
  if (!(error <= kRotationTolerance) || !(det > 0.0)) {
    return Status::Error(At(path, line) + ": R: not a rotation (|R^T R - I| " +
                         "= " + Approx(error) + ", det = " + Approx(det) + ")");
  }
  row->T_co = Rigid3d(Eigen::Quaterniond(R).normalized(),
                      Eigen::Vector3d(t[0], t[1], t[2]) / 1000.0);
  row->line = line;
  return Status::Ok();
}

// A first line that starts with "scene_id" is the header and must name the
// seven columns (a file with old Mac line ends, '\r' only, is one line).
Status CheckHeader(const std::string& path, int line, std::string_view text) {
  std::string_view f[8];
  const int n = SplitCsv(text, f);
  std::string_view columns = kColumns;
  bool same = n == 7;
  for (int i = 0; same && i < 7; ++i) {
    const std::size_t comma = columns.find(',');
    same = f[i] == columns.substr(0, comma);
    columns.remove_prefix(std::min(comma + 1, columns.size()));
  }
  if (same) return Status::Ok();
  return Status::Error(
      At(path, line) + ": a header line must be " + std::string(kColumns) +
      (text.find('\r') != std::string_view::npos
           ? " (this line holds a carriage return: lines must end with \\n "
             "or \\r\\n)"
           : ""));
}

// Asks Linux to back [data, data + bytes) with 2 MB pages where its
// transparent huge pages are given only on request: the rows of a 100 MB
// CSV fill ~60 MB, and faulting that in 4 kB pages cost a third of the
// reading on a virtual machine. Advice only; nothing changes elsewhere.
void AdviseHugePages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const std::uintptr_t start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t end = (start + bytes) & ~(kHuge - 1);
  if (end > begin) {
    ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

// Calls on_line(line number from 1, line without '\n' and a trailing '\r',
// the first without a byte order mark) for each line of `in` until it
// returns an error; a last line without '\n' counts when not empty. The
// file is read in chunks into one buffer (a line longer than the buffer
// grows it): a whole 100 MB file in memory costs more in page faults than
// parsing it. The read error is ReadText's.
template <typename OnLine>
Status ForEachLine(const std::string& path, std::ifstream* in, OnLine on_line) {
  std::string buffer(std::size_t{1} << 20, '\0');
  std::size_t end = 0;  // bytes in the buffer
  int line = 0;
  for (bool eof = false; !eof;) {
    if (end == buffer.size()) buffer.resize(2 * buffer.size());
    in->read(buffer.data() + end,
             static_cast<std::streamsize>(buffer.size() - end));
    // A read that stops short of the buffer has met the end (eof); one
    // that fails otherwise would be repeated for ever.
    if (in->bad() || (in->fail() && !in->eof())) {
      return Status::Error(path + ": cannot read");
    }
    end += static_cast<std::size_t>(in->gcount());
    eof = in->eof();
    std::string_view rest(buffer.data(), end);
    for (;;) {
      std::size_t newline = rest.find('\n');
      if (newline == std::string_view::npos && (!eof || rest.empty())) break;
      std::string_view current = rest.substr(0, newline);
      rest.remove_prefix(std::min(current.size() + 1, rest.size()));
      if (!current.empty() && current.back() == '\r') current.remove_suffix(1);
      if (line == 0) current = internal::WithoutByteOrderMark(current);
      Status status = on_line(++line, current);
      if (!status.ok()) return status;
    }
    std::memmove(buffer.data(), rest.data(), rest.size());  // unfinished line
    end = rest.size();
  }
  return Status::Ok();
}

}  // namespace

Status ReadBopResults(const std::string& path,
                      const std::optional<int>& scene,
                      std::vector<BopResultRow>* rows,
                      int* other_scene_rows) {
  std::ifstream in;
  Status opened = internal::OpenForReading(path, &in);
  if (!opened.ok()) return opened;
  rows->clear();
  // Rows are at least ~40 bytes; most are three times that.
  rows->reserve(internal::StreamSize(&in) / 120);
  AdviseHugePages(rows->data(), rows->capacity() * sizeof(BopResultRow));
  bool first = true;
  std::optional<int> only_scene = scene;
  int skipped = 0;  // with `scene`: rows of other scenes
  Status status =
      ForEachLine(path, &in, [&](int line, std::string_view current) -> Status {
        if (internal::IsBlank(current)) return Status::Ok();
        if (first && Trim(current).substr(0, 8) == "scene_id") {
          first = false;
          return CheckHeader(path, line, current);
        }
        first = false;
        BopResultRow row;
        Status status = ParseRow(path, line, current, &row);
        if (!status.ok()) return status;
        if (!only_scene) only_scene = row.scene_id;
        if (row.scene_id != *only_scene) {
          if (scene) {
            ++skipped;
            return Status::Ok();
          }
          return Status::Error(
              At(path, line) + ": scene " + std::to_string(row.scene_id) +
              " after scene " + std::to_string(*only_scene) +
              ": a log holds one scene; choose it with --scene");
        }
        rows->push_back(row);
        return Status::Ok();
      });
  if (other_scene_rows != nullptr) *other_scene_rows = skipped;
  return status;
}

}  // namespace symba::import_internal
