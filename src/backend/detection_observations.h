// Turning one detection into the observations its object edges are built
// from, per method (method notes Sec. 4; docs/backend.md "Mode merging").
// Pure functions of the detection, its categorization and the options; the
// keyframe and the discrete angle of each observation are set by the
// caller. Not installed.
#ifndef SYMBA_SRC_BACKEND_DETECTION_OBSERVATIONS_H_
#define SYMBA_SRC_BACKEND_DETECTION_OBSERVATIONS_H_

#include <optional>
#include <string>
#include <vector>

#include "backend/backend_state.h"
#include "symba/backend/backend_options.h"
#include "symba/backend/keyframe_input.h"
#include "symba/categorization/categorize.h"
#include "symba/categorization/hypothesis_scatter.h"

namespace symba::internal {

// A detection's id: its own, else "<keyframe id>/<index>" (the log
// format's default).
std::string DetectionId(const KeyframeInput& input, size_t d);

// True if `detection` gives no sigma and has enough hypotheses for its
// scatter to weigh it (BackendOptions::scatter_min_hypotheses, under
// estimate_noise: the class's white part holds it).
bool WantsScatter(const DetectionInput& detection,
                  const BackendOptions& options);
// The scatter of a detection that WantsScatter, if its categorisation kept
// scatter_min_hypotheses inliers and they are spread at all (sigmas at
// least kMinSigmaT/R); nullopt otherwise.
std::optional<HypothesisScatter> UsableScatter(
    const DetectionInput& detection,
    const CategorizedDetection& categorized,
    const BackendOptions& options);

// The noise a detection's components start with: its own sigmas (the
// options' default filling in a missing one), or its scatter.
Matrix6d InitialSqrtInfo(const DetectionInput& detection,
                         const std::optional<HypothesisScatter>& scatter,
                         const BackendOptions& options);

// The detection's noise on `observation`: a detection that gives a sigma
// is calibrated (claimed): what it gives is taken as it is, the options'
// default fills in the other. Without either: its hypotheses' scatter
// where there is one (from_scatter), else the default, or under
// estimate_noise the floor for an uncalibrated detector.
void SetObservationNoise(const DetectionInput& detection,
                         const std::optional<HypothesisScatter>& scatter,
                         const BackendOptions& options,
                         ObjectObservation* observation);

// The index of the highest-weight hypothesis among `indices` (ties: the
// first).
int HighestWeight(const std::vector<PoseHypothesis>& hyps,
                  const std::vector<int>& indices);
// The index of the highest-weight hypothesis of all (ties: the first).
int HighestWeight(const std::vector<PoseHypothesis>& hyps);
// 0, 1, ..., n - 1.
std::vector<int> AllIndices(size_t n);

// SH and MH: the highest-weight hypothesis (SH) or every hypothesis (MH) as
// 6-DoF components of one observation.
struct SixDofObservation {
  int best = 0;           // the highest-weight hypothesis
  std::vector<int> used;  // the hypotheses in the edge
  ObjectObservation observation;
};
SixDofObservation MakeSixDofObservation(const std::vector<PoseHypothesis>& hyps,
                                        Method method,
                                        const Matrix6d& sqrt_info);

// symba: the observations of a categorized detection.
//   per_angle (the map object is discrete and the detection is not
//   continuous): one observation per mode, a discrete cluster (R_base
//   Rot(a_o, theta_c), t_co) or an asymmetric detection's inliers at
//   T_co_base;
//   otherwise one observation of the inliers (an asymmetric object's 6-DoF
//   pose, or a continuous edge's positions and axis).
// With merge_modes each mode is one component at its mean with the modes'
// total weight; without, every member hypothesis is a component.
std::vector<ObjectObservation> MakeSymbaObservations(
    const CategorizedDetection& cat,
    const std::vector<PoseHypothesis>& hyps,
    const Matrix6d& sqrt_info,
    bool merge_modes,
    bool per_angle);

// Each observation's share of its detection: its components' total
// hypothesis weight over all of theirs (equal shares if that total is not
// positive). The shares sum to 1.
std::vector<double> ModeShares(
    const std::vector<ObjectObservation>& observations);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_DETECTION_OBSERVATIONS_H_
