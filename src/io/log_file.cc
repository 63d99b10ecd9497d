#include "symba/io/log_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include "symba/io/file_output.h"

namespace symba {

Status WriteLogAtomically(const std::string& path,
                          const LogHeader& header,
                          const std::function<const KeyframeInput*()>& next) {
  Status checked = CheckFileTarget(path);
  if (!checked.ok()) return checked;
  const std::string temporary =
      path + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  Status status;
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    if (!file.is_open()) {
      return Status::Error(path + ": cannot open for writing (" +
                           std::strerror(errno) + ")");
    }
    std::unique_ptr<LogWriter> writer;
    status = LogWriter::OpenStream(&file, path, header, &writer);
    const KeyframeInput* keyframe = nullptr;
    while (status.ok() && (keyframe = next()) != nullptr) {
      status = writer->Write(*keyframe);
    }
    if (status.ok()) status = writer->Close();
    if (status.ok()) {
      file.close();
      if (!file) status = Status::Error(path + ": write error");
    }
  }
  if (status.ok() && std::rename(temporary.c_str(), path.c_str()) != 0) {
    status = Status::Error(path + ": cannot rename into place (" +
                           std::strerror(errno) + ")");
  }
  if (!status.ok()) std::remove(temporary.c_str());
  return status;
}

Status WriteLogAtomically(const std::string& path,
                          const LogHeader& header,
                          const std::vector<KeyframeInput>& keyframes) {
  std::size_t i = 0;
  return WriteLogAtomically(path, header, [&]() -> const KeyframeInput* {
    return i < keyframes.size() ? &keyframes[i++] : nullptr;
  });
}

}  // namespace symba
