// Internal: one map object as symba's files hold it (objects.json and the
// map file, docs/map-format.md): its writer and its strict reader.
//
//   {id, class, symmetry, t, axis?, angles?, poses, observations,
//    position_covariance?, rotation_covariance?, axis_covariance?,
//    angle_variances?, covariance_source?, upgrade?}
//
// axis only for symmetric objects, angles only for discrete ones (one pose
// per angle; one pose otherwise); poses are {"t": [x, y, z], "q": [qx, qy,
// qz, qw]}; covariances are 3x3 matrices as three rows written with 6
// significant digits, angle_variances numbers or null.
#ifndef SYMBA_SRC_IO_OBJECT_RECORD_H_
#define SYMBA_SRC_IO_OBJECT_RECORD_H_

#include "io/json_tree_reader.h"
#include "io/json_writer.h"
#include "symba/backend/estimates.h"
#include "symba/common/status.h"

namespace symba {
namespace io_internal {

void WriteObjectRecord(const MapObjectEstimate& object, JsonWriter* json);

// A pose as the records hold it: {"t": [x, y, z], "q": [qx, qy, qz, qw]}.
void WritePose(const Rigid3d& T, JsonWriter* json);

// Reads the record at `object` (an entry of an "objects" array at `where`).
// axis_o is derived from the first pose and the axis (symmetric objects).
Status ReadObjectRecord(const JsonTreeReader& r,
                        JsonTree::Index object,
                        const JsonPath& where,
                        MapObjectEstimate* result);

}  // namespace io_internal
}  // namespace symba

#endif  // SYMBA_SRC_IO_OBJECT_RECORD_H_
