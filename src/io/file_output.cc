#include "symba/io/file_output.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace symba {
namespace {

namespace fs = std::filesystem;

// A sibling path of `dir` that no other writer uses.
fs::path SiblingPath(const fs::path& dir, const char* tag) {
  static std::atomic<int> counter{0};
  return dir.parent_path() /
         ("." + dir.filename().string() + "." + tag + "-" +
          std::to_string(::getpid()) + "-" + std::to_string(counter++));
}

Status WriteFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
  out.close();
  if (!out) return Status::Error(path.string() + ": cannot write");
  return Status::Ok();
}

}  // namespace

Status WriteDirectoryAtomically(
    const std::string& dir_name,
    const std::vector<std::pair<std::string, std::string>>& files) {
  if (dir_name.empty()) return Status::Error("output directory: empty path");
  std::error_code error;
  fs::path dir = fs::path(dir_name);
  if (dir.filename().empty()) dir = dir.parent_path();  // "out/" -> "out"
  if (dir.filename() == "." || dir.filename() == "..") {
    return Status::Error(dir_name +
                         ": name the output directory itself, not . or ..");
  }
  if (dir.parent_path().empty()) dir = fs::path(".") / dir;
  if (!fs::is_directory(dir.parent_path(), error)) {
    return Status::Error(dir_name + ": parent directory " +
                         dir.parent_path().string() + " does not exist");
  }
  if (fs::exists(dir, error) && !fs::is_directory(dir, error)) {
    return Status::Error(dir_name + ": exists and is not a directory");
  }
  const fs::path staging = SiblingPath(dir, "tmp");
  if (!fs::create_directory(staging, error)) {
    return Status::Error(dir_name + ": cannot create " + staging.string() +
                         ": " + error.message());
  }
  for (const auto& [name, content] : files) {
    Status status = WriteFile(staging / name, content);
    if (!status.ok()) {
      fs::remove_all(staging, error);
      return status;
    }
  }
  fs::path old;
  if (fs::exists(dir, error)) {
    old = SiblingPath(dir, "old");
    fs::rename(dir, old, error);
    if (error) {
      const std::string message = error.message();
      fs::remove_all(staging, error);
      return Status::Error(dir_name + ": cannot replace: " + message);
    }
  }
  fs::rename(staging, dir, error);
  if (error) {
    const std::string message = error.message();
    if (!old.empty()) fs::rename(old, dir, error);
    fs::remove_all(staging, error);
    return Status::Error(dir_name + ": cannot rename into place: " + message);
  }
  if (!old.empty()) fs::remove_all(old, error);
  return Status::Ok();
}

Status CheckFileTarget(const std::string& path) {
  if (path.empty()) return Status::Error("output file: empty path");
  std::error_code error;
  const fs::file_status target = fs::status(path, error);
  if (fs::exists(target) && !fs::is_regular_file(target)) {
    return Status::Error(path + ": exists and is not a regular file");
  }
  return Status::Ok();
}

Status CheckOutputSparesInputs(const std::string& output,
                               const std::vector<std::string>& inputs) {
  std::error_code error;
  fs::path out = fs::weakly_canonical(output, error);
  if (error || out.empty()) return Status::Ok();
  if (out.filename().empty()) out = out.parent_path();  // "dir/" -> "dir"
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    const fs::path in = fs::weakly_canonical(input, error);
    if (error) continue;
    if (in == out) return Status::Error(output + ": is the input " + input);
    // `in` lies inside `out` when `out` is a prefix of its components.
    auto o = out.begin();
    auto i = in.begin();
    while (o != out.end() && i != in.end() && *o == *i) ++o, ++i;
    if (o == out.end() && i != in.end()) {
      return Status::Error(output + ": holds the input " + input);
    }
  }
  return Status::Ok();
}

Status WriteFileAtomically(const std::string& path,
                           const std::string& content) {
  Status checked = CheckFileTarget(path);
  if (!checked.ok()) return checked;
  std::error_code error;
  const fs::path target(path);
  const fs::path temporary = SiblingPath(target, "tmp");
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out.is_open()) {
      return Status::Error(path + ": cannot write (" + std::strerror(errno) +
                           ")");
    }
    out << content;
    out.close();
    if (!out) {
      fs::remove(temporary, error);
      return Status::Error(path + ": cannot write (write error)");
    }
  }
  fs::rename(temporary, target, error);
  if (error) {
    const std::string message = error.message();
    fs::remove(temporary, error);
    return Status::Error(path + ": cannot rename into place (" + message + ")");
  }
  return Status::Ok();
}

}  // namespace symba
