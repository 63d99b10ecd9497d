#include "journaled_backend.h"

#include <memory>
#include <sstream>
#include <utility>

#include "symba/backend/backend_option_table.h"
#include "symba/io/log_format.h"
#include "symba/io/map_file.h"

namespace symba::python {
namespace {

constexpr char kAddKeyframe = 'k';
constexpr char kOptimizeWindow = 'w';
constexpr char kOptimizeBatch = 'b';
constexpr char kGiveUpRelocalization = 'g';

Status Unpickling(const std::string& message) {
  return Status::Error("cannot unpickle the Backend: " + message);
}

Status OptionsFromJournal(const BackendJournal& journal,
                          BackendOptions* options) {
  const OptionTable<BackendOptions>& table = BackendOptionTable();
  for (const auto& [name, value] : journal.options) {
    const OptionField<BackendOptions>* field = FindOption(table, name);
    if (field == nullptr) return Unpickling("unknown option " + name);
    if (!field->set(value, options)) {
      return Unpickling("option " + name + " has a value of the wrong type");
    }
  }
  return Status::Ok();
}

// Makes the journal's calls on `backend`, reading the keyframes from `log`.
Status Replay(const BackendJournal& journal,
              LogReader* log,
              JournaledBackend* backend) {
  KeyframeInput keyframe;
  for (const char call : journal.calls) {
    switch (call) {
      case kAddKeyframe: {
        bool end = false;
        Status status = log->Next(&keyframe, &end);
        if (status.ok() && end) status = Status::Error("too few keyframes");
        if (status.ok()) status = backend->AddKeyframe(keyframe, nullptr);
        if (!status.ok()) return Unpickling(status.message());
        break;
      }
      // A solve was recorded whatever it returned; it returns the same now.
      case kOptimizeWindow:
        static_cast<void>(backend->OptimizeWindow(nullptr));
        break;
      case kOptimizeBatch:
        static_cast<void>(backend->OptimizeBatch(nullptr));
        break;
      case kGiveUpRelocalization:
        backend->GiveUpRelocalization();
        break;
      default:
        return Unpickling(std::string("unknown call '") + call + "'");
    }
  }
  return Status::Ok();
}

}  // namespace

Status JournaledBackend::Create(
    const BackendOptions& options,
    const std::optional<PinholeIntrinsics>& intrinsics,
    const std::map<std::string, ClassPrior>& class_priors,
    bool keep_journal,
    std::unique_ptr<JournaledBackend>* backend) {
  std::unique_ptr<JournaledBackend> made(new JournaledBackend());
  Status status =
      Backend::Create(options, intrinsics, class_priors, &made->backend_);
  if (!status.ok()) return status;
  made->keep_journal_ = keep_journal;
  made->options_ = options;
  made->intrinsics_ = intrinsics;
  made->class_priors_ = class_priors;
  *backend = std::move(made);
  return Status::Ok();
}

Status JournaledBackend::Restore(const BackendJournal& journal,
                                 std::unique_ptr<JournaledBackend>* backend) {
  BackendOptions options;
  Status status = OptionsFromJournal(journal, &options);
  if (!status.ok()) return status;
  std::unique_ptr<LogReader> log;
  status = LogReader::OpenStream(
      std::make_unique<std::istringstream>(journal.log), "<pickle>", &log);
  if (!status.ok()) return Unpickling(status.message());
  std::unique_ptr<JournaledBackend> made;
  status = Create(options,
                  log->header().camera,
                  log->header().classes,
                  /*keep_journal=*/true,
                  &made);
  if (!status.ok()) return Unpickling(status.message());
  if (journal.map) {
    status = made->LoadMap(*journal.map, "<pickle>", journal.relocalize);
    if (!status.ok()) return Unpickling(status.message());
  }
  status = Replay(journal, log.get(), made.get());
  if (!status.ok()) return status;
  *backend = std::move(made);
  return Status::Ok();
}

Status JournaledBackend::AddKeyframe(
    const KeyframeInput& keyframe,
    std::vector<DetectionAssignment>* assignments) {
  const Status status = backend_->AddKeyframe(keyframe, assignments);
  if (status.ok() && keep_journal_) {
    keyframes_.push_back(keyframe);
    calls_ += kAddKeyframe;
  }
  return status;
}

Status JournaledBackend::OptimizeWindow(SolveReport* report) {
  if (keep_journal_) calls_ += kOptimizeWindow;
  return backend_->OptimizeWindow(report);
}

Status JournaledBackend::OptimizeBatch(SolveReport* report) {
  if (keep_journal_) calls_ += kOptimizeBatch;
  return backend_->OptimizeBatch(report);
}

Status JournaledBackend::LoadMap(const std::string& text,
                                 const std::string& name,
                                 bool relocalize) {
  SavedMap map;
  Status status = ParseMapFile(text, name, &map);
  if (!status.ok()) return status;
  std::optional<RelocalizationOptions> options;
  if (relocalize) options.emplace();
  status = backend_->LoadMap(map, options);
  if (status.ok() && keep_journal_) {
    map_ = text;
    relocalize_ = relocalize;
  }
  return status;
}

void JournaledBackend::GiveUpRelocalization() {
  if (keep_journal_) calls_ += kGiveUpRelocalization;
  backend_->GiveUpRelocalization();
}

Status JournaledBackend::Journal(BackendJournal* journal) const {
  if (!keep_journal_) {
    return Status::Error(
        "this Backend was made with keep_journal=False and cannot be "
        "pickled");
  }
  BackendJournal j;
  for (const OptionField<BackendOptions>& field : BackendOptionTable()) {
    j.options.emplace_back(field.name, field.get(options_));
  }
  LogHeader header;
  header.camera = intrinsics_;
  header.classes = class_priors_;
  std::ostringstream log;
  std::unique_ptr<LogWriter> writer;
  Status status = LogWriter::OpenStream(&log, "<pickle>", header, &writer);
  for (size_t i = 0; status.ok() && i < keyframes_.size(); ++i) {
    status = writer->Write(keyframes_[i]);
  }
  if (status.ok()) status = writer->Close();
  if (!status.ok()) {
    return Status::Error("cannot pickle the Backend: " + status.message());
  }
  j.log = log.str();
  j.map = map_;
  j.relocalize = relocalize_;
  j.calls = calls_;
  *journal = std::move(j);
  return Status::Ok();
}

}  // namespace symba::python
