// Writing a set of output files as one directory that appears complete or
// not at all (the outputs of `symba replay`, `symba simulate`, symba-bench).
#ifndef SYMBA_IO_FILE_OUTPUT_H_
#define SYMBA_IO_FILE_OUTPUT_H_

#include <string>
#include <utility>
#include <vector>

#include "symba/common/status.h"

namespace symba {

// Writes `files` (name, content) into directory `dir` atomically: they are
// written into a fresh sibling directory which is then renamed onto `dir`
// (an existing `dir` is moved aside first and removed only after the rename
// succeeded). On any failure nothing is left behind and an existing `dir` is
// untouched. The parent of `dir` must exist; `dir` must not be empty, "."
// or "..", nor an existing file that is not a directory.
Status WriteDirectoryAtomically(
    const std::string& dir,
    const std::vector<std::pair<std::string, std::string>>& files);

// Whether `path` can be replaced whole by a new file: not empty, and not an
// existing directory, device, pipe or socket (renaming a file over
// /dev/null would replace the device). Errors read "PATH: exists and is
// not a regular file" or "output file: empty path".
Status CheckFileTarget(const std::string& path);

// An output must not destroy an input: "OUTPUT: is the input INPUT" when
// the file `output` is one of `inputs` (the same file, by any path), and
// "OUTPUT: holds the input INPUT" when an input lies inside the directory
// `output` that is to be replaced. Empty inputs are skipped.
Status CheckOutputSparesInputs(const std::string& output,
                               const std::vector<std::string>& inputs);

// Writes `content` to the file `path` atomically: into a temporary sibling
// that is renamed onto `path` when complete. On failure the temporary file
// is removed and an existing `path` is untouched. Errors: CheckFileTarget's,
// "PATH: cannot write (reason)" or "PATH: cannot rename into place
// (reason)".
Status WriteFileAtomically(const std::string& path, const std::string& content);

}  // namespace symba

#endif  // SYMBA_IO_FILE_OUTPUT_H_
