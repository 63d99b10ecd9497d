// The BOP challenge's results format, as the BOP toolkit reads it
// (docs/import.md): a CSV with the header line
//   scene_id,im_id,obj_id,score,R,t,time
// and one row per object pose: R nine space-separated numbers, row-major,
// t three in millimetres, R, t model-to-camera (p_c = R p_o + t, T_co),
// time the detector's run time in seconds (-1: not measured).
#ifndef SYMBA_EXPORT_BOP_RESULTS_CSV_H_
#define SYMBA_EXPORT_BOP_RESULTS_CSV_H_

#include <string>
#include <vector>

#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// One row of a BOP results CSV.
struct BopResult {
  int scene_id = 0;
  int im_id = 0;
  int obj_id = 0;
  double score = 1.0;
  Rigid3d T_co;        // model to camera, metres (written in mm)
  double time = -1.0;  // s; -1: not measured
};

// The header line and one line per row, each number in the shortest text
// that reads back as the same double (R = T_co.q as a matrix, t = 1000
// T_co.t). Rows are written in the given order.
std::string FormatBopResultsCsv(const std::vector<BopResult>& rows);

// FormatBopResultsCsv written to `path` atomically (WriteFileAtomically):
// on any error `path` is left as it was.
Status WriteBopResultsCsv(const std::string& path,
                          const std::vector<BopResult>& rows);

}  // namespace symba

#endif  // SYMBA_EXPORT_BOP_RESULTS_CSV_H_
