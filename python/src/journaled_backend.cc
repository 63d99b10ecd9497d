#include "journaled_backend.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>

#include "symba/backend/backend_option_table.h"
#include "symba/io/map_file.h"

namespace symba::python {
namespace {

Status Unpickling(const std::string& message) {
  return Status::Error("cannot unpickle the Backend: " + message);
}

// ---------------------------------------------------------------------------
// Encoding: every number as its 8 bytes, little-endian (doubles bit for
// bit), a string as its length and bytes, an optional as a flag byte and
// the value. Exact, so the restored backend gets the same inputs.

class Encoder {
 public:
  explicit Encoder(std::string* out) : out_(out) {}
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out_->push_back(static_cast<char>(v >> 8 * i));
  }
  void I64(int64_t v) { U64(static_cast<uint64_t>(v)); }
  void F64(double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    U64(bits);
  }
  void Flag(bool v) { out_->push_back(v ? 1 : 0); }
  void Text(const std::string& s) {
    U64(s.size());
    out_->append(s);
  }
  void Pose(const Rigid3d& T) {
    for (int i = 0; i < 4; ++i) F64(T.q.coeffs()[i]);
    for (int i = 0; i < 3; ++i) F64(T.t[i]);
  }
  void OptionalF64(const std::optional<double>& v) {
    Flag(v.has_value());
    if (v) F64(*v);
  }

 private:
  std::string* out_;
};

class Decoder {
 public:
  explicit Decoder(const std::string& in) : in_(in) {}
  bool ok() const { return ok_; }
  bool AtEnd() const { return at_ == in_.size(); }
  uint64_t U64() {
    if (!Need(8)) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      v |= static_cast<uint64_t>(static_cast<unsigned char>(in_[at_++]))
           << 8 * i;
    }
    return v;
  }
  int64_t I64() { return static_cast<int64_t>(U64()); }
  double F64() {
    const uint64_t bits = U64();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  bool Flag() { return Need(1) && in_[at_++] != 0; }
  std::string Text() {
    const uint64_t size = U64();
    if (!Need(size)) return std::string();
    std::string s = in_.substr(at_, size);
    at_ += size;
    return s;
  }
  Rigid3d Pose() {
    Rigid3d T;
    for (int i = 0; i < 4; ++i) T.q.coeffs()[i] = F64();
    for (int i = 0; i < 3; ++i) T.t[i] = F64();
    return T;
  }
  std::optional<double> OptionalF64() {
    if (!Flag()) return std::nullopt;
    return F64();
  }
  // A count of items of at least `item_bytes` each (bounded by the data
  // left, so a corrupted count cannot allocate without limit).
  size_t Count(size_t item_bytes) {
    const uint64_t n = U64();
    if (ok_ && n > (in_.size() - at_) / item_bytes) ok_ = false;
    return ok_ ? static_cast<size_t>(n) : 0;
  }

 private:
  bool Need(uint64_t bytes) {
    if (ok_ && bytes <= in_.size() - at_) return true;
    ok_ = false;
    return false;
  }
  const std::string& in_;
  size_t at_ = 0;
  bool ok_ = true;
};

void EncodeSetup(const std::optional<PinholeIntrinsics>& intrinsics,
                 const std::map<std::string, ClassPrior>& class_priors,
                 Encoder* e) {
  e->Flag(intrinsics.has_value());
  if (intrinsics) {
    e->F64(intrinsics->fx);
    e->F64(intrinsics->fy);
    e->F64(intrinsics->cx);
    e->F64(intrinsics->cy);
  }
  e->U64(class_priors.size());
  for (const auto& [name, prior] : class_priors) {
    e->Text(name);
    e->I64(static_cast<int64_t>(prior.symmetry));
    e->I64(prior.order);
    for (int i = 0; i < 3; ++i) e->F64(prior.axis_o[i]);
  }
}

void DecodeSetup(Decoder* d,
                 std::optional<PinholeIntrinsics>* intrinsics,
                 std::map<std::string, ClassPrior>* class_priors) {
  if (d->Flag()) {
    PinholeIntrinsics k;
    k.fx = d->F64();
    k.fy = d->F64();
    k.cx = d->F64();
    k.cy = d->F64();
    *intrinsics = k;
  }
  const size_t priors = d->Count(8 + 8 + 8 + 24);
  for (size_t i = 0; i < priors && d->ok(); ++i) {
    const std::string name = d->Text();
    ClassPrior prior;
    prior.symmetry = static_cast<SymmetryType>(d->I64());
    prior.order = static_cast<int>(d->I64());
    for (int j = 0; j < 3; ++j) prior.axis_o[j] = d->F64();
    (*class_priors)[name] = prior;
  }
}

void EncodeLoopClosure(const LoopClosureInput& c, Encoder* e) {
  e->I64(c.keyframe);
  e->Pose(c.T);
  e->F64(c.sigma_t);
  e->F64(c.sigma_r);
}

LoopClosureInput DecodeLoopClosure(Decoder* d) {
  LoopClosureInput c;
  c.keyframe = d->I64();
  c.T = d->Pose();
  c.sigma_t = d->F64();
  c.sigma_r = d->F64();
  return c;
}

void EncodeKeyframe(const KeyframeInput& k, Encoder* e) {
  e->I64(k.id);
  e->F64(k.timestamp);
  e->Flag(k.T_wc.has_value());
  if (k.T_wc) e->Pose(*k.T_wc);
  e->Flag(k.odometry.has_value());
  if (k.odometry) {
    e->Pose(k.odometry->T_prev_cur);
    e->F64(k.odometry->sigma_t);
    e->F64(k.odometry->sigma_r);
  }
  e->U64(k.detections.size());
  for (const DetectionInput& det : k.detections) {
    e->Text(det.id);
    e->Text(det.class_name);
    e->U64(det.hypotheses.size());
    for (const PoseHypothesis& h : det.hypotheses) {
      e->Pose(h.T_co);
      e->F64(h.weight);
    }
    e->OptionalF64(det.sigma_t);
    e->OptionalF64(det.sigma_r);
    e->F64(det.score);
  }
  e->U64(k.points.size());
  for (const PointObservation& p : k.points) {
    e->I64(p.id);
    e->F64(p.uv.x());
    e->F64(p.uv.y());
    e->OptionalF64(p.depth);
  }
  e->U64(k.loop_closures.size());
  for (const LoopClosureInput& c : k.loop_closures) EncodeLoopClosure(c, e);
}

void DecodeKeyframe(Decoder* d, KeyframeInput* k) {
  *k = KeyframeInput();
  k->id = d->I64();
  k->timestamp = d->F64();
  if (d->Flag()) k->T_wc = d->Pose();
  if (d->Flag()) {
    Odometry odometry;
    odometry.T_prev_cur = d->Pose();
    odometry.sigma_t = d->F64();
    odometry.sigma_r = d->F64();
    k->odometry = odometry;
  }
  const size_t detections = d->Count(8 + 8 + 8 + 1 + 1 + 8);
  for (size_t i = 0; i < detections && d->ok(); ++i) {
    DetectionInput det;
    det.id = d->Text();
    det.class_name = d->Text();
    const size_t hypotheses = d->Count(8 * 8);
    for (size_t j = 0; j < hypotheses && d->ok(); ++j) {
      PoseHypothesis h;
      h.T_co = d->Pose();
      h.weight = d->F64();
      det.hypotheses.push_back(h);
    }
    det.sigma_t = d->OptionalF64();
    det.sigma_r = d->OptionalF64();
    det.score = d->F64();
    k->detections.push_back(std::move(det));
  }
  const size_t points = d->Count(8 + 16 + 1);
  for (size_t i = 0; i < points && d->ok(); ++i) {
    PointObservation p;
    p.id = d->I64();
    p.uv.x() = d->F64();
    p.uv.y() = d->F64();
    p.depth = d->OptionalF64();
    k->points.push_back(p);
  }
  const size_t closures = d->Count(8 + 7 * 8 + 16);
  for (size_t i = 0; i < closures && d->ok(); ++i) {
    k->loop_closures.push_back(DecodeLoopClosure(d));
  }
}

// ---------------------------------------------------------------------------
// Calls.

constexpr char kAddKeyframe = 'k';
constexpr char kOptimizeWindow = 'w';
constexpr char kOptimizeBatch = 'b';
constexpr char kObjectCovariances = 'c';
constexpr char kSaveMap = 's';
constexpr char kLoadMap = 'm';
constexpr char kLoadMapRelocalize = 'r';
constexpr char kGiveUpRelocalization = 'g';
constexpr char kAddLoopClosure = 'l';

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

// One recorded call made again. Calls recorded whatever they returned are
// made whatever they return now (the same).
Status MakeCall(char call,
                const BackendJournal& journal,
                Decoder* inputs,
                size_t* next_map,
                JournaledBackend* backend) {
  switch (call) {
    case kAddKeyframe: {
      KeyframeInput keyframe;
      DecodeKeyframe(inputs, &keyframe);
      if (!inputs->ok()) return Unpickling("truncated inputs");
      const Status status = backend->AddKeyframe(keyframe, nullptr);
      return status.ok() ? status : Unpickling(status.message());
    }
    case kOptimizeWindow:
      static_cast<void>(backend->OptimizeWindow(nullptr));
      return Status::Ok();
    case kOptimizeBatch:
      static_cast<void>(backend->OptimizeBatch(nullptr));
      return Status::Ok();
    case kObjectCovariances: {
      std::vector<MapObjectCovariance> covariances;
      static_cast<void>(backend->ObjectCovariances(&covariances));
      return Status::Ok();
    }
    case kSaveMap: {
      SavedMap map;
      static_cast<void>(backend->SaveMap(&map));
      return Status::Ok();
    }
    case kLoadMap:
    case kLoadMapRelocalize: {
      if (*next_map >= journal.maps.size()) return Unpickling("too few maps");
      const Status status = backend->LoadMap(
          journal.maps[(*next_map)++], "<pickle>", call == kLoadMapRelocalize);
      return status.ok() ? status : Unpickling(status.message());
    }
    case kGiveUpRelocalization:
      backend->GiveUpRelocalization();
      return Status::Ok();
    case kAddLoopClosure: {
      const KeyframeId keyframe = inputs->I64();
      const LoopClosureInput closure = DecodeLoopClosure(inputs);
      if (!inputs->ok()) return Unpickling("truncated inputs");
      const Status status = backend->AddLoopClosure(keyframe, closure, nullptr);
      return status.ok() ? status : Unpickling(status.message());
    }
    default:
      return Unpickling(std::string("unknown call '") + call + "'");
  }
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
  if (keep_journal) {
    Encoder encoder(&made->inputs_);
    EncodeSetup(intrinsics, class_priors, &encoder);
  }
  *backend = std::move(made);
  return Status::Ok();
}

Status JournaledBackend::Restore(const BackendJournal& journal,
                                 std::unique_ptr<JournaledBackend>* backend) {
  BackendOptions options;
  Status status = OptionsFromJournal(journal, &options);
  if (!status.ok()) return status;
  Decoder inputs(journal.inputs);
  std::optional<PinholeIntrinsics> intrinsics;
  std::map<std::string, ClassPrior> class_priors;
  DecodeSetup(&inputs, &intrinsics, &class_priors);
  if (!inputs.ok()) return Unpickling("truncated inputs");
  std::unique_ptr<JournaledBackend> made;
  status = Create(options, intrinsics, class_priors, true, &made);
  if (!status.ok()) return Unpickling(status.message());
  size_t next_map = 0;
  for (const char call : journal.calls) {
    status = MakeCall(call, journal, &inputs, &next_map, made.get());
    if (!status.ok()) return status;
  }
  if (!inputs.AtEnd() || next_map != journal.maps.size()) {
    return Unpickling("inputs or maps that no call used");
  }
  *backend = std::move(made);
  return Status::Ok();
}

void JournaledBackend::Record(char call) {
  if (keep_journal_) calls_ += call;
}

Status JournaledBackend::AddKeyframe(
    const KeyframeInput& keyframe,
    std::vector<DetectionAssignment>* assignments) {
  const Status status = backend_->AddKeyframe(keyframe, assignments);
  if (status.ok() && keep_journal_) {
    Encoder encoder(&inputs_);
    EncodeKeyframe(keyframe, &encoder);
    Record(kAddKeyframe);
  }
  return status;
}

Status JournaledBackend::OptimizeWindow(SolveReport* report) {
  Record(kOptimizeWindow);
  return backend_->OptimizeWindow(report);
}

Status JournaledBackend::OptimizeBatch(SolveReport* report) {
  Record(kOptimizeBatch);
  return backend_->OptimizeBatch(report);
}

Status JournaledBackend::ObjectCovariances(
    std::vector<MapObjectCovariance>* covariances) {
  Record(kObjectCovariances);
  return backend_->ObjectCovariances(covariances);
}

Status JournaledBackend::SaveMap(SavedMap* map) {
  Record(kSaveMap);
  return backend_->SaveMap(map);
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
    maps_.push_back(text);
    Record(relocalize ? kLoadMapRelocalize : kLoadMap);
  }
  return status;
}

Status JournaledBackend::AddLoopClosure(KeyframeId keyframe,
                                        const LoopClosureInput& closure,
                                        LoopClosureReport* report) {
  const Status status = backend_->AddLoopClosure(keyframe, closure, report);
  if (status.ok() && keep_journal_) {
    Encoder encoder(&inputs_);
    encoder.I64(keyframe);
    EncodeLoopClosure(closure, &encoder);
    Record(kAddLoopClosure);
  }
  return status;
}

void JournaledBackend::GiveUpRelocalization() {
  Record(kGiveUpRelocalization);
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
  j.inputs = inputs_;
  j.maps = maps_;
  j.calls = calls_;
  *journal = std::move(j);
  return Status::Ok();
}

}  // namespace symba::python
