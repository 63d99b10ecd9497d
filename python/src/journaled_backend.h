// A Backend together with what it was given, so that pickle can make it
// again (docs/python.md "Pickling"). The Backend holds its window,
// marginalisation priors, Ceres problem and map in forms that have no file
// format; what made them does: the options, the camera and class priors (a
// log header), the map it loaded, every keyframe it accepted (log lines)
// and every call that changed it, in order. The backend is deterministic,
// so making a new Backend and making the same calls gives the same state,
// bit for bit. The cost: the journal keeps every accepted keyframe
// (keep_journal = false turns that off, and pickling with it), and
// unpickling takes as long as the run took.
#ifndef SYMBA_PYTHON_SRC_JOURNALED_BACKEND_H_
#define SYMBA_PYTHON_SRC_JOURNALED_BACKEND_H_

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "symba/backend/backend.h"
#include "symba/backend/saved_map.h"
#include "symba/common/option_field.h"
#include "symba/common/status.h"

namespace symba::python {

// What a pickle holds.
struct BackendJournal {
  // Every option of the table (BackendOptionTable) by name.
  std::vector<std::pair<std::string, OptionValue>> options;
  // A log v1: the header (camera, class priors) and every accepted keyframe.
  std::string log;
  std::optional<std::string> map;  // the map file's text it loaded
  bool relocalize = false;
  // One letter per call, in order: k AddKeyframe (the log's next keyframe),
  // w OptimizeWindow, b OptimizeBatch, g GiveUpRelocalization.
  std::string calls;
};

class JournaledBackend {
 public:
  static Status Create(const BackendOptions& options,
                       const std::optional<PinholeIntrinsics>& intrinsics,
                       const std::map<std::string, ClassPrior>& class_priors,
                       bool keep_journal,
                       std::unique_ptr<JournaledBackend>* backend);
  // A new backend that made the journal's calls; errors start with
  // "cannot unpickle the Backend: ".
  static Status Restore(const BackendJournal& journal,
                        std::unique_ptr<JournaledBackend>* backend);

  Backend& backend() { return *backend_; }
  const Backend& backend() const { return *backend_; }
  bool keeps_journal() const { return keep_journal_; }

  // Backend's calls, recorded when they change the backend. A refused
  // keyframe or map changes nothing and is not recorded; a solve is
  // recorded whatever it returned (a failed solve may have moved blocks).
  Status AddKeyframe(const KeyframeInput& keyframe,
                     std::vector<DetectionAssignment>* assignments);
  Status OptimizeWindow(SolveReport* report);
  Status OptimizeBatch(SolveReport* report);
  // The map file's text (`name` stands for the file in errors).
  Status LoadMap(const std::string& text,
                 const std::string& name,
                 bool relocalize);
  void GiveUpRelocalization();

  // The journal so far; an error without keep_journal.
  Status Journal(BackendJournal* journal) const;

 private:
  JournaledBackend() = default;

  std::unique_ptr<Backend> backend_;
  bool keep_journal_ = true;
  BackendOptions options_;
  std::optional<PinholeIntrinsics> intrinsics_;
  std::map<std::string, ClassPrior> class_priors_;
  std::vector<KeyframeInput> keyframes_;
  std::optional<std::string> map_;
  bool relocalize_ = false;
  std::string calls_;
};

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_JOURNALED_BACKEND_H_
