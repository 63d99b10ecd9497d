#include "symba/replay/replay.h"

#include <chrono>
#include <memory>
#include <set>
#include <string>

namespace symba {

const char* ReplayModeName(ReplayMode mode) {
  return mode == ReplayMode::kBatch ? "batch" : "window";
}

bool ParseReplayMode(const std::string& name, ReplayMode* mode) {
  if (name == "window") {
    *mode = ReplayMode::kWindow;
  } else if (name == "batch") {
    *mode = ReplayMode::kBatch;
  } else {
    return false;
  }
  return true;
}

namespace {

// Each map object's covariance, where the backend has one; a problem whose
// covariance Ceres cannot compute leaves them all out, with the reason.
void AttachCovariances(Backend* backend, ReplayResult* replay) {
  std::vector<MapObjectCovariance> covariances;
  const auto start = std::chrono::steady_clock::now();
  const Status status = backend->ObjectCovariances(&covariances);
  replay->covariance_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  replay->covariance_noise = backend->CovarianceNoise();
  if (!status.ok()) {
    replay->covariance_note = status.message();
    return;
  }
  size_t c = 0;
  for (MapObjectEstimate& object : replay->objects) {
    while (c < covariances.size() && covariances[c].id < object.id) ++c;
    if (c < covariances.size() && covariances[c].id == object.id) {
      object.covariance = covariances[c];
    }
  }
}

}  // namespace

Status ReplayLog(const std::string& log_path,
                 const ReplayOptions& options,
                 ReplayResult* result) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::Open(log_path, &reader);
  if (!status.ok()) return status;
  // A final batch solve needs every factor, also those of keyframes that
  // left the window.
  const bool batch = options.mode == ReplayMode::kBatch || options.final_batch;
  BackendOptions backend_options = options.backend;
  backend_options.keep_history = backend_options.keep_history || batch;
  std::unique_ptr<Backend> backend;
  status = Backend::Create(backend_options,
                           reader->header().camera,
                           reader->header().classes,
                           &backend);
  if (!status.ok()) return Status::Error("options: " + status.message());
  if (options.relocalize && !options.map_in) {
    return Status::Error("options: relocalisation needs a map to start from");
  }
  if (options.relocalize && options.mode == ReplayMode::kBatch) {
    return Status::Error(
        "options: relocalisation matches after window solves; batch mode "
        "has none");
  }
  if (options.map_in) {
    status = backend->LoadMap(*options.map_in, options.relocalize);
    if (!status.ok()) return Status::Error("map: " + status.message());
  }

  ReplayResult replay;
  replay.header = reader->header();
  int count = 0;
  KeyframeInput keyframe;
  for (;;) {
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (!status.ok()) return status;
    if (end) break;
    const std::string where = log_path + ":" + std::to_string(reader->line());
    status = backend->AddKeyframe(keyframe);
    if (!status.ok()) return Status::Error(where + ": " + status.message());
    if (options.mode == ReplayMode::kWindow) {
      status = backend->OptimizeWindow(&replay.last_solve);
      if (!status.ok()) return Status::Error(where + ": " + status.message());
    }
    ++count;
    if (options.progress) options.progress(count);
  }
  // Still searching at the end: the run's own frame for everything.
  backend->GiveUpRelocalization();
  if (batch && count > 0) {
    status = backend->OptimizeBatch(&replay.last_solve);
    if (!status.ok()) return Status::Error(log_path + ": " + status.message());
  }
  replay.keyframes = backend->Keyframes();
  replay.objects = backend->Objects();
  AttachCovariances(backend.get(), &replay);
  replay.assignments = backend->Assignments();
  // A detection of an object still tentative at the end is in no map
  // object, like one of a dropped object.
  std::set<int> in_map;
  for (const MapObjectEstimate& object : replay.objects)
    in_map.insert(object.id);
  for (DetectionAssignment& a : replay.assignments) {
    if (in_map.count(a.object) == 0) a.object = -1;
  }
  replay.statistics = backend->Statistics();
  replay.relocalization = backend->Relocalization();
  replay.loop_closures = backend->LoopClosures();
  replay.noise = backend->Noise();
  replay.motion = backend->MotionNoise();
  if (options.save_map) {
    replay.map.emplace();
    status = backend->SaveMap(&*replay.map);
    if (!status.ok()) return status;
  }
  replay.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  *result = std::move(replay);
  return Status::Ok();
}

}  // namespace symba
