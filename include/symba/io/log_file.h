// Writing a whole log v1 file at once, atomically: what a converter that
// builds a log in memory (symba import) needs so that an error never leaves
// a partial file behind.
#ifndef SYMBA_IO_LOG_FILE_H_
#define SYMBA_IO_LOG_FILE_H_

#include <functional>
#include <string>
#include <vector>

#include "symba/backend/keyframe_input.h"
#include "symba/common/status.h"
#include "symba/io/log_format.h"

namespace symba {

// Writes the log with LogWriter into a temporary sibling "PATH.tmp-<pid>",
// then renames it onto `path`; on any error the temporary file is removed
// and `path` is left as it was (absent or the old file). Errors name `path`
// ("PATH: cannot open for writing (reason)", LogWriter's
// "PATH: keyframe ID: ..." refusals, "PATH: cannot rename into place").
Status WriteLogAtomically(const std::string& path,
                          const LogHeader& header,
                          const std::vector<KeyframeInput>& keyframes);

// The same with the keyframes made one at a time, so a large log need not
// be held in memory: `next` returns the next keyframe (valid until the next
// call), or null after the last.
Status WriteLogAtomically(const std::string& path,
                          const LogHeader& header,
                          const std::function<const KeyframeInput*()>& next);

}  // namespace symba

#endif  // SYMBA_IO_LOG_FILE_H_
