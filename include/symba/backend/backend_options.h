// BackendOptions: every option of the backend, with its default and unit.
// docs/backend.md explains them; Validate() says which one is out of range.
#ifndef SYMBA_BACKEND_BACKEND_OPTIONS_H_
#define SYMBA_BACKEND_BACKEND_OPTIONS_H_

#include <algorithm>
#include <string>

#include "symba/categorization/categorization_options.h"
#include "symba/common/status.h"
#include "symba/factors/mixture_options.h"
#include "symba/geometry/pi.h"

namespace symba {

// Every noise standard deviation symba is given (a detection's or the
// odometry's sigma_t / sigma_r, a loop closure's, the sigma options) must
// lie in [kMinNoiseSigma, kMaxNoiseSigma] (m, rad or px): its information
// 1 / sigma^2, and the determinant of a 6 x 6 square-root information built
// from it, must be finite and non-zero.
inline constexpr double kMinNoiseSigma = 1e-9;
inline constexpr double kMaxNoiseSigma = 1e9;
inline bool IsUsableNoiseSigma(double sigma) {
  return sigma >= kMinNoiseSigma && sigma <= kMaxNoiseSigma;  // NaN: false
}
// A sigma symba made (from a loaded map's noise, claim factors, estimates)
// held within that range, as the edges weigh with it.
inline double UsableNoiseSigma(double sigma) {
  return std::clamp(sigma, kMinNoiseSigma, kMaxNoiseSigma);
}
// Every translation (a pose's, m) and pixel coordinate (px) symba is given
// must be within +-kMaxCoordinate: the squares of residuals built from
// them stay finite (an odometry step of 1e300 m made every solve fail).
inline constexpr double kMaxCoordinate = 1e9;
// A hypothesis's weight (relative to the detection's others) is at most this
// (1e300 overflowed the sums of the mode merging).
inline constexpr double kMaxHypothesisWeight = 1e100;

// The three methods of the paper's Table I. Everything but the method runs
// the same code.
enum class Method {
  kSymba,             // categorise, unambiguous parameters (method notes 2-6)
  kMultiHypothesis,   // "mh": all hypotheses in one 6-DoF max-mixture (Fu et
                      // al.)
  kSingleHypothesis,  // "sh": the highest-weight hypothesis, plain SE(3) edge
};

const char* MethodName(Method method);  // "symba", "mh", "sh"
// Parses "symba" | "mh" | "sh"; false for anything else.
bool ParseMethod(const std::string& name, Method* method);

// What happens to a keyframe that leaves the window (docs/backend.md "The
// window"). The batch solve is the same under every policy.
enum class WindowPolicy {
  // Its factors leave the problem for good, linearised at the current
  // estimate into priors (chain_prior says how): its motion factors into a
  // prior on the later keyframes, its object edges and point observations,
  // conditioned on its final pose, into each object's and point's own
  // prior. A window solve touches the window's factors and those priors
  // only: bounded work per keyframe. The default.
  kMarginalize,
  // It is held constant with all its factors; every object a window
  // keyframe observes brings all its observations ever (the work grows with
  // the run).
  kCondition,
  // Its factors leave the problem and their information is lost; the
  // oldest window keyframe is held constant (the gauge).
  kDrop,
};

const char* WindowPolicyName(WindowPolicy policy);  // "marginalize", ...
bool ParseWindowPolicy(const std::string& name, WindowPolicy* policy);

// marginalize: what the keyframe chain keeps of a keyframe that leaves the
// window (docs/backend.md "The window").
enum class ChainPrior {
  // The leaving keyframe's estimate is taken as final, as condition holds
  // it: its motion factors become a linear prior on the keyframes they
  // reach, and the leaving keyframe's point observations inform the points
  // only. The default: it keeps condition's accuracy.
  kConditional,
  // The leaving keyframe's pose is eliminated by the Schur complement from
  // the previous prior, its motion factors and half of each point
  // observation (the point held at its estimate; the other half goes to the
  // point's prior): the chain keeps the accumulated uncertainty of the
  // keyframes that left. Exact for the chain alone; the points and objects
  // are conditioned, not marginalised jointly.
  kMarginal,
};

const char* ChainPriorName(ChainPrior prior);  // "conditional", "marginal"
bool ParseChainPrior(const std::string& name, ChainPrior* prior);

enum class LossType { kNone, kHuber, kCauchy };
const char* LossName(LossType loss);  // "none", "huber", "cauchy"
bool ParseLoss(const std::string& name, LossType* loss);

// How a detection's sigma_t and sigma_r weigh its pose edge's error, the
// SE(3) log [rho; omega] of the measured against the estimated T_co
// (symba/factors/pose_component.h, DetectionSqrtInfo; docs/backend.md
// "Detection errors").
enum class DetectionErrors {
  // rho and omega independent, sigma_t on rho (the paper's edge): a
  // rotation error swings the measured position about the camera with it.
  kLog,
  // The position t_co (camera frame) and the rotation independent, sigma_t
  // on the position: the bearing to the object is as good as the position.
  kIndependent,
};
const char* DetectionErrorsName(DetectionErrors errors);  // "log", ...
bool ParseDetectionErrors(const std::string& name, DetectionErrors* errors);

struct BackendOptions {
  Method method = Method::kSymba;

  // Windowed solve: the last `window_size` keyframes and everything they
  // observe are free; older keyframes are marginalised, held constant or
  // dropped, as window_policy says.
  int window_size = 10;
  // marginalize keeps condition's accuracy at bounded work per keyframe
  // (docs/backend.md "The window" has the comparison).
  WindowPolicy window_policy = WindowPolicy::kMarginalize;
  // marginalize: a max-mixture edge enters the prior with its current
  // winner only if the winner's cost (negative log-likelihood) is this much
  // below every rival's; an ambiguous edge is dropped instead. A rival is a
  // component whose whitened residual differs from the winner's by more
  // than marginalize_rival_distance: closer components are taken as the
  // winner's mode (the frozen winner may then be off by up to that many
  // whitened units for them; docs/backend.md "The window").
  double marginalize_min_margin = 2.0;
  double marginalize_rival_distance = 5.0;
  ChainPrior chain_prior = ChainPrior::kConditional;
  // Whether the factors of keyframes that left the window are kept for
  // OptimizeBatch. Without (the default) they are freed once marginalised
  // or dropped, so memory grows with the map and the keyframes' poses, not
  // with every detection ever made; OptimizeBatch then fails unless
  // window_policy is condition (under which nothing leaves). symba replay
  // keeps them when asked for a final batch solve.
  bool keep_history = false;
  // Levenberg-Marquardt iterations per window solve and per batch solve.
  int max_iterations = 10;
  int batch_max_iterations = 50;
  int num_threads = 1;
  // The keyframe graph's covariances (docs/backend.md "Covariances"): each
  // group of edges' noise as the residuals of the estimate show it, the
  // covariance that of the estimate the stated noise made (true), or the
  // inverse of the stated information (false).
  bool calibrate_covariances = true;

  // Default hypothesis noise when a detection gives none (m, rad).
  double hypothesis_sigma_t = 0.05;
  double hypothesis_sigma_r = 0.1;
  // The continuous edge's axis weight (paper Eq. 5) and axis noise (rad).
  double gamma = 1.0;
  double axis_sigma = 0.1;
  // symba only. true: the hypotheses of one mode enter an object edge as one
  // component at their mean (an asymmetric detection's inliers: T_co_base;
  // a discrete cluster c: (R_base Rot(a_o, theta_c), t_co); a continuous
  // detection's positions: t_co), with the detection's per-hypothesis
  // sigmas. false: every hypothesis is a component (the paper). A
  // max-mixture over a cloud of near-identical hypotheses follows the one
  // nearest the current estimate and barely resists a drifting camera; see
  // docs/backend.md "Mode merging" for the measurements.
  bool merge_modes = true;
  // Robust loss on every object edge; scale in whitened units.
  LossType object_loss = LossType::kCauchy;
  double object_loss_scale = 3.0;
  // What a detection's sigmas are the noise of (see DetectionErrors; every
  // method's edges, so the comparison stays one of methods).
  DetectionErrors detection_errors = DetectionErrors::kLog;
  MixtureOptions mixture;

  // Camera motion: the front end's relative motion between consecutive
  // keyframes (when a keyframe has no odometry) enters with these sigmas.
  double frontend_sigma_t = 0.05;
  double frontend_sigma_r = 0.02;
  // Reprojection noise (pixels) and its Huber loss scale (whitened).
  double point_sigma_px = 1.0;
  double point_loss_scale = 2.0;
  // A point observation with a depth also constrains the depth (RGB-D),
  // with sigma = point_depth_sigma_relative * depth (m). 0 disables it.
  double point_depth_sigma_relative = 0.01;

  // Data association gates (method notes Sec. 5).
  double gate_position = 0.5;                 // m
  double gate_axis = 20.0 * kPi / 180.0;      // rad, axis vs axis, sign-free
  double gate_rotation = 30.0 * kPi / 180.0;  // rad, 6-DoF rotation
  double gate_angle = 20.0 * kPi / 180.0;     // rad, discrete angle vs angle

  // A discrete object is re-anchored (a_w0 <- a_w) when its axis has moved
  // this far from its anchor (the swing is singular at 180 degrees).
  double reanchor_angle = 45.0 * kPi / 180.0;

  // Real detectors (docs/backend.md "Real detectors"). Every method gets
  // these; only the upgrade evidence is symba's.
  //
  // A new map object is tentative: its edges stay out of the solves until
  // detections in `confirm_keyframes` different keyframes joined it (1:
  // every object enters the map at once). A tentative object that no
  // detection joined for `tentative_timeout` keyframes is dropped with its
  // edges, and its detections are reported with object -1.
  int confirm_keyframes = 5;
  int tentative_timeout = 10;
  // With estimate_noise, a tentative object is confirmed only if its
  // detections, where the front end alone puts them, changed from one to
  // the next as one static object's do: the median of the changes over
  // their expected spread (the class's frame-to-frame noise and the motion
  // noise of the steps in between) at most track_tolerance times the median
  // of the class's confirmed objects (src/backend/object_track.h;
  // docs/backend.md "Real detectors", 1). 0: no test; nor with
  // confirm_keyframes 1.
  double track_tolerance = 3.0;
  // Position gate in the detection's noise: an object of n observations
  // takes a detection only within gate_sigmas * sigma_t * sqrt(1 + 1/n)
  // (and gate_position). 0: gate_position only.
  double gate_sigmas = 5.0;
  // Estimate each class's detection noise from its detections placed with
  // the front end's own poses (the chained odometry, never optimised;
  // robust medians of the last noise_window samples, used from
  // noise_min_samples on; docs/backend.md "Real detectors", 3) and build its
  // edges with it; a class's edges are rebuilt when its estimate moves by
  // more than the factor noise_update_ratio. A detection that gives its own
  // sigma is weighed with it as given, unless its class's frame-to-frame
  // changes contradict the claim (below).
  bool estimate_noise = true;
  int noise_window = 500;
  int noise_min_samples = 20;
  double noise_update_ratio = 1.25;
  // With estimate_noise, a declared sigma is a prior the data can overrule:
  // the changes between a class's claimed detections in consecutive
  // keyframes (where the front end alone puts them) give the class's claim
  // scale, the factor by which the claims must grow for the changes to be
  // chi-square consistent with them and the steps' motion noise; from
  // noise_min_samples pairs on, once the scale exceeds
  // claimed_noise_tolerance, and while it stays above 1, it multiplies
  // every claimed sigma of the class (docs/backend.md "Real detectors", 4).
  double claimed_noise_tolerance = 1.5;
  // With estimate_noise, the front end's stated motion noise is tested the
  // same way by the pairs of detections whose noise is known (declared or
  // their hypotheses' scatter): per group of steps stated alike, once the
  // scale by which the stated sigmas must grow exceeds
  // motion_noise_tolerance, and while it stays above 1, it multiplies the
  // sigmas of the group's next steps (src/backend/motion_claims.h;
  // docs/backend.md "Real detectors", 7).
  double motion_noise_tolerance = 1.2;
  // With estimate_noise, a detection that gives no sigma is weighed with
  // max(estimate, uncalibrated_sigma) instead of hypothesis_sigma: errors
  // that persist over many frames (a bias) cannot be told from camera
  // motion until the object was seen from elsewhere, so an uncalibrated
  // detector must not steer the camera (docs/backend.md "Real detectors"
  // has the measurements behind these values).
  double uncalibrated_sigma_t = 2.0;  // m
  double uncalibrated_sigma_r = 3.0;  // rad
  // With estimate_noise, the edge of a detection weighed at the floor
  // (undeclared, no scatter) gets three more rows on its object's position
  // alone: where the detection puts the object given the camera, weighed
  // across its line of sight at the class's estimate and along it at that
  // times how much wider the class's errors are along it (at most the
  // floor; LineOfSightRows; docs/backend.md "Real detectors", mechanism 8).
  // The rows do not pull the cameras; the object is placed by its views'
  // sight lines.
  bool sight_rows = true;
  // With estimate_noise, a detection that gives no sigma but whose
  // categorisation kept at least scatter_min_hypotheses hypotheses is
  // weighed with their spread about their modes (MeasureHypothesisScatter:
  // a multi-hypothesis detector's own word on its noise), or with its
  // class's frame-to-frame noise sigma_I where that is larger; neither the
  // uncalibrated floor nor the persistence inflation applies
  // (docs/backend.md "Real detectors", 4). Every method gets it. 0: never.
  int scatter_min_hypotheses = 5;
  // A confirmed object that was in view (in front of the camera, within
  // the widest bearing and depth any detection had) in min_support_views
  // keyframes, but detected in fewer than min_support of them, is dropped:
  // a cluster of outliers that happened to agree. 0 disables.
  double min_support = 0.2;
  int min_support_views = 20;
  // symba: an asymmetric object becomes discrete only after
  // `upgrade_evidence` flips in different keyframes agree (axis within
  // gate_axis, angle within gate_angle) on an angle within
  // upgrade_angle_tolerance of 2 pi j / K, K <= max_upgrade_order.
  // The agreeing flips must also be at least upgrade_min_fraction of the
  // keyframes that detected the object: a symmetric object seen by a
  // single-pose detector flips in about half of them (1 - 1/K), a textured
  // box that a detector now and then turns by 90 degrees in a few percent.
  // Both rotations must recur: with n0 keyframes that saw the object
  // unflipped, n1 agreeing flips, m = min(n0, n1), n = n0 + n1, the odds
  // (1/3)^m (2/3)^(n-m) / (c^m (1-c)^(n-m)) of a symmetric object against
  // one rotation and a detector's confusion at the rate
  // c = upgrade_confusion_rate must reach upgrade_odds; and the class's
  // asymmetric objects must flip in upgrade_min_fraction of their keyframes.
  int upgrade_evidence = 3;
  double upgrade_min_fraction = 0.3;
  double upgrade_confusion_rate = 0.05;
  double upgrade_odds = 100.0;
  int max_upgrade_order = 4;
  double upgrade_angle_tolerance = 10.0 * kPi / 180.0;  // rad

  // Loops found from the objects (docs/loop-closure.md "Loops from the
  // objects"). When a keyframe's window solve follows the confirmation of
  // an object, the confirmed objects first detected in the last
  // loop_recent_keyframes keyframes are matched (MatchConstellation)
  // against the confirmed objects last detected before them and before the
  // window. A unique match of at least loop_min_objects objects whose
  // correction of the newest keyframe is within loop_drift_factor times
  // the drift the camera motion could have made since the place was last
  // seen (every step off by its stated sigma the same way) closes a loop
  // to that keyframe (a relative pose with loop_sigma_t m, loop_sigma_r
  // rad) and merges each recognised duplicate into its map object.
  bool detect_loops = true;
  int loop_min_objects = 3;
  int loop_recent_keyframes = 30;
  double loop_drift_factor = 1.5;
  double loop_sigma_t = 0.1;   // m
  double loop_sigma_r = 0.05;  // rad

  CategorizationOptions categorization;

  // OK, or which option is out of range and why.
  Status Validate() const;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_BACKEND_OPTIONS_H_
