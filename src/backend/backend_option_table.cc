#include "symba/backend/backend_option_table.h"

#include "common/option_ranges.h"
#include "symba/geometry/angle.h"

namespace symba {
namespace {

// A noise sigma: its information and square-root information stay finite
// (backend_options.h).
OptionRange NoiseSigma() { return Between(kMinNoiseSigma, kMaxNoiseSigma); }

OptionTable<MixtureOptions> MakeMixtureTable() {
  using O = MixtureOptions;
  return {
      BoolOption<O>("use_null_hypothesis",
                    &O::use_null_hypothesis,
                    "add a null-hypothesis component to every max-mixture"),
      DoubleOption<O>("null_weight",
                      &O::null_weight,
                      "",
                      Positive(),
                      "the null hypothesis's weight, relative to the "
                      "hypotheses' weights normalised to sum 1"),
      DoubleOption<O>("null_sigma_scale",
                      &O::null_sigma_scale,
                      "",
                      Above(1.0),
                      "the null hypothesis's sigmas are the nearest "
                      "component's times this"),
  };
}

void AppendWindowOptions(OptionTable<BackendOptions>* table) {
  using O = BackendOptions;
  table->insert(
      table->end(),
      {
          EnumOption<O>("method",
                        &O::method,
                        MethodNames(),
                        "symba, mh (all hypotheses in one 6-DoF max-mixture) "
                        "or sh (the highest-weight hypothesis)"),
          IntOption<O>("window_size",
                       &O::window_size,
                       AtLeast(1),
                       "keyframes free in a window solve"),
          EnumOption<O>("window_policy",
                        &O::window_policy,
                        WindowPolicyNames(),
                        "what a keyframe leaving the window becomes: "
                        "marginalize, condition or drop"),
          DoubleOption<O>("marginalize_min_margin",
                          &O::marginalize_min_margin,
                          "",
                          NonNegative(),
                          "marginalize: the cost lead (nats) a max-mixture's "
                          "winner needs over every rival to enter a prior"),
          DoubleOption<O>("marginalize_rival_distance",
                          &O::marginalize_rival_distance,
                          "",
                          NonNegative(),
                          "marginalize: whitened residual distance beyond "
                          "which a component is the winner's rival"),
          EnumOption<O>("chain_prior",
                        &O::chain_prior,
                        ChainPriorNames(),
                        "marginalize: a leaving keyframe held at its estimate "
                        "(conditional) or eliminated by the Schur complement "
                        "(marginal)"),
          BoolOption<O>("keep_history",
                        &O::keep_history,
                        "keep the factors of keyframes that left the window "
                        "for a batch solve (otherwise they are freed)"),
          BoolOption<O>("calibrate_covariances",
                        &O::calibrate_covariances,
                        "keyframe graph covariances with each edge group's "
                        "noise as the estimate's residuals show it (otherwise "
                        "as stated)"),
          IntOption<O>("max_iterations",
                       &O::max_iterations,
                       AtLeast(1),
                       "solver iterations per window solve"),
          IntOption<O>("batch_max_iterations",
                       &O::batch_max_iterations,
                       AtLeast(1),
                       "solver iterations of a batch solve"),
          IntOption<O>(
              "num_threads", &O::num_threads, AtLeast(1), "Ceres threads"),
      });
}

void AppendObjectEdgeOptions(OptionTable<BackendOptions>* table) {
  using O = BackendOptions;
  table->insert(
      table->end(),
      {
          DoubleOption<O>("hypothesis_sigma_t",
                          &O::hypothesis_sigma_t,
                          "m",
                          NoiseSigma(),
                          "hypothesis translation noise when a detection "
                          "gives none"),
          DoubleOption<O>("hypothesis_sigma_r",
                          &O::hypothesis_sigma_r,
                          "rad",
                          NoiseSigma(),
                          "hypothesis rotation noise when a detection gives "
                          "none"),
          DoubleOption<O>("gamma",
                          &O::gamma,
                          "",
                          NonNegative(),
                          "weight of the continuous edge's axis term"),
          DoubleOption<O>("axis_sigma",
                          &O::axis_sigma,
                          "rad",
                          NoiseSigma(),
                          "noise of a measured axis"),
          BoolOption<O>("merge_modes",
                        &O::merge_modes,
                        "symba: one component per mode at its mean; false: "
                        "one per hypothesis, as in the paper"),
          EnumOption<O>("object_loss",
                        &O::object_loss,
                        LossNames(),
                        "robust loss on every object edge: none, huber or "
                        "cauchy"),
          DoubleOption<O>("object_loss_scale",
                          &O::object_loss_scale,
                          "",
                          Positive(),
                          "scale of the object loss (whitened units)"),
          EnumOption<O>("detection_errors",
                        &O::detection_errors,
                        DetectionErrorsNames(),
                        "what a detection's sigmas are the noise of: log "
                        "(the SE(3) log error, the paper's) or independent "
                        "(its position and its rotation)"),
      });
  AppendNested("mixture", &O::mixture, MixtureOptionTable(), table);
}

void AppendCameraAndGateOptions(OptionTable<BackendOptions>* table) {
  using O = BackendOptions;
  table->insert(
      table->end(),
      {
          DoubleOption<O>("frontend_sigma_t",
                          &O::frontend_sigma_t,
                          "m",
                          NoiseSigma(),
                          "translation noise of the front end's relative "
                          "motion"),
          DoubleOption<O>("frontend_sigma_r",
                          &O::frontend_sigma_r,
                          "rad",
                          NoiseSigma(),
                          "rotation noise of the front end's relative motion"),
          DoubleOption<O>("point_sigma_px",
                          &O::point_sigma_px,
                          "px",
                          NoiseSigma(),
                          "reprojection noise"),
          DoubleOption<O>("point_loss_scale",
                          &O::point_loss_scale,
                          "",
                          Positive(),
                          "Huber scale of the reprojection (whitened units)"),
          DoubleOption<O>("point_depth_sigma_relative",
                          &O::point_depth_sigma_relative,
                          "",
                          NonNegative(),
                          "depth noise as a fraction of the depth; 0 ignores "
                          "depths"),
          DoubleOption<O>("gate_position",
                          &O::gate_position,
                          "m",
                          Positive(),
                          "association gate on position"),
          DoubleOption<O>("gate_axis",
                          &O::gate_axis,
                          "rad",
                          AngleBelowHalfPi(),
                          "association gate on the axis, sign-free"),
          DoubleOption<O>("gate_rotation",
                          &O::gate_rotation,
                          "rad",
                          Positive(),
                          "association gate on the 6-DoF rotation"),
          DoubleOption<O>("gate_angle",
                          &O::gate_angle,
                          "rad",
                          AngleBelowPi(),
                          "association gate of a discrete cluster's angle"),
          DoubleOption<O>("reanchor_angle",
                          &O::reanchor_angle,
                          "rad",
                          AngleBelowPi(),
                          "a discrete object's axis is re-anchored when it "
                          "moved this far"),
      });
}

void AppendRealDetectorOptions(OptionTable<BackendOptions>* table) {
  using O = BackendOptions;
  table->insert(
      table->end(),
      {
          IntOption<O>("confirm_keyframes",
                       &O::confirm_keyframes,
                       AtLeast(1),
                       "keyframes with a detection before a new object "
                       "enters the map (1: at once)"),
          IntOption<O>("tentative_timeout",
                       &O::tentative_timeout,
                       AtLeast(1),
                       "keyframes without a detection after which a "
                       "tentative object is dropped"),
          DoubleOption<O>("track_tolerance",
                          &O::track_tolerance,
                          "",
                          NonNegative(),
                          "with estimate_noise: a tentative object whose "
                          "detections changed by more than this times a "
                          "static object's is not confirmed; 0: no test"),
          DoubleOption<O>("gate_sigmas",
                          &O::gate_sigmas,
                          "",
                          NonNegative(),
                          "position gate in the detection's noise; 0: "
                          "gate_position only"),
          BoolOption<O>("estimate_noise",
                        &O::estimate_noise,
                        "estimate each class's detection noise from the data"),
          IntOption<O>("noise_window",
                       &O::noise_window,
                       AtLeast(1),
                       "noise samples kept per class (>= noise_min_samples)"),
          IntOption<O>("noise_min_samples",
                       &O::noise_min_samples,
                       AtLeast(1),
                       "noise samples needed before a class's estimate is "
                       "used"),
          DoubleOption<O>("noise_update_ratio",
                          &O::noise_update_ratio,
                          "",
                          AtLeast(1.0),
                          "change of a class's noise estimate that rebuilds "
                          "its edges"),
          DoubleOption<O>("claimed_noise_tolerance",
                          &O::claimed_noise_tolerance,
                          "",
                          AtLeast(1.0),
                          "with estimate_noise: the factor by which a class's "
                          "frame-to-frame changes may exceed its declared "
                          "sigmas before they are scaled"),
          DoubleOption<O>("motion_noise_tolerance",
                          &O::motion_noise_tolerance,
                          "",
                          AtLeast(1.0),
                          "with estimate_noise: factor by which a front end's "
                          "steps may exceed their stated sigmas before they "
                          "are scaled"),
          DoubleOption<O>("uncalibrated_sigma_t",
                          &O::uncalibrated_sigma_t,
                          "m",
                          NoiseSigma(),
                          "with estimate_noise: least translation noise of a "
                          "detection without sigmas"),
          DoubleOption<O>("uncalibrated_sigma_r",
                          &O::uncalibrated_sigma_r,
                          "rad",
                          NoiseSigma(),
                          "with estimate_noise: least rotation noise of a "
                          "detection without sigmas"),
          BoolOption<O>("sight_rows",
                        &O::sight_rows,
                        "with estimate_noise: a detection weighed at the "
                        "floor also places its object across its line of "
                        "sight with the class's noise, the camera held"),
          IntOption<O>("scatter_min_hypotheses",
                       &O::scatter_min_hypotheses,
                       AtLeast(0),
                       "weigh a detection without sigmas by its hypotheses' "
                       "spread when it has this many; 0: never"),
          DoubleOption<O>("min_support",
                          &O::min_support,
                          "",
                          Fraction(),
                          "drop a confirmed object detected in under this "
                          "share of the keyframes it was in view; 0 disables"),
          IntOption<O>("min_support_views",
                       &O::min_support_views,
                       AtLeast(1),
                       "keyframes in view before min_support applies"),
          IntOption<O>("upgrade_evidence",
                       &O::upgrade_evidence,
                       AtLeast(1),
                       "symba: agreeing flips before an asymmetric object "
                       "becomes discrete"),
          DoubleOption<O>("upgrade_min_fraction",
                          &O::upgrade_min_fraction,
                          "",
                          Fraction(),
                          "symba: the agreeing flips' least share of the "
                          "keyframes that detected the object (and the "
                          "class's flips' of its objects' keyframes)"),
          DoubleOption<O>("upgrade_confusion_rate",
                          &O::upgrade_confusion_rate,
                          "",
                          AboveBelow(0.0, 0.3),
                          "symba: how often a detector turns an asymmetric "
                          "object to a wrong rotation (the upgrade test's "
                          "alternative)"),
          DoubleOption<O>("upgrade_odds",
                          &O::upgrade_odds,
                          "",
                          AtLeast(1.0),
                          "symba: the odds two recurring rotations need over "
                          "one rotation and confusions before an upgrade"),
          IntOption<O>("max_upgrade_order",
                       &O::max_upgrade_order,
                       AtLeast(2),
                       "symba: the largest symmetry order a flip may show"),
          DoubleOption<O>("upgrade_angle_tolerance",
                          &O::upgrade_angle_tolerance,
                          "rad",
                          AngleBelowHalfPi(),
                          "symba: how closely a flip angle must fit 2 pi j / "
                          "K"),
      });
}

void AppendLoopOptions(OptionTable<BackendOptions>* table) {
  using O = BackendOptions;
  table->insert(
      table->end(),
      {
          BoolOption<O>("detect_loops",
                        &O::detect_loops,
                        "find loop closures from the objects and merge the "
                        "objects a revisit mapped again"),
          IntOption<O>("loop_min_objects",
                       &O::loop_min_objects,
                       AtLeast(2),
                       "recognised objects a loop found from objects needs"),
          IntOption<O>("loop_recent_keyframes",
                       &O::loop_recent_keyframes,
                       AtLeast(1),
                       "objects first detected this recently are matched "
                       "against the older map"),
          DoubleOption<O>("loop_drift_factor",
                          &O::loop_drift_factor,
                          "",
                          Positive(),
                          "a loop's correction must be within this times "
                          "the drift the stated motion noise allows"),
          DoubleOption<O>("loop_sigma_t",
                          &O::loop_sigma_t,
                          "m",
                          NoiseSigma(),
                          "position noise of a loop found from objects"),
          DoubleOption<O>("loop_sigma_r",
                          &O::loop_sigma_r,
                          "rad",
                          NoiseSigma(),
                          "rotation noise of a loop found from objects"),
      });
}

OptionTable<BackendOptions> MakeBackendTable() {
  OptionTable<BackendOptions> table;
  AppendWindowOptions(&table);
  AppendObjectEdgeOptions(&table);
  AppendCameraAndGateOptions(&table);
  AppendRealDetectorOptions(&table);
  AppendLoopOptions(&table);
  AppendNested("categorization",
               &BackendOptions::categorization,
               CategorizationOptionTable(),
               &table);
  return table;
}

}  // namespace

const std::vector<EnumName<Method>>& MethodNames() {
  static const std::vector<EnumName<Method>> names = {
      {Method::kSymba, "symba"},
      {Method::kMultiHypothesis, "mh"},
      {Method::kSingleHypothesis, "sh"}};
  return names;
}

const std::vector<EnumName<WindowPolicy>>& WindowPolicyNames() {
  static const std::vector<EnumName<WindowPolicy>> names = {
      {WindowPolicy::kMarginalize, "marginalize"},
      {WindowPolicy::kCondition, "condition"},
      {WindowPolicy::kDrop, "drop"}};
  return names;
}

const std::vector<EnumName<ChainPrior>>& ChainPriorNames() {
  static const std::vector<EnumName<ChainPrior>> names = {
      {ChainPrior::kConditional, "conditional"},
      {ChainPrior::kMarginal, "marginal"}};
  return names;
}

const std::vector<EnumName<LossType>>& LossNames() {
  static const std::vector<EnumName<LossType>> names = {
      {LossType::kNone, "none"},
      {LossType::kHuber, "huber"},
      {LossType::kCauchy, "cauchy"}};
  return names;
}

const std::vector<EnumName<DetectionErrors>>& DetectionErrorsNames() {
  static const std::vector<EnumName<DetectionErrors>> names = {
      {DetectionErrors::kLog, "log"},
      {DetectionErrors::kIndependent, "independent"}};
  return names;
}

const OptionTable<MixtureOptions>& MixtureOptionTable() {
  static const OptionTable<MixtureOptions> table = MakeMixtureTable();
  return table;
}

const OptionTable<BackendOptions>& BackendOptionTable() {
  static const OptionTable<BackendOptions> table = MakeBackendTable();
  return table;
}

}  // namespace symba
