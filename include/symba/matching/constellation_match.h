// Which objects of one constellation (a place seen from an unknown frame)
// are which objects of a map, and the rigid transform between the two
// frames: pairwise consistency maximisation over symmetry-aware invariants
// (docs/relocalization.md).
//
// A candidate pairs a local object with a map object of the same class and
// a compatible symmetry type (continuous with continuous; asymmetric and
// discrete with either, a discrete object of known order standing for its
// symmetry group). Axes are lines: their sign is arbitrary. Two candidates
// are consistent when every quantity a rigid transform keeps agrees within
// the gates: the distance between the two objects, the displacement in
// each object's own frame (modulo its symmetry) or along its axis, the
// angle between two axes and the relative rotation of two asymmetric
// objects. The maximal cliques of that graph are the candidate matches;
// each gets a transform (weighted Kabsch over positions, axes and
// rotations, a discrete object's pose chosen per correspondence) and keeps
// the correspondences that transform explains.
// The match is the one with the most such correspondences if it has at
// least min_support, determines the rotation, and no other transform is
// explained by as many (two places with the same arrangement of the same
// classes are ambiguous, not matched).
#ifndef SYMBA_MATCHING_CONSTELLATION_MATCH_H_
#define SYMBA_MATCHING_CONSTELLATION_MATCH_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/backend/ids.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct ConstellationMatchOptions {
  int min_support = 3;  // correspondences a match needs
  // Distances and positions agree within position_gate (m)
  // + relative_position_gate * distance + 3 sigma of the objects' position
  // covariances where they have them.
  double position_gate = 0.15;
  double relative_position_gate = 0.05;
  double angle_gate = 0.35;  // rad: rotations and axes
  // A different transform explained by at least (best support - this)
  // correspondences, and by min_support, makes the match ambiguous.
  int ambiguity_margin = 0;
  int max_candidates = 4000;  // the search refuses larger problems
      // More maximal cliques than this: no match (one left out could be as
  // well supported as the best found).
  int max_cliques = 10000;
  // Each class's symmetry order where known (a class prior's): a discrete
  // object then stands for its whole symmetry group, each of its poses
  // turned by 2 pi m / order about its axis. A discrete object of a class
  // without one (and not upgraded with an order) is matched by its
  // position and axis only.
  std::map<std::string, int> symmetry_orders;
};

struct ObjectCorrespondence {
  ObjectId local = 0;
  ObjectId map = 0;
};

struct ConstellationMatch {
  Rigid3d T_map_local;  // p_map = T_map_local * p_local
  std::vector<ObjectCorrespondence> correspondences;  // by local id
  double position_rmse = 0.0;  // m, of the matched objects after T
};

struct ConstellationMatchResult {
  enum class Outcome {
    kMatched,
    kTooFewCandidates,  // fewer than min_support candidate pairs
    kNoConsistentSet,   // no transform explains min_support of them
    kAmbiguous,         // another transform explains as many
    kTooLarge,          // more than max_candidates candidate pairs
    kTooManyCliques,    // more than max_cliques maximal cliques
  };
  Outcome outcome = Outcome::kTooFewCandidates;
  std::optional<ConstellationMatch> match;  // kMatched only
  int candidates = 0;
  int cliques = 0;
  int runner_up_support = 0;  // of the best different transform
};

const char* ToString(ConstellationMatchResult::Outcome outcome);

// `local` and `map` are confirmed objects (MapObjectEstimate as
// Backend::Objects() or a SavedMap gives them) in their own frames; their
// covariances widen the position gates where present.
ConstellationMatchResult MatchConstellation(
    const std::vector<MapObjectEstimate>& local,
    const std::vector<MapObjectEstimate>& map,
    const ConstellationMatchOptions& options = {});

}  // namespace symba

#endif  // SYMBA_MATCHING_CONSTELLATION_MATCH_H_
