#include "backend/detection_observations.h"

#include <cmath>
#include <utility>

#include "backend/detection_noise.h"

namespace symba::internal {
namespace {

// A detection's hypotheses as edge components, for the given indices.
std::vector<PoseComponent> Components(const std::vector<PoseHypothesis>& hyps,
                                      const std::vector<int>& indices,
                                      const Matrix6d& sqrt_info) {
  std::vector<PoseComponent> components;
  components.reserve(indices.size());
  for (int j : indices) {
    components.push_back({Normalized(hyps[j].T_co), sqrt_info, hyps[j].weight});
  }
  return components;
}

// One mode's hypotheses merged into one component at `T_co` (the mode's
// mean from the categorization), weighted by their total weight.
std::vector<PoseComponent> MergedComponent(
    const std::vector<PoseHypothesis>& hyps,
    const std::vector<int>& members,
    const Rigid3d& T_co,
    const Matrix6d& sqrt_info) {
  double weight = 0.0;
  for (int j : members) weight += hyps[j].weight;
  return {{Normalized(T_co), sqrt_info, weight}};
}

// The modes of a detection seen by a discrete object: each a member list
// and its mean pose T_co.
std::vector<std::pair<std::vector<int>, Rigid3d>> Modes(
    const CategorizedDetection& cat, const std::vector<int>& inliers) {
  std::vector<std::pair<std::vector<int>, Rigid3d>> modes;
  if (cat.type != SymmetryType::kDiscrete) {
    modes.emplace_back(inliers, cat.T_co_base);
    return modes;
  }
  for (const AngleCluster& cluster : cat.clusters) {
    const Eigen::Quaterniond R_cluster =
        cat.T_co_base.q *
        Eigen::Quaterniond(Eigen::AngleAxisd(cluster.theta, cat.axis_o));
    modes.emplace_back(cluster.members, Rigid3d(R_cluster, cat.t_co));
  }
  return modes;
}

}  // namespace

std::string DetectionId(const KeyframeInput& input, size_t d) {
  const DetectionInput& det = input.detections[d];
  return det.id.empty() ? std::to_string(input.id) + "/" + std::to_string(d)
                        : det.id;
}

bool WantsScatter(const DetectionInput& detection,
                  const BackendOptions& options) {
  return !detection.sigma_t && !detection.sigma_r && options.estimate_noise &&
         options.scatter_min_hypotheses > 0 &&
         static_cast<int>(detection.hypotheses.size()) >=
             options.scatter_min_hypotheses;
}

std::optional<HypothesisScatter> UsableScatter(
    const DetectionInput& detection,
    const CategorizedDetection& categorized,
    const BackendOptions& options) {
  if (!WantsScatter(detection, options)) return std::nullopt;
  const HypothesisScatter scatter =
      MeasureHypothesisScatter(detection.hypotheses, categorized);
  // Copies of one pose say nothing of the noise.
  if (scatter.count < options.scatter_min_hypotheses ||
      !(scatter.sigma_t >= kMinSigmaT) || !(scatter.sigma_r >= kMinSigmaR) ||
      !std::isfinite(scatter.sigma_t) || !std::isfinite(scatter.sigma_r)) {
    return std::nullopt;
  }
  return scatter;
}

Matrix6d InitialSqrtInfo(const DetectionInput& detection,
                         const std::optional<HypothesisScatter>& scatter,
                         const BackendOptions& options) {
  if (scatter) return IsotropicPoseSqrtInfo(scatter->sigma_t, scatter->sigma_r);
  return IsotropicPoseSqrtInfo(
      detection.sigma_t.value_or(options.hypothesis_sigma_t),
      detection.sigma_r.value_or(options.hypothesis_sigma_r));
}

void SetObservationNoise(const DetectionInput& detection,
                         const std::optional<HypothesisScatter>& scatter,
                         const BackendOptions& options,
                         ObjectObservation* observation) {
  if (scatter) {
    observation->sigma_t = scatter->sigma_t;
    observation->sigma_r = scatter->sigma_r;
    observation->claimed_t = observation->claimed_r = false;
    observation->from_scatter = true;
    return;
  }
  const bool calibrated = detection.sigma_t || detection.sigma_r;
  const bool uncalibrated_floor = !calibrated && options.estimate_noise;
  observation->sigma_t = detection.sigma_t.value_or(
      uncalibrated_floor ? options.uncalibrated_sigma_t
                         : options.hypothesis_sigma_t);
  observation->sigma_r = detection.sigma_r.value_or(
      uncalibrated_floor ? options.uncalibrated_sigma_r
                         : options.hypothesis_sigma_r);
  observation->claimed_t = calibrated;
  observation->claimed_r = calibrated;
}

int HighestWeight(const std::vector<PoseHypothesis>& hyps,
                  const std::vector<int>& indices) {
  int best = indices.front();
  for (int j : indices) {
    if (hyps[j].weight > hyps[best].weight) best = j;
  }
  return best;
}

int HighestWeight(const std::vector<PoseHypothesis>& hyps) {
  int best = 0;
  for (size_t j = 1; j < hyps.size(); ++j) {
    if (hyps[j].weight > hyps[best].weight) best = static_cast<int>(j);
  }
  return best;
}

std::vector<int> AllIndices(size_t n) {
  std::vector<int> indices(n);
  for (size_t j = 0; j < n; ++j) indices[j] = static_cast<int>(j);
  return indices;
}

SixDofObservation MakeSixDofObservation(const std::vector<PoseHypothesis>& hyps,
                                        Method method,
                                        const Matrix6d& sqrt_info) {
  SixDofObservation result;
  result.best = HighestWeight(hyps, AllIndices(hyps.size()));
  result.used = method == Method::kSingleHypothesis
                    ? std::vector<int>{result.best}
                    : AllIndices(hyps.size());
  result.observation.components = Components(hyps, result.used, sqrt_info);
  result.observation.T_co_best = Normalized(hyps[result.best].T_co);
  return result;
}

std::vector<ObjectObservation> MakeSymbaObservations(
    const CategorizedDetection& cat,
    const std::vector<PoseHypothesis>& hyps,
    const Matrix6d& sqrt_info,
    bool merge_modes,
    bool per_angle) {
  const std::vector<int>& inliers =
      cat.inliers.empty() ? std::vector<int>{cat.reference} : cat.inliers;
  ObjectObservation base;
  if (cat.type != SymmetryType::kAsymmetric) base.axis_c = cat.axis_c;
  std::vector<ObjectObservation> observations;
  if (per_angle) {
    for (const auto& [members, T_co_mode] : Modes(cat, inliers)) {
      if (members.empty()) continue;
      ObjectObservation observation = base;
      observation.T_co_best =
          merge_modes ? Normalized(T_co_mode)
                      : Normalized(hyps[HighestWeight(hyps, members)].T_co);
      observation.components =
          merge_modes ? MergedComponent(hyps, members, T_co_mode, sqrt_info)
                      : Components(hyps, members, sqrt_info);
      observations.push_back(std::move(observation));
    }
    return observations;
  }
  base.T_co_best = cat.type == SymmetryType::kAsymmetric
                       ? cat.T_co_base
                       : Normalized(hyps[HighestWeight(hyps, inliers)].T_co);
  // A continuous edge uses only the components' positions, so merging them
  // at T_co_base (position t_co) is right for both types.
  base.components =
      merge_modes ? MergedComponent(hyps, inliers, cat.T_co_base, sqrt_info)
                  : Components(hyps, inliers, sqrt_info);
  observations.push_back(std::move(base));
  return observations;
}

std::vector<double> ModeShares(
    const std::vector<ObjectObservation>& observations) {
  std::vector<double> shares;
  shares.reserve(observations.size());
  double total = 0.0;
  for (const ObjectObservation& observation : observations) {
    double weight = 0.0;
    for (const PoseComponent& c : observation.components) weight += c.weight;
    shares.push_back(weight);
    total += weight;
  }
  for (double& share : shares) {
    share = total > 0.0 ? share / total : 1.0 / shares.size();
  }
  return shares;
}

}  // namespace symba::internal
