// BOP symmetries (models_info.json) onto symba's three symmetry types. BOP
// lists an object's symmetry transforms explicitly: discrete ones as 4x4
// matrices, continuous ones as an axis and an offset. symba knows an
// asymmetric object, the cyclic group C_n of one axis through the object's
// origin, and the rotations about one such axis (docs/import.md has the
// table of what is mapped how).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "import/bop_files.h"
#include "symba/geometry/pi.h"

namespace symba::import_internal {
namespace {

constexpr double kDeg = kPi / 180.0;
// Rotations closer than this to the identity are the identity; axes closer
// than this are one axis; angles closer than this are one angle.
constexpr double kAngleTolerance = 2.0 * kDeg;
// Offsets below this (m) are zero: the axis passes through the origin.
constexpr double kOffsetTolerance = 1e-3;

// The sign of an axis that makes its largest component positive, so that
// one axis is always written the same way.
Eigen::Vector3d Canonical(const Eigen::Vector3d& axis) {
  Eigen::Index largest = 0;
  axis.cwiseAbs().maxCoeff(&largest);
  return axis[largest] < 0.0 ? Eigen::Vector3d(-axis) : axis;
}

// A distance in metres as "N mm" for a note; any double, however large.
std::string Millimetres(double metres) {
  std::ostringstream out;
  out.precision(metres < 1e3 ? 6 : 3);
  out << std::round(1000.0 * metres) << " mm";
  return out.str();
}

std::string Format(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(3);
  out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return out.str();
}

// The rotations about one axis, as angles in (0, 2 pi).
struct AxisGroup {
  Eigen::Vector3d axis;
  std::vector<double> angles;
};

// The order n of the cyclic group the angles form with the identity
// ({2 pi k / n, k = 1..n-1}), or 0 when they form none.
int CyclicOrder(std::vector<double> angles) {
  const int n = static_cast<int>(angles.size()) + 1;
  std::sort(angles.begin(), angles.end());
  for (int k = 1; k < n; ++k) {
    if (std::abs(angles[k - 1] - 2.0 * kPi * k / n) > kAngleTolerance) {
      return 0;
    }
  }
  return n;
}

// The largest cyclic subgroup the angles contain: the largest n such that
// every 2 pi k / n (k = 1..n-1) is among them (1 if none). Its generator
// 2 pi / n is one of the angles, so each angle a nominates n = 2 pi / a
// (rounded) and only those are checked, by binary search: O(N n log N)
// rather than trying every n up to N + 1.
int LargestCyclicSubgroup(std::vector<double> angles) {
  std::sort(angles.begin(), angles.end());
  auto contains = [&](double angle) {
    const auto it =
        std::lower_bound(angles.begin(), angles.end(), angle - kAngleTolerance);
    return it != angles.end() && *it <= angle + kAngleTolerance;
  };
  const long most = static_cast<long>(angles.size()) + 1;
  int best = 1;
  for (const double a : angles) {
    const long n = std::lround(2.0 * kPi / a);
    if (n <= best || n > most) continue;
    bool all = true;
    for (long k = 1; k < n && all; ++k) all = contains(2.0 * kPi * k / n);
    if (all) best = static_cast<int>(n);
  }
  return best;
}

std::vector<AxisGroup> GroupByAxis(const std::vector<Rigid3d>& discrete) {
  std::vector<AxisGroup> groups;
  for (const Rigid3d& T : discrete) {
    const Eigen::AngleAxisd aa(T.q);
    if (aa.angle() < kAngleTolerance) continue;  // the identity
    Eigen::Vector3d axis = aa.axis();
    double angle = aa.angle();
    const Eigen::Vector3d canonical = Canonical(axis);
    if (canonical.dot(axis) < 0.0) angle = 2.0 * kPi - angle;
    axis = canonical;
    auto same = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      return g.axis.dot(axis) >= std::cos(kAngleTolerance);
    });
    if (same == groups.end()) {
      groups.push_back({axis, {}});
      same = groups.end() - 1;
    }
    same->angles.push_back(angle);
  }
  return groups;
}

double LargestOffset(const std::vector<Rigid3d>& discrete) {
  double largest = 0.0;
  for (const Rigid3d& T : discrete) largest = std::max(largest, T.t.norm());
  return largest;
}

ClassPrior Continuous(const std::vector<BopContinuousSymmetry>& continuous,
                      int discrete_count,
                      std::string* note) {
  ClassPrior prior;
  prior.symmetry = SymmetryType::kContinuous;
  prior.axis_o = Canonical(continuous[0].axis);
  std::vector<std::string> parts;
  if (continuous.size() > 1) {
    parts.push_back(std::to_string(continuous.size()) +
                    " continuous axes: mapped to continuous about the first");
  }
  if (discrete_count > 0) {
    parts.push_back("continuous about " + Format(prior.axis_o) + " plus " +
                    std::to_string(discrete_count) +
                    " discrete symmetries: mapped to continuous about " +
                    Format(prior.axis_o) + "; the others are not modelled");
  }
  if (continuous[0].offset.norm() > kOffsetTolerance) {
    parts.push_back("its axis passes " +
                    Millimetres(continuous[0].offset.norm()) +
                    " from the model's origin, symba's through it");
  }
  for (const std::string& part : parts) {
    *note += (note->empty() ? "" : "; ") + part;
  }
  return prior;
}

}  // namespace

ClassPrior MapBopSymmetries(
    const std::vector<Rigid3d>& discrete,
    const std::vector<BopContinuousSymmetry>& continuous,
    std::string* note) {
  note->clear();
  if (!continuous.empty()) {
    return Continuous(continuous, static_cast<int>(discrete.size()), note);
  }
  ClassPrior prior;  // asymmetric
  const std::vector<AxisGroup> groups = GroupByAxis(discrete);
  if (groups.empty()) return prior;
  const double offset = LargestOffset(discrete);
  const std::string offset_note =
      offset > kOffsetTolerance
          ? "; its symmetries move the model's origin by up to " +
                Millimetres(offset) +
                " (the axis misses the origin, symba's passes through it)"
          : "";
  if (groups.size() == 1) {
    const int order = CyclicOrder(groups[0].angles);
    if (order >= 2) {
      prior.symmetry = SymmetryType::kDiscrete;
      prior.order = order;
      prior.axis_o = groups[0].axis;
      if (!offset_note.empty()) *note = offset_note.substr(2);
      return prior;
    }
  }
  // Not one cyclic group: the largest cyclic subgroup of one axis.
  int best_order = 1;
  Eigen::Vector3d best_axis = Eigen::Vector3d::Zero();
  for (const AxisGroup& group : groups) {
    const int order = LargestCyclicSubgroup(group.angles);
    if (order > best_order) {
      best_order = order;
      best_axis = group.axis;
    }
  }
  const std::string what =
      std::to_string(discrete.size()) +
      " discrete symmetries that are not the cyclic group of one axis";
  if (best_order < 2) {
    *note = what + ": mapped to asymmetric" + offset_note;
    return prior;
  }
  prior.symmetry = SymmetryType::kDiscrete;
  prior.order = best_order;
  prior.axis_o = best_axis;
  *note = what + ": mapped to discrete " + std::to_string(best_order) +
          " about " + Format(best_axis) + "; the others are not modelled" +
          offset_note;
  return prior;
}

}  // namespace symba::import_internal
