// Whether the front end's stated motion noise holds, tested by the objects
// (docs/backend.md "Real detectors", 7). Between consecutive keyframes a
// static object's detection moves, where the front end alone puts it, by
// the change of the detector's error plus the front end's error over the
// step. With the detections' noise known (declared, times the class's claim
// factor, or a multi-hypothesis detection's scatter) the change d of a pair
// of detections has per axis the variance
//   c + g^2 s^2,   c = sigma_a^2 + sigma_b^2,   s^2 = s_t^2 + dist^2 s_r^2,
// s_t, s_r the step's stated sigmas and dist the later detection's distance
// to its camera; g = 1 when the statement holds. As for a detector's claims
// (detection_noise.h, "Claims"), the g that makes the changes chi-square
// consistent is the median of
//   g_i = sqrt(max(0, |d_i|^2 / 1.5382^2 - T^2 c_i) / s_i^2),
// T the tolerance a detector's claims get (claimed_noise_tolerance): the
// detections get the benefit of the doubt. Where a step's stated variance is
// small against the detections' (a front end with features), any misfit of
// the detector's noise, outliers included, would otherwise be put on the
// step, magnified by sqrt(c / s^2).
// Steps are grouped by the sigmas the front end stated for them, rounded to
// quarter octaves (a front end that knows when it has features says so),
// each group with its own g. A group's factor is g once g exceeds
// `tolerance`, and from then on while g exceeds 1; else 1: a front end is
// only ever found to understate its noise (what the objects cannot see, a
// front end better than it says, is left to its word). And only while
// another group vouches for the detections: its g at most 1 (the same
// detector's changes explained by its noise and those steps as stated)
// with its steps stated no wider than the detections' noise (the median of
// s^2 / (T^2 c) at most 1; a group of loosely stated steps would explain
// any detector). Without such a group the factor falls back to 1 and must
// pass `tolerance` again: with steps stated alike throughout, a change
// beyond the detections' noise and the step's cannot be told from a
// detector that claims too little, which its own claims test
// (detection_noise.h) scales; the front end is then taken at its word.
// The two tests share the pairs and each subtracts the other's current
// belief: the claims test the applied step variance, this one the claims
// times their class's factor (T^2 on top); whichever passes its tolerance
// first takes the excess. A claimed_noise_tolerance large enough to believe
// every claim therefore also leaves every step as stated.
#ifndef SYMBA_SRC_BACKEND_MOTION_CLAIMS_H_
#define SYMBA_SRC_BACKEND_MOTION_CLAIMS_H_

#include <map>
#include <utility>
#include <vector>

#include "backend/detection_noise.h"
#include "symba/backend/estimates.h"

namespace symba::internal {

// Steps stated alike: the quarter octaves (round(4 log2 sigma)) of a step's
// stated sigmas (m, rad). The objects' test of the steps (MotionClaims) and
// the keyframe graph's covariances group steps by it.
using StatedSigmasKey = std::pair<int, int>;
StatedSigmasKey StatedSigmasKeyOf(double stated_t, double stated_r);

class MotionClaims {
 public:
  MotionClaims(int window,
               int min_samples,
               double tolerance,
               double detection_tolerance)
      : window_(window),
        min_samples_(min_samples),
        tolerance_(tolerance),
        detection_tolerance_(detection_tolerance) {}

  // One pair (see above) over a step stated with sigmas (stated_t m,
  // stated_r rad): change_squared |d|^2 (m^2), detection_variance c and
  // stated_variance s^2 (m^2, per axis).
  void Add(double stated_t,
           double stated_r,
           double change_squared,
           double detection_variance,
           double stated_variance);
  // The factor for the sigmas of a step stated as (stated_t, stated_r),
  // from the samples so far (see above; >= 1). Updates the group's applied
  // factor: call it once per new step.
  double Factor(double stated_t, double stated_r);

  // Every group with samples, in the order of their stated sigmas.
  std::vector<MotionNoiseReport::Group> Report() const;

 private:
  using Key = StatedSigmasKey;
  // Another group's pairs (min_samples of them) are explained by the
  // detections' noise and their steps as stated (scale at most 1), and
  // its steps are stated no wider than the detections' noise (median of
  // s^2 / (T^2 c) at most 1), so that a detector claiming too little would
  // have shown there.
  bool DetectionsVouchedFor(const Key& key) const;
  struct Group {
    explicit Group(int window) : samples(window), step_share(window) {}
    double stated_t = 0.0;
    double stated_r = 0.0;
    ClaimSamples samples;
    // s^2 / (T^2 c) of its pairs: at most 1 (median), a detector that
    // claims too little would show in this group's g.
    RobustScale step_share;
    double factor = 1.0;  // applied
  };

  int window_;
  int min_samples_;
  double tolerance_;
  double detection_tolerance_;
  std::map<Key, Group> groups_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_MOTION_CLAIMS_H_
