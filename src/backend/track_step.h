// One step of an object's track (object_track.h), kept while the object is
// tentative and, for confirmed objects, as the class's reference.
#ifndef SYMBA_SRC_BACKEND_TRACK_STEP_H_
#define SYMBA_SRC_BACKEND_TRACK_STEP_H_

#include <cstddef>

namespace symba::internal {

// Two detections of one object in keyframes j < k: the change of their
// positions where the front end alone puts them (m), and the motion
// variance the camera factors apply to keyframes j + 1 .. k at the later
// detection's distance (m^2; PlaceGrowth).
struct TrackStep {
  double change = 0.0;
  double growth = 0.0;
};

// The steps a tentative object keeps (the latest ones).
inline constexpr std::size_t kMaxTrackSteps = 32;

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_TRACK_STEP_H_
