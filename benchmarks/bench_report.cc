#include "bench_report.h"

#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iterator>
#include <thread>

namespace symba::bench {

std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  int n = 0;
  for (double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++n;
    }
  }
  return n > 0 ? sum / n : std::nan("");
}

double Median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(),
                              values.end(),
                              [](double v) { return !std::isfinite(v); }),
               values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string Count(int n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

Status WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) return Status::Error(path + ": cannot write");
  return Status::Ok();
}

namespace {

std::string ReadOrEmpty(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
}

// The offset of the line `heading` in `text`, or npos.
std::size_t HeadingAt(const std::string& text, const std::string& heading) {
  if (text.compare(0, heading.size(), heading) == 0) return 0;
  const std::size_t at = text.find("\n" + heading);
  return at == std::string::npos ? at : at + 1;
}

}  // namespace

std::string TailFrom(const std::string& path, const std::string& heading) {
  const std::string text = ReadOrEmpty(path);
  const std::size_t at = HeadingAt(text, heading);
  return at == std::string::npos ? "" : text.substr(at);
}

Status WriteKeepingTail(const std::string& path,
                        const std::string& head,
                        const std::string& heading) {
  const std::string tail = TailFrom(path, heading);
  return WriteText(path, tail.empty() ? head : head + "\n" + tail);
}

Status ReplaceTail(const std::string& path,
                   const std::string& heading,
                   const std::string& section) {
  std::string text = ReadOrEmpty(path);
  const std::size_t at = HeadingAt(text, heading);
  if (at != std::string::npos) {
    text.erase(at);
  } else if (!text.empty()) {
    text += "\n";
  }
  return WriteText(path, text + section);
}

Status ReplaceSection(const std::string& path,
                      const std::string& heading,
                      const std::string& next,
                      const std::string& section) {
  const std::string text = ReadOrEmpty(path);
  const std::size_t at = HeadingAt(text, heading);
  if (at == std::string::npos) {
    return WriteText(path, text.empty() ? section : text + "\n" + section);
  }
  const std::size_t end = text.find("\n" + next, at + heading.size());
  const std::string rest =
      end == std::string::npos ? "" : "\n" + text.substr(end + 1);
  return WriteText(path, text.substr(0, at) + section + rest);
}

std::string Command(int argc, char** argv) {
  std::string command;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) command += ' ';
    command += argv[i];
  }
  return command;
}

std::string Machine() {
  std::string cpu = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) cpu = line.substr(colon + 2);
      break;
    }
  }
  std::string os = "unknown OS";
  struct utsname name;
  if (::uname(&name) == 0) {
    os = std::string(name.sysname) + " " + name.release + " " + name.machine;
  }
  return cpu + ", " + std::to_string(std::thread::hardware_concurrency()) +
         " hardware threads, " + os;
}

std::string UtcDate() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%d %H:%M UTC", &tm);
  return buffer;
}

}  // namespace symba::bench
