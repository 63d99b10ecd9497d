// What the backend reports back: camera poses, map objects and, for every
// detection, the map object it went to and the type it was given.
#ifndef SYMBA_BACKEND_ESTIMATES_H_
#define SYMBA_BACKEND_ESTIMATES_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/ids.h"
#include "symba/backend/object_covariance.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct KeyframeEstimate {
  KeyframeId id = 0;
  double timestamp = 0.0;
  Rigid3d T_wc;
};

struct MapObjectEstimate {
  ObjectId id = 0;
  std::string class_name;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  Eigen::Vector3d t_wo = Eigen::Vector3d::Zero();
  // Unit world axis and object-frame axis (symmetric objects; zero otherwise).
  Eigen::Vector3d axis_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();
  std::vector<double> angles;  // discrete: theta_i (rad)
  // Discrete, one per angle: the detections' evidence for each angle. Every
  // detection shares one unit among the angles its modes went to, in
  // proportion to the modes' hypothesis weights; a detection from before
  // the object became discrete counts whole for angle 0. Summed over the
  // whole run (and the loaded map's), not only the window.
  std::vector<double> angle_evidence;
  // angle_evidence normalised to sum 1 (uniform while it sums to 0): how
  // the detections divided themselves among the angles. A truly symmetric
  // object seen by a detector that cannot tell its angles apart has
  // shares near 1/K; an object whose angle 0 dominates is likely at its
  // first pose, the others being the detector's flips.
  std::vector<double> angle_probabilities;
  // One pose (asymmetric), one per angle (discrete), or the representative
  // angle-0 pose (continuous).
  std::vector<Rigid3d> poses;
  int observations = 0;  // detections associated with it
  // An asymmetric object that became symmetric: when and on what evidence.
  struct Upgrade {
    KeyframeId keyframe = 0;  // the keyframe of the upgrade
    int evidence = 0;         // agreeing flips, or 1 symmetric detection
    int order = 0;            // the order the flips' angle fits (0: none)
    double angle = 0.0;       // the flips' mean angle (rad; 0 without flips)
  };
  std::optional<Upgrade> upgrade;
  // How far it can be trusted, where computed: Backend::Objects() leaves
  // it empty (Backend::ObjectCovariances() computes it on demand); a
  // replay fills it for every object it can (docs/backend.md
  // "Covariances").
  std::optional<MapObjectCovariance> covariance;
};

// Evidence normalised to sum 1; uniform while it sums to 0 (an object
// loaded from a map that kept none). MapObjectEstimate::angle_probabilities.
inline std::vector<double> AngleProbabilities(
    const std::vector<double>& evidence) {
  double total = 0.0;
  for (double e : evidence) total += e;
  std::vector<double> probabilities(evidence.size());
  for (size_t i = 0; i < evidence.size(); ++i) {
    probabilities[i] =
        total > 0.0 ? evidence[i] / total : 1.0 / evidence.size();
  }
  return probabilities;
}

struct DetectionAssignment {
  KeyframeId keyframe = 0;
  std::string detection;
  // The map object's id; -1 if the detection made a tentative object that
  // was dropped (an outlier). A tentative object's id while it waits for
  // confirmation (it is not in Backend::Objects() until then).
  ObjectId object = -1;
  SymmetryType symmetry = SymmetryType::kAsymmetric;  // as categorised
};

// What the backend estimated of one class's detection noise and what it
// weighs the class's detections with (docs/backend.md "Real detectors",
// mechanisms 3 and 4). The rotation part comes from asymmetric objects.
struct ClassNoiseEstimate {
  std::string class_name;
  // The estimate, sigma_L sqrt((1 + rho) / (1 - rho)); nullopt until the
  // class has noise_min_samples levels (or without estimate_noise).
  std::optional<double> sigma_t;  // m
  std::optional<double> sigma_r;  // rad
  // What a detection of the class that gives no sigma (and is not weighed
  // by its hypotheses' scatter) is weighed with: the larger of the estimate
  // its edges were last built with and uncalibrated_sigma_*
  // (hypothesis_sigma_* without estimate_noise).
  double weight_sigma_t = 0.0;  // m
  double weight_sigma_r = 0.0;  // rad
  // The samples behind each estimate: levels and increments, their sigmas
  // (nullopt below noise_min_samples), the correlation of consecutive
  // errors rho and the factor sqrt((1 + rho) / (1 - rho)).
  struct Samples {
    int levels = 0;
    int increments = 0;
    std::optional<double> sigma_level;
    std::optional<double> sigma_increment;
    double correlation = 0.0;
    double inflation = 1.0;
  };
  Samples translation;  // m
  Samples rotation;     // rad
  // The detections of the class measured by their hypotheses' scatter
  // (BackendOptions::scatter_min_hypotheses; a rotation outlier that got
  // no edge counts too): how many, and the medians of
  // their sigma_t, sigma_r over the last noise_window of them (nullopt:
  // none). Each such detection is weighed with its own scatter, or with
  // the class's sigma_increment where that is larger.
  struct Scatter {
    int detections = 0;
    std::optional<double> sigma_t;  // m
    std::optional<double> sigma_r;  // rad
  };
  Scatter scatter;
  // The detections of the class that declare their sigma
  // (BackendOptions::claimed_noise_tolerance): how many pairs in
  // consecutive keyframes measured the claims, and the claim scales, the
  // factor f by which the claims must grow for the pairs' changes to be
  // chi-square consistent with f^2 claims + the steps' motion noise (the
  // median of each pair's f_i), about 1 when the claims hold, 0 when the
  // steps alone explain them (nullopt below noise_min_samples). Once a
  // scale exceeds the tolerance, and while it stays above 1, the class's
  // claimed sigmas are weighed times it: factor_t, factor_r are what the
  // edges were last built with (1: as claimed).
  struct Claims {
    int translation_samples = 0;
    int rotation_samples = 0;
    std::optional<double> scale_t;
    std::optional<double> scale_r;
    double factor_t = 1.0;
    double factor_r = 1.0;
  };
  Claims claims;
  // What a tentative object's track is compared with before it is
  // confirmed (BackendOptions::track_tolerance; docs/backend.md "Real
  // detectors", 1): the median ratio of the steps of the class's confirmed
  // objects, each change between two detections of one object over its
  // expected spread (the class's sigma_increment and the motion noise the
  // camera factors apply in between); nullopt below noise_min_samples
  // steps or without a sigma_increment.
  std::optional<double> track_ratio;
  // What the edges of the class's confirmed objects weighed its detections
  // with, each edge as it was last built (one that left the window with
  // the noise of its time, which its information in the priors keeps; a
  // view of a merged copy that had left the window is not counted, its
  // edge went with the copy's prior): how many edges are of detections
  // that declare a sigma (weighed with it times the claim factor; one
  // declared sigma makes the other hypothesis_sigma_*, as the edge has
  // it), that are weighed by their hypotheses' scatter (held to the
  // class's frame-to-frame noise), or that state neither (the class's
  // estimate against uncalibrated_sigma_*; the first ones, built before
  // the class's first noise update, hypothesis_sigma_*), and the medians of the
  // sigmas (nullopt: no edge; the rotation's over the edges that weigh the
  // rotation with sigma_r: asymmetric views and a discrete angle's, not a
  // continuous view, whose axis has axis_sigma). A detection has one edge,
  // one per cluster on a discrete object, none when it is a rotation
  // outlier that joins without one; a view an object turned away from
  // (docs/backend.md "Real detectors", 5) weighs nothing and is not
  // counted. Unlike weight_sigma_*, which holds for a detection stating
  // neither, this is what the edges used.
  struct Weights {
    int declared = 0;
    int scatter = 0;
    int unstated = 0;
    std::optional<double> sigma_t;  // m
    std::optional<double> sigma_r;  // rad
  };
  Weights weights;
};

// What the backend weighs the camera's motion with, against the objects
// (docs/backend.md "Real detectors"): how many keyframes a motion factor
// ties to the one before by the odometry, and by the front end's poses,
// and the medians (over the last 500 such keyframes) of the sigmas per step
// each stated: the odometry's as the log states them, the front end's
// poses' the options' frontend_sigma_t, frontend_sigma_r. The factors are
// built with those times the factor of their group (`claims`), 1 unless the
// objects contradict the statement.
struct MotionNoiseReport {
  int odometry_steps = 0;
  std::optional<double> odometry_sigma_t;  // m
  std::optional<double> odometry_sigma_r;  // rad
  int frontend_steps = 0;
  std::optional<double> frontend_sigma_t;  // m
  std::optional<double> frontend_sigma_r;  // rad
  // With estimate_noise, the steps' statements tested by the objects
  // (docs/backend.md "Real detectors", 7), per group of steps the front end
  // stated alike: those sigmas, the pairs of detections that tested them,
  // the scale they give (once there are noise_min_samples) and the factor
  // the group's sigmas were last multiplied by (1: the statement holds).
  struct Group {
    double stated_sigma_t = 0.0;  // m
    double stated_sigma_r = 0.0;  // rad
    int pairs = 0;
    std::optional<double> scale;
    double factor = 1.0;
  };
  std::vector<Group> claims;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_ESTIMATES_H_
