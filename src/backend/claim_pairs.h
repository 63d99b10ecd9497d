// The samples that test a detector's declared noise (detection_noise.h,
// "Claims") and the front end's stated steps (motion_claims.h): each
// detection that declares a sigma is paired with the nearest detection of
// its class that declared one in the previous keyframe, and each detection
// whose noise is known (declared, or a scatter) with the nearest whose
// noise is known, both where the front end alone puts them (the chained
// poses). Between consecutive keyframes the front end's drift is one
// step's, which the step's motion noise states (as applied: stated times
// its group's factor), so a change far beyond what the claims and that step
// predict is the detector's own frame-to-frame noise; and a change far
// beyond the detections' known noise is the step's. A claim pair gives, for
// translation, |p_b - p_a|^2, sigma_t,a^2 + sigma_t,b^2 and s_t^2 + d^2
// s_r^2, and for rotation angle(R_a^T R_b)^2, sigma_r,a^2 + sigma_r,b^2 and
// s_r^2 (p world positions in m, R world rotations of asymmetric
// detections, d the later detection's distance to its camera in m, s_t^2,
// s_r^2 the step's motion variance per axis); a step pair |p_b - p_a|^2,
// the two known variances and the step's stated variance at the object.
// Pairing by class and distance, not by map object, keeps the test working
// when a detector that claims too little noise fails every association
// gate. A pair farther apart than `max_distance` is not taken (two
// instances of a class, or an outlier), nor a rotation pair turned by more
// than `max_angle` (a flip between the modes of a symmetric object, or an
// outlier: a change of mode, not noise).
#ifndef SYMBA_SRC_BACKEND_CLAIM_PAIRS_H_
#define SYMBA_SRC_BACKEND_CLAIM_PAIRS_H_

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "backend/detection_noise.h"
#include "backend/motion_claims.h"

namespace symba::internal {

struct ClaimedDetection {
  std::string class_name;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // m, front end's world
  std::optional<Eigen::Quaterniond> R_w;          // asymmetric only
  std::optional<double> sigma_t;                  // m, as declared
  std::optional<double> sigma_r;                  // rad, as declared
  double distance = 0.0;                          // m, |t_co|
  // The position noise per axis the pair's test of the front end's step
  // subtracts (m^2; motion_claims.h): a declared sigma_t times its class's
  // claim factor, or a multi-hypothesis detection's scatter, squared; 0:
  // not known (the detection tests no step).
  double variance_t = 0.0;
};

struct StepVariance {
  double t = 0.0;  // m^2
  double r = 0.0;  // rad^2
  // The sigmas the front end stated for the step (m, rad), which t and r
  // are those times its group's factor (motion_claims.h) of.
  double stated_t = 0.0;
  double stated_r = 0.0;
};

class ClaimPairs {
 public:
  ClaimPairs(double max_distance, double max_angle)
      : max_distance_(max_distance), max_angle_(max_angle) {}

  // A detection of keyframe (index) k. `step`: the variances (per axis)
  // of the motion factor from keyframe k - 1 to k; none when keyframe k's
  // motion factor starts elsewhere (a front-end pose after keyframes
  // without one): the change from k - 1 then holds steps no variance
  // states, and the detection is kept only to pair with keyframe k + 1's.
  // Keyframes come in increasing order; its pair, if any, goes to `noise`
  // (where both declare their sigmas) and to `motion` (where both have a
  // variance_t).
  void Add(int k,
           const ClaimedDetection& detection,
           const std::optional<StepVariance>& step,
           DetectionNoiseEstimator* noise,
           MotionClaims* motion);

 private:
  // The nearest detection of its class in the previous keyframe within
  // max_distance that declared its sigmas (claimed) or has a known noise.
  const ClaimedDetection* Nearest(const ClaimedDetection& detection,
                                  bool claimed) const;

  double max_distance_;  // m
  double max_angle_;     // rad
  int keyframe_ = -1;
  int previous_keyframe_ = -1;
  std::vector<ClaimedDetection> current_;
  std::vector<ClaimedDetection> previous_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_CLAIM_PAIRS_H_
