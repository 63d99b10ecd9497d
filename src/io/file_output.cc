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
  std::error_code error;
  fs::path dir = fs::path(dir_name);
  if (dir.filename().empty()) dir = dir.parent_path();  // "out/" -> "out"
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

Status WriteFileAtomically(const std::string& path,
                           const std::string& content) {
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
