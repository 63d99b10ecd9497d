// The refined object poses of a replay written back as BOP results
// (`symba replay --bop-out`, docs/import.md "Export"), so the BOP toolkit
// can score symba's map against the raw detector.
//
// One row per detection that the replay assigned to a map object, in the
// log's order (keyframe by keyframe, detection by detection):
//   scene_id  options.scene_id, else the log header's bop.scene_id
//   im_id     the keyframe id
//   obj_id    the header's bop.obj_ids of the detection's class, else N for
//             a class named obj_N (digits only)
//   score     the detection's score
//   R, t      T_co = T_cw * T_wo: the map object's refined pose T_wo seen
//             from the keyframe's refined camera (T_cw = T_wc^-1); for a
//             symmetric object the one of its symmetric poses nearest in
//             rotation to the detection's best (highest-weight) hypothesis
//             (ClosestSymmetricPose), so the row stays comparable with the
//             detector's
//   time      -1
#ifndef SYMBA_EXPORT_REFINED_BOP_RESULTS_H_
#define SYMBA_EXPORT_REFINED_BOP_RESULTS_H_

#include <optional>
#include <string>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/backend/keyframe_input.h"
#include "symba/common/status.h"
#include "symba/export/bop_results_csv.h"
#include "symba/geometry/rigid3.h"
#include "symba/replay/replay.h"

namespace symba {

struct RefinedBopResultsOptions {
  // The BOP scene id; when set it is used instead of the header's
  // bop.scene_id (and needed when the header has no "bop" key).
  std::optional<int> scene_id;
};

// The map object's pose T_wo among its symmetric poses whose T_cw * T_wo is
// nearest in rotation (geodesic angle) to `T_co_reference`:
//   asymmetric  its one pose
//   discrete    the pose of one of its angles (MapObjectEstimate::poses),
//               each also turned about axis_o by 2 pi m / order, m < order,
//               when `order` (the class prior's) is >= 2: with the prior a
//               single-pose detector's flips fold onto one angle
//   continuous  its representative pose turned about the world axis through
//               t_wo by the angle that fits best
// The translation is t_wo in every case (with no pose at all, the identity
// rotation).
Rigid3d ClosestSymmetricPose(const MapObjectEstimate& object,
                             const Rigid3d& T_cw,
                             const Rigid3d& T_co_reference,
                             int order = 0);

// The rows for the detections of `keyframes` (the replayed log's keyframes,
// for their detections' scores and hypotheses) as described above.
// Errors: no scene id ("no BOP scene id: ..."), a negative scene id, a
// keyframe id that is no im_id ("keyframe -1: ..."), a class without an
// obj_id ("class \"table\": no BOP obj_id: ..."), a keyframe the replay
// does not have; `rows` is then unspecified.
Status RefinedBopResults(const ReplayResult& replay,
                         const std::vector<KeyframeInput>& keyframes,
                         const RefinedBopResultsOptions& options,
                         std::vector<BopResult>* rows);

// The same, reading the keyframes from the replayed log `log_path` one at a
// time (LogReader's errors name FILE:LINE).
Status RefinedBopResultsFromLog(const std::string& log_path,
                                const ReplayResult& replay,
                                const RefinedBopResultsOptions& options,
                                std::vector<BopResult>* rows);

}  // namespace symba

#endif  // SYMBA_EXPORT_REFINED_BOP_RESULTS_H_
