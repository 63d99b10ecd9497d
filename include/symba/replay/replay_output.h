// The outputs of a replay (log-format.md, "Outputs of a replay"), formatted
// in memory and written as one directory that appears complete or not at
// all (WriteDirectoryAtomically, symba/io/file_output.h).
//
//   trajectory.tum    timestamp tx ty tz qx qy qz qw  (T_wc, one per keyframe)
//   objects.json      {"objects": [{id, class, symmetry, t, axis?, angles?,
//                                   poses, observations}]}
//   associations.csv  keyframe,detection,object,symmetry
//   loop_closures.csv keyframe,other,moved_past,correction_m,correction_deg,
//                     keyframes_moved,initial_cost,final_cost,seconds,message
//   summary.json      counts, timings, solver statistics, options used
#ifndef SYMBA_REPLAY_REPLAY_OUTPUT_H_
#define SYMBA_REPLAY_REPLAY_OUTPUT_H_

#include <string>
#include <utility>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/io/objects_json.h"
#include "symba/io/tum_trajectory.h"
#include "symba/pose_graph/optimize_pose_graph.h"
#include "symba/replay/replay.h"

namespace symba {

std::string FormatAssociationsCsv(
    const std::vector<DetectionAssignment>& assignments);
// One row per loop closure (Backend::LoopClosures), header first.
std::string FormatLoopClosuresCsv(
    const std::vector<LoopClosureReport>& loop_closures);
std::string FormatReplaySummaryJson(const std::string& log_path,
                                    const ReplayOptions& options,
                                    const ReplayResult& result);

// The four files of a replay, named as above.
std::vector<std::pair<std::string, std::string>> ReplayOutputFiles(
    const std::string& log_path,
    const ReplayOptions& options,
    const ReplayResult& result);

// The outputs of replaying a g2o pose graph: trajectory.tum (vertex id as
// timestamp) and summary.json (initial and final cost, iterations, ...).
std::vector<std::pair<std::string, std::string>> PoseGraphOutputFiles(
    const std::string& graph_path,
    const PoseGraph& graph,
    const PoseGraphSolveSummary& summary);

}  // namespace symba

#endif  // SYMBA_REPLAY_REPLAY_OUTPUT_H_
