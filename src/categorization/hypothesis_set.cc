#include "categorization/hypothesis_set.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace symba {
namespace categorization {
namespace {

// Quaternions must be unit within this (the log format's tolerance).
constexpr double kUnitQuaternionTolerance = 1e-3;

}  // namespace

Status ValidateHypotheses(const std::vector<PoseHypothesis>& hypotheses) {
  if (hypotheses.empty()) {
    return Status::Error("categorize: the detection has no hypotheses");
  }
  for (int j = 0; j < static_cast<int>(hypotheses.size()); ++j) {
    const PoseHypothesis& h = hypotheses[j];
    // Built only on failure: no allocation on the normal path.
    const auto where = [j] {
      return "categorize: hypothesis " + std::to_string(j);
    };
    if (!h.T_co.q.coeffs().allFinite()) {
      return Status::Error(where() + ": rotation is not finite");
    }
    if (!h.T_co.t.allFinite()) {
      return Status::Error(where() + ": translation is not finite");
    }
    const double norm = h.T_co.q.norm();
    if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) {
      return Status::Error(where() + ": quaternion norm " +
                           std::to_string(norm) + " is not 1");
    }
    if (!(std::isfinite(h.weight) && h.weight > 0.0)) {
      return Status::Error(where() + ": weight " + std::to_string(h.weight) +
                           " is not positive and finite");
    }
  }
  return Status::Ok();
}

std::vector<char> GateTranslations(
    const std::vector<PoseHypothesis>& hypotheses, double gate) {
  const int n = static_cast<int>(hypotheses.size());
  std::vector<char> usable(n, 1);
  if (!std::isfinite(gate)) return usable;
  Eigen::Vector3d median;
  std::vector<double> coordinate(n);
  for (int axis = 0; axis < 3; ++axis) {
    for (int j = 0; j < n; ++j) coordinate[j] = hypotheses[j].T_co.t[axis];
    auto mid = coordinate.begin() + n / 2;
    std::nth_element(coordinate.begin(), mid, coordinate.end());
    median[axis] = *mid;
  }
  int kept = 0;
  for (int j = 0; j < n; ++j) {
    usable[j] = (hypotheses[j].T_co.t - median).norm() <= gate;
    kept += usable[j];
  }
  if (kept == 0) usable.assign(n, 1);
  return usable;
}

HypothesisSet MakeHypothesisSet(const std::vector<PoseHypothesis>& hypotheses,
                                double translation_gate) {
  const int n = static_cast<int>(hypotheses.size());
  HypothesisSet set;
  set.q.resize(n);
  set.R.resize(n);
  set.t.resize(n);
  set.w.resize(n);
  for (int j = 0; j < n; ++j) {
    set.q[j] = hypotheses[j].T_co.q.normalized();
    set.R[j] = set.q[j].toRotationMatrix();
    set.t[j] = hypotheses[j].T_co.t;
    set.w[j] = hypotheses[j].weight;
  }
  set.usable = GateTranslations(hypotheses, translation_gate);
  return set;
}

Eigen::Vector3d MeanTranslation(const HypothesisSet& set,
                                const std::vector<int>& members) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (int j : members) {
    sum += set.w[j] * set.t[j];
    weight += set.w[j];
  }
  return weight > 0.0 ? Eigen::Vector3d(sum / weight) : set.t[0];
}

}  // namespace categorization
}  // namespace symba
