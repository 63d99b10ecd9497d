// A map that outlives a run (docs/map-format.md): what Backend::SaveMap
// gives and Backend::LoadMap starts a run from.
#ifndef SYMBA_BACKEND_SAVED_MAP_H_
#define SYMBA_BACKEND_SAVED_MAP_H_

#include <optional>
#include <string>
#include <vector>

#include "symba/backend/estimates.h"

namespace symba {

// What a class's detections that give no sigma were weighed with when the
// map was saved (the estimate their edges were built with; nullopt where
// the run had none yet).
struct SavedClassNoise {
  std::string class_name;
  std::optional<double> sigma_t;  // m
  std::optional<double> sigma_r;  // rad
};

// Map object ids are below this (Backend::LoadMap gives a loaded object
// the index of its id, so they must stay dense enough to hold in memory).
inline constexpr int kMaxMapObjectId = 100000;

struct SavedMap {
  // The confirmed map objects, each with its covariance where it had one:
  // a loaded object keeps what it knew as a prior of that covariance.
  std::vector<MapObjectEstimate> objects;
  // Sorted by class name, one entry per class.
  std::vector<SavedClassNoise> noise;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_SAVED_MAP_H_
