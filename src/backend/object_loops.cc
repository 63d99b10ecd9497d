// Backend::Impl: loops found from the objects (docs/loop-closure.md "Loops
// from the objects"). When the camera comes back to a place after its pose
// drifted, the objects there are too far from the map's to be associated
// and are mapped again. Once such duplicates are confirmed, their
// constellation is matched against the objects the camera has not seen
// since before them and a loaded map's objects it has not seen yet
// (MatchConstellation: symmetry-aware, refusing an ambiguous match); a
// match closes a loop to the keyframe that last saw the place (for a loaded
// map's unseen objects: the last keyframe tied to the map), which moves the
// past (loop_closure.cc), and each duplicate is then merged into the object
// it is.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "backend/backend_impl.h"
#include "symba/matching/constellation_match.h"

namespace symba {

Backend::Impl::LoopCandidates Backend::Impl::ObjectLoopCandidates() const {
  const internal::ObjectList& objects = map_.objects();
  const int n = static_cast<int>(trajectory_.keyframes().size());
  const int recent_begin = std::max(0, n - options_.loop_recent_keyframes);
  LoopCandidates candidates;
  int first_recent = n;
  for (const auto& object : objects) {
    if (!internal::IsMapped(*object) ||
        object->created_keyframe < recent_begin ||
        unmerged_duplicates_.count(object->id) > 0) {
      continue;
    }
    candidates.recent.push_back(EstimateOf(*object));
    first_recent = std::min(first_recent, object->created_keyframe);
  }
  if (static_cast<int>(candidates.recent.size()) < options_.loop_min_objects) {
    return candidates;
  }
  // Last seen before the recent objects were first seen, and before the
  // window: their observations all precede the duplicates', and only the
  // keyframe graph can move the keyframes that saw them. A loaded map's
  // objects this run has not seen are there too: the run, placed in the
  // map's frame, may come back to them off by its drift since.
  const int seen_before = std::min(first_recent, n - options_.window_size);
  for (const auto& object : objects) {
    if ((internal::IsMapped(*object) && object->last_keyframe >= 0 &&
         object->last_keyframe < seen_before) ||
        internal::IsLoadedUnseen(*object)) {
      candidates.earlier.push_back(EstimateOf(*object));
    }
  }
  return candidates;
}

int Backend::Impl::LastKeyframeOnLoadedObjects() const {
  int last = -1;
  for (const auto& object : map_.objects()) {
    if (internal::IsLoaded(*object) &&
        object->status == internal::ObjectStatus::kConfirmed) {
      last = std::max(last, object->last_keyframe);
    }
  }
  return last;
}

bool Backend::Impl::WithinPossibleDrift(int earlier,
                                        int later,
                                        const Rigid3d& correction) const {
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const Eigen::Vector3d t_later = keyframes[later]->T_wc().t;
  // The drift if every step erred by its stated sigma the same way (a
  // front end's drift is a bias more than a random walk): a rotation error
  // at step i moves the later keyframe by its lever arm too.
  double bound_t = 0.0;
  double bound_r = 0.0;
  for (int i = earlier + 1; i <= later; ++i) {
    const internal::KeyframeState& kf = *keyframes[i];
    const internal::StepSigmas sigmas = internal::StepSigmasOf(kf);
    bound_t += sigmas.t + sigmas.r * (t_later - kf.T_wc().t).norm();
    bound_r += sigmas.r;
  }
  const double factor = options_.loop_drift_factor;
  const ConstellationMatchOptions match;
  const double angle =
      2.0 * std::atan2(correction.q.vec().norm(), std::abs(correction.q.w()));
  return (correction * t_later - t_later).norm() <=
             factor * bound_t + match.position_gate &&
         angle <= factor * bound_r + match.angle_gate;
}

bool Backend::Impl::MergeDuplicate(int from, int into) {
  const internal::ObjectState& duplicate = *map_.objects()[from];
  if (duplicate.type != map_.objects()[into]->type) return false;
  // Each of the duplicate's angles is the merged object's nearest one
  // (modulo the class's order where the prior gives it; its observations
  // are then turned to it) or a new one, at the duplicate's rotation after
  // the loop moved it.
  std::vector<int> angles;
  std::vector<int> multiples;
  for (size_t a = 0; a < duplicate.thetas.size(); ++a) {
    int multiple = 0;
    angles.push_back(map_.MatchOrAddAngle(
        into, duplicate.Rotation(static_cast<int>(a)), angles, &multiple));
    multiples.push_back(multiple);
  }
  const std::vector<double> evidence = duplicate.angle_evidence;
  std::vector<internal::ObjectObservation> observations =
      map_.MergeInto(from, into);
  for (size_t a = 0; a < angles.size(); ++a) {
    map_.AddAngleEvidence(into, angles[a], evidence[a]);
  }
  for (internal::ObjectObservation& observation : observations) {
    if (observation.angle >= 0) {
      map_.TurnByFold(into, multiples[observation.angle], &observation);
      observation.angle = angles[observation.angle];
    }
    edges_.Add(into, std::move(observation));
  }
  edges_.RestoreKeyframeOrder(into);
  return true;
}

bool Backend::Impl::DetectObjectLoop() {
  if (!options_.detect_loops) return false;
  bool closed = false;
  if (map_.confirmations() != confirmations_checked_) {
    confirmations_checked_ = map_.confirmations();
    closed = CloseLoopFromObjects();
  }
  // After every solve: the window may have been pulled onto the earlier
  // map since a duplicate was made (by objects associated again).
  return MergeRevisitedDuplicates() > 0 || closed;
}

bool Backend::Impl::CloseLoopFromObjects() {
  const auto start = std::chrono::steady_clock::now();
  const LoopCandidates candidates = ObjectLoopCandidates();
  const int min_objects = options_.loop_min_objects;
  if (static_cast<int>(candidates.recent.size()) < min_objects ||
      static_cast<int>(candidates.earlier.size()) < min_objects) {
    return false;
  }
  ConstellationMatchOptions match_options;
  match_options.min_support = min_objects;
  for (const auto& [name, prior] : class_priors_) {
    if (prior.symmetry == SymmetryType::kDiscrete && prior.order >= 2) {
      match_options.symmetry_orders.emplace(name, prior.order);
    }
  }
  const ConstellationMatchResult result =
      MatchConstellation(candidates.recent, candidates.earlier, match_options);
  if (!result.match) return false;
  const ConstellationMatch& match = *result.match;

  // The loop: the newest keyframe, where the match puts it, relative to the
  // last keyframe that saw one of the recognised objects. If they are all a
  // loaded map's that this run has not seen, relative to the last keyframe
  // that saw any loaded object (the map's priors hold it in the map's
  // frame), or else to the first keyframe (which holds it).
  const internal::KeyframeList& keyframes = trajectory_.keyframes();
  const int k = static_cast<int>(keyframes.size()) - 1;
  int earlier = -1;
  for (const ObjectCorrespondence& c : match.correspondences) {
    earlier = std::max(earlier, map_.objects()[c.map]->last_keyframe);
  }
  if (earlier < 0) earlier = std::max(0, LastKeyframeOnLoadedObjects());
  if (earlier >= k || !WithinPossibleDrift(earlier, k, match.T_map_local)) {
    return false;
  }
  LoopClosureInput closure;
  closure.keyframe = keyframes[earlier]->id;
  closure.T = keyframes[earlier]->T_wc().Inverse() *
              (match.T_map_local * keyframes[k]->T_wc());
  closure.sigma_t = std::max(options_.loop_sigma_t, match.position_rmse);
  closure.sigma_r = options_.loop_sigma_r;
  const double close_seconds_before = statistics_.loop_closure_seconds;
  CloseLoop(k, closure);
  LoopClosureReport& report = loop_closures_.back();
  report.from_objects = true;
  // Without the moved past (the graph's solve failed; the closure was left
  // out) the duplicates stay where the drift put them.
  const bool closed = report.message.empty();
  if (closed) ++statistics_.object_loop_closures;
  for (const ObjectCorrespondence& c : match.correspondences) {
    LoopObjectPair pair;
    pair.map = c.map;
    pair.duplicate = c.local;
    pair.merged = closed && MergeDuplicate(static_cast<int>(c.local),
                                           static_cast<int>(c.map));
    // A recognised duplicate that stays (its type differs) must not make
    // the same loop again at the next confirmation.
    if (closed && !pair.merged) {
      unmerged_duplicates_.insert(static_cast<int>(c.local));
    }
    report.objects.push_back(pair);
  }
  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  statistics_.loop_closure_seconds = close_seconds_before + report.seconds;
  return closed;
}

double Backend::Impl::PositionSigma(const internal::ObjectState& o) const {
  // The detections' noise as the association gate takes it: the
  // detection's own (times its class's claim factor), or its scatter held
  // to the class's white part, or the class's estimate (with the
  // persistent part of its errors, ObjectMeanSigma), or the default; over
  // the square root of the keyframes that saw the object.
  const internal::ObjectObservation& first = o.observations.front();
  const double sigma_t =
      first.claimed_t
          ? first.sigma_t * ClaimFactorT(o.class_name)
          : GateSigmaT(o.class_name,
                       first.from_scatter ? std::optional<double>(first.sigma_t)
                                          : std::nullopt)
                .value_or(first.sigma_t);
  const int n = std::max(1, o.keyframes_seen);
  if (first.claimed_t || first.from_scatter) return sigma_t / std::sqrt(n);
  return internal::ObjectMeanSigma(
      sigma_t, n, map_.noise().TranslationReport(o.class_name));
}

bool Backend::Impl::SameObject(const internal::ObjectState& a,
                               const internal::ObjectState& b) const {
  // gate_position first: the noise's gate takes the class's estimate.
  const double distance = (a.position() - b.position()).norm();
  if (a.type != b.type || distance > options_.gate_position) return false;
  if (options_.gate_sigmas > 0.0 &&
      distance > options_.gate_sigmas *
                     std::hypot(PositionSigma(a), PositionSigma(b))) {
    return false;
  }
  switch (a.type) {
    case SymmetryType::kAsymmetric:
      return a.Rotation(-1).angularDistance(b.Rotation(-1)) <=
             options_.gate_rotation;
    case SymmetryType::kContinuous:
      return std::abs(a.axis_w().normalized().dot(b.axis_w().normalized())) >=
             std::cos(options_.gate_axis);
    case SymmetryType::kDiscrete:
      // An angle of one within gate_angle of an angle of the other.
      for (size_t i = 0; i < a.thetas.size(); ++i) {
        for (size_t j = 0; j < b.thetas.size(); ++j) {
          if (a.Rotation(static_cast<int>(i))
                  .angularDistance(b.Rotation(static_cast<int>(j))) <=
              options_.gate_angle) {
            return true;
          }
        }
      }
      return false;
  }
  return false;
}

namespace {

// No keyframe detected both: two objects one keyframe showed together are
// two objects. One pass over both, which are in keyframe order.
bool NeverSeenTogether(const internal::ObjectState& a,
                       const internal::ObjectState& b) {
  auto i = a.observations.begin();
  auto j = b.observations.begin();
  while (i != a.observations.end() && j != b.observations.end()) {
    if (i->keyframe == j->keyframe) return false;
    if (i->keyframe < j->keyframe) {
      ++i;
    } else {
      ++j;
    }
  }
  return true;
}

}  // namespace

bool Backend::Impl::MergeDuplicatesTheMoveJoined() {
  // A moved past can bring together two copies of an object that neither
  // the revisit nor the camera's place now touch: made on a visit whose
  // window drifted off the merged place, and put back on it by a later
  // closure elsewhere (the graph moves both with their keyframes).
  const bool moved = past_moved_;
  past_moved_ = false;
  if (!moved || !options_.detect_loops) return false;
  return MergeRevisitedDuplicates(/*every_object=*/true) > 0;
}

int Backend::Impl::OneCopyOf(int o) const {
  const internal::ObjectList& objects = map_.objects();
  const internal::ObjectState& object = *objects[o];
  int match = -1;
  int matches = 0;
  for (int e : map_.ObjectsOfClass(object.class_name)) {
    const internal::ObjectState& other = *objects[e];
    // Two objects of a loaded map were told apart by the run that made it,
    // whose detections this run does not have.
    if (e == o || !internal::IsMapped(other) ||
        (internal::IsLoaded(object) && internal::IsLoaded(other)) ||
        !SameObject(object, other) || !NeverSeenTogether(object, other)) {
      continue;
    }
    match = e;
    ++matches;
  }
  return matches == 1 ? match : -1;
}

int Backend::Impl::MergeRevisitedDuplicates(bool every_object) {
  const internal::ObjectList& objects = map_.objects();
  const int n = static_cast<int>(trajectory_.keyframes().size());
  const int recent_begin = std::max(0, n - options_.loop_recent_keyframes);
  int merged = 0;
  for (size_t r = 0; r < objects.size(); ++r) {
    const internal::ObjectState& candidate = *objects[r];
    // Made recently (a revisit's duplicate), or seen now: two copies of
    // one object that a drift made and a loop brought together are
    // detected in turn, each where the other is.
    if (!internal::IsMapped(candidate) ||
        (!every_object && candidate.created_keyframe < recent_begin &&
         candidate.last_keyframe != n - 1)) {
      continue;
    }
    // The one other object of its class it now is, as association would
    // have found it, which no keyframe detected together with it; and it
    // the one such object of the other.
    const int match = OneCopyOf(static_cast<int>(r));
    if (match < 0 || OneCopyOf(match) != static_cast<int>(r)) continue;
    // The later-made one goes into the earlier-made one (its id stays).
    const bool older = std::make_pair(candidate.created_keyframe, r) <
                       std::make_pair(objects[match]->created_keyframe,
                                      static_cast<size_t>(match));
    const int from = older ? match : static_cast<int>(r);
    const int into = older ? static_cast<int>(r) : match;
    if (MergeDuplicate(from, into)) ++merged;
  }
  return merged;
}

}  // namespace symba
