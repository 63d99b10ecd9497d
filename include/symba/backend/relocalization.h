// Relocalisation against a loaded map whose frame the keyframes are not
// given in (docs/relocalization.md): what Backend::LoadMap is told and
// what Backend::Relocalization() reports.
#ifndef SYMBA_BACKEND_RELOCALIZATION_H_
#define SYMBA_BACKEND_RELOCALIZATION_H_

#include <optional>
#include <string>
#include <vector>

#include "symba/backend/ids.h"
#include "symba/geometry/rigid3.h"
#include "symba/matching/constellation_match.h"

namespace symba {

struct RelocalizationOptions {
  // How the objects the run has mapped so far are matched with the map's.
  ConstellationMatchOptions match;
  // The search gives up after this many keyframes without a match and
  // the run goes on in its own frame without the map (bounds the memory
  // the search's keyframes hold).
  int max_keyframes = 1000;
};

struct RelocalizationReport {
  enum class State {
    kSearching,    // estimating in the run's own frame, matching each solve
    kRelocalized,  // in the map's frame since `keyframe`
    kGaveUp,       // max_keyframes without a match: the run's own frame
  };
  State state = State::kSearching;
  int keyframes = 0;         // keyframes the search estimated
  int attempts = 0;          // matches tried (one per window solve)
  std::string last_outcome;  // of the last attempt (ToString(Outcome))
  // Relocalised: the keyframe whose solve matched, the run's own frame in
  // the map's (T_map_run, applied to every keyframe pose given), and which
  // of the search's objects (by its ids) were which map objects.
  std::optional<KeyframeId> keyframe;
  Rigid3d T_map_run;
  std::vector<ObjectCorrespondence> correspondences;
  double position_rmse = 0.0;  // m, of the matched objects
  // The search's matching and, once matched, re-estimating its keyframes
  // in the map's frame.
  double seconds = 0.0;
};

const char* ToString(RelocalizationReport::State state);

}  // namespace symba

#endif  // SYMBA_BACKEND_RELOCALIZATION_H_
