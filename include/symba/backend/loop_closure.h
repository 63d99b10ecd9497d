// What one loop closure did (docs/loop-closure.md): the two keyframes it
// relates, whether it moved the past, and how far; for a loop symba found
// from the objects, which map objects it recognised and merged.
#ifndef SYMBA_BACKEND_LOOP_CLOSURE_H_
#define SYMBA_BACKEND_LOOP_CLOSURE_H_

#include <string>
#include <vector>

#include "symba/backend/ids.h"

namespace symba {

// A map object a revisit mapped again (`duplicate`) and the object it is
// (`map`); merged: the duplicate's detections now belong to `map` and the
// duplicate is gone (false: their symmetry types differ, both stay).
struct LoopObjectPair {
  ObjectId map = 0;
  ObjectId duplicate = 0;
  bool merged = false;
};

struct LoopClosureReport {
  // The keyframe it was added with (KeyframeInput::loop_closures: the one
  // that carried it; AddLoopClosure: its `keyframe` argument) and the one
  // it relates it to.
  KeyframeId keyframe = 0;
  KeyframeId other = 0;
  // Not closed yet: one of its keyframes waits for a solve (nothing below
  // is set but the message).
  bool waiting = false;
  // The other keyframe had left the window: the keyframe graph was
  // optimised and every keyframe, object and point moved with it.
  bool moved_past = false;
  // How far the correction moved `keyframe` (m, degrees; 0 without one).
  double correction_m = 0.0;
  double correction_deg = 0.0;
  int keyframes_moved =
      0;  // keyframes that moved by more than 1 mm or 0.01 deg
  // The keyframe graph's cost (1/2 sum r^T r) before and after.
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;  // the whole event
  // Empty unless the keyframe graph's solve failed: the past then stays
  // where it was and the closure is left out. A waiting closure's report
  // says "waits for the next solve".
  std::string message;
  // Found by symba from the objects (docs/loop-closure.md "Loops from the
  // objects"), not given by the host; `objects` are the recognised pairs.
  bool from_objects = false;
  std::vector<LoopObjectPair> objects;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_LOOP_CLOSURE_H_
