// A Backend together with what it was given, so that pickle can make it
// again (docs/python.md "Pickling"). The Backend holds its window,
// marginalisation priors, Ceres problem and map in forms that have no file
// format; what made them does: the options, the camera and class priors,
// every keyframe it accepted, every map it loaded and every other call
// that changed it, in order. The backend is deterministic, so a new Backend
// that makes the same calls with the same inputs, bit for bit, has the same
// state. The cost: the journal keeps every accepted keyframe (keep_journal
// = false turns that off, and pickling with it), and unpickling takes as
// long as the run took.
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
  // The camera, the class priors and every accepted keyframe, each number
  // as its 8 bytes (journaled_backend.cc, "Encoding"): exact, unlike a
  // text that a reader would normalise.
  std::string inputs;
  std::vector<std::string> maps;  // the map files' texts, in load order
  // One letter per call, in order: k AddKeyframe (the next keyframe of
  // `inputs`), w OptimizeWindow, b OptimizeBatch, c ObjectCovariances,
  // s SaveMap, m / r LoadMap of the next map (r: relocalise),
  // g GiveUpRelocalization, l AddLoopClosure (its keyframe id and closure
  // follow in `inputs`).
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

  const Backend& backend() const { return *backend_; }
  bool keeps_journal() const { return keep_journal_; }

  // The Backend's calls that can change it (the const ones go to
  // backend()). A refused keyframe or map changes nothing and is not
  // recorded; every other call is, whatever it returned (a failed solve
  // may have moved blocks; covariances and saving a map set the solver's
  // problem up, which orders its residuals).
  Status AddKeyframe(const KeyframeInput& keyframe,
                     std::vector<DetectionAssignment>* assignments);
  Status OptimizeWindow(SolveReport* report);
  Status OptimizeBatch(SolveReport* report);
  Status ObjectCovariances(std::vector<MapObjectCovariance>* covariances);
  Status SaveMap(SavedMap* map);
  // The map file's text (`name` stands for the file in errors).
  Status LoadMap(const std::string& text,
                 const std::string& name,
                 bool relocalize);
  void GiveUpRelocalization();
  Status AddLoopClosure(KeyframeId keyframe,
                        const LoopClosureInput& closure,
                        LoopClosureReport* report);

  // The journal so far; an error without keep_journal.
  Status Journal(BackendJournal* journal) const;

 private:
  JournaledBackend() = default;
  void Record(char call);

  std::unique_ptr<Backend> backend_;
  bool keep_journal_ = true;
  BackendOptions options_;
  std::string inputs_;  // encoded: camera, priors, then keyframes
  std::vector<std::string> maps_;
  std::string calls_;
};

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_JOURNALED_BACKEND_H_
