#include "io/text_file.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace symba::internal {

Status OpenForReading(const std::string& path, std::ifstream* in) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    return Status::Error(path + ": is a directory");
  }
  in->open(path, std::ios::binary);
  if (!*in) return Status::Error(path + ": cannot open");
  return Status::Ok();
}

std::size_t StreamSize(std::ifstream* in) {
  in->seekg(0, std::ios::end);
  const std::streamoff size =
      *in ? static_cast<std::streamoff>(in->tellg()) : std::streamoff(-1);
  in->clear();
  if (size < 0) return 0;  // not seekable: nothing was moved
  in->seekg(0);
  return static_cast<std::size_t>(size);
}

Status ReadText(const std::string& path, std::string* text) {
  std::ifstream in;
  Status status = OpenForReading(path, &in);
  if (!status.ok()) return status;
  // One read of the whole size (a byte-by-byte copy is 10x slower on the
  // 100 MB files detectors write); a stream without a size (a pipe) is read
  // to its end.
  const std::size_t size = StreamSize(&in);
  if (size > 0) {
    text->resize(size);
    in.read(text->data(), static_cast<std::streamsize>(size));
    if (static_cast<std::size_t>(in.gcount()) != size) {
      return Status::Error(path + ": cannot read");
    }
    return Status::Ok();
  }
  text->assign(std::istreambuf_iterator<char>(in),
               std::istreambuf_iterator<char>());
  if (in.bad()) return Status::Error(path + ": cannot read");
  return Status::Ok();
}

std::string_view WithoutByteOrderMark(std::string_view text) {
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  if (text.substr(0, kUtf8Bom.size()) == kUtf8Bom) {
    text.remove_prefix(kUtf8Bom.size());
  }
  return text;
}

std::vector<std::string_view> SplitLines(const std::string& text) {
  std::vector<std::string_view> lines;
  std::string_view rest = WithoutByteOrderMark(text);
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    std::string_view line = rest.substr(0, end);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    rest.remove_prefix(end + 1);
  }
  return lines;
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(" \t", pos);
    if (pos == std::string_view::npos) break;
    const std::size_t end =
        std::min(line.find_first_of(" \t", pos), line.size());
    fields.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return fields;
}

bool IsBlank(std::string_view line) {
  return line.find_first_not_of(" \t") == std::string_view::npos;
}

bool ParseDouble(std::string_view token, double* value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(*value);
}

std::string At(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

std::string Quoted(const std::string& text) { return "\"" + text + "\""; }

std::string Approx(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", value);
  return buffer;
}

}  // namespace symba::internal
