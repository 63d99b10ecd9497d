// objects.json, the map objects of a replay (log-format.md, "Outputs of a
// replay"): its writer and its strict reader.
//
//   {"objects": [{id, class, symmetry, t, axis?, angles?, poses,
//                 observations, position_covariance?, rotation_covariance?,
//                 axis_covariance?, angle_variances?, covariance_source?,
//                 upgrade?}],
//    "noise"?: [...], "motion"?: {...}}   (as in summary.json)
//
// axis only for symmetric objects, angles only for discrete ones; poses are
// {"t": [x, y, z], "q": [qx, qy, qz, qw]}; the covariances (docs/replay.md)
// are 3x3 matrices as three rows, angle_variances numbers or null.
#ifndef SYMBA_IO_OBJECTS_JSON_H_
#define SYMBA_IO_OBJECTS_JSON_H_

#include <optional>
#include <string>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/common/status.h"

namespace symba {

std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects);
// The same with the noise the replay's backend used after the objects, as
// summary.json has it: per class "noise" and "motion" (docs/replay.md).
// The reader below ignores them.
std::string FormatObjectsJson(const std::vector<MapObjectEstimate>& objects,
                              const std::vector<ClassNoiseEstimate>& noise,
                              const std::optional<MotionNoiseReport>& motion);

// Reads objects.json strictly: errors "PATH:LINE: invalid JSON: ..." or
// "PATH: where: reason". axis_o is not in the file: a symmetric object's is
// its first pose's rotation applied backwards to the axis.
Status ReadObjectsJson(const std::string& path,
                       std::vector<MapObjectEstimate>* objects);

}  // namespace symba

#endif  // SYMBA_IO_OBJECTS_JSON_H_
