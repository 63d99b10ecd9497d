// Replay: feed a log v1 through the backend, keyframe by keyframe, as a SLAM
// system would, and collect what a user reads back (docs/replay.md).
//
// Window mode optimises the window after every keyframe; batch mode adds all
// keyframes (association then uses the initial poses) and solves once.
#ifndef SYMBA_REPLAY_REPLAY_H_
#define SYMBA_REPLAY_REPLAY_H_

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "symba/backend/backend.h"
#include "symba/common/status.h"
#include "symba/io/log_format.h"

namespace symba {

enum class ReplayMode { kWindow, kBatch };
const char* ReplayModeName(ReplayMode mode);  // "window", "batch"
bool ParseReplayMode(const std::string& name, ReplayMode* mode);

struct ReplayOptions {
  ReplayMode mode = ReplayMode::kWindow;
  // Window mode: after the last keyframe, one batch solve over every factor
  // ever added (the smoothed trajectory and map; association stays as the
  // window made it).
  bool final_batch = false;
  BackendOptions backend;
  // Start from this saved map (Backend::LoadMap; docs/map-format.md).
  std::optional<SavedMap> map_in;
  // With map_in: the log's frame is not the map's, relocalise
  // (Backend::LoadMap; docs/relocalization.md).
  std::optional<RelocalizationOptions> relocalize;
  // Also give the map at the end (ReplayResult::map; Backend::SaveMap).
  bool save_map = false;
  // Called after each keyframe with the number replayed so far (optional).
  std::function<void(int)> progress;
};

struct ReplayResult {
  LogHeader header;
  std::vector<KeyframeEstimate> keyframes;
  std::vector<MapObjectEstimate> objects;
  std::vector<DetectionAssignment> assignments;
  BackendStatistics statistics;
  std::vector<ClassNoiseEstimate> noise;  // Backend::Noise() at the end
  MotionNoiseReport motion;               // Backend::MotionNoise() at the end
  SolveReport last_solve;                 // the final window or the batch solve
  // Why no object has a covariance (Backend::ObjectCovariances failed);
  // empty when they were computed.
  std::string covariance_note;
  double covariance_seconds = 0.0;  // wall time of ObjectCovariances
  // Backend::CovarianceNoise() after ObjectCovariances.
  std::vector<CovarianceNoiseGroup> covariance_noise;
  std::optional<SavedMap> map;  // with ReplayOptions::save_map
  // With ReplayOptions::relocalize: Backend::Relocalization() at the end.
  std::optional<RelocalizationReport> relocalization;
  std::vector<LoopClosureReport> loop_closures;  // Backend::LoopClosures()
  double seconds = 0.0;  // wall time of the whole replay
};

// Reads `log_path` and replays it. Errors name the file and line.
Status ReplayLog(const std::string& log_path,
                 const ReplayOptions& options,
                 ReplayResult* result);

}  // namespace symba

#endif  // SYMBA_REPLAY_REPLAY_H_
