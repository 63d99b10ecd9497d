// A map that outlives a run (docs/map-format.md): what Backend::SaveMap
// gives and Backend::LoadMap starts a run from.
#ifndef SYMBA_BACKEND_SAVED_MAP_H_
#define SYMBA_BACKEND_SAVED_MAP_H_

#include <optional>
#include <string>
#include <vector>

#include "symba/backend/estimates.h"

namespace symba {

// What a class's detections were weighed with when the map was saved
// (docs/backend.md "Real detectors"; nullopt where the run had none yet),
// so that a run from the map weighs them so from its first keyframe:
struct SavedClassNoise {
  std::string class_name;
  // The estimate the edges of detections that give no sigma were built
  // with.
  std::optional<double> sigma_t{};  // m
  std::optional<double> sigma_r{};  // rad
  // The frame-to-frame part (sigma_I) that the class's detections weighed
  // by their hypotheses' scatter are held to.
  std::optional<double> white_sigma_t{};  // m
  std::optional<double> white_sigma_r{};  // rad
  // The factors the class's declared sigmas were multiplied by (>= 1; the
  // claims stood where nullopt).
  std::optional<double> claim_factor_t{};
  std::optional<double> claim_factor_r{};
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
