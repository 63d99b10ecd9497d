#include "symba/matching/constellation_match.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include <Eigen/SVD>

#include "symba/geometry/pi.h"
#include "symba/matching/maximal_cliques.h"

namespace symba {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// What the matcher reads of one object: its position, the rotations it may
// have (one for an asymmetric object; for a discrete one of known order,
// each pose turned by 2 pi m / order about its axis; none otherwise) and
// its axis as a line (symmetric objects: its sign is arbitrary).
struct Feature {
  ObjectId id = 0;
  const std::string* class_name = nullptr;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  Vector3d position = Vector3d::Zero();
  std::vector<Matrix3d> rotations;
  std::optional<Vector3d> axis;
  double sigma = 0.0;  // m, isotropic position standard deviation
};

// The symmetry order of a discrete object: its class's where known, else
// the one its upgrade found (0: unknown).
int OrderOf(const MapObjectEstimate& object,
            const std::map<std::string, int>& orders) {
  const auto it = orders.find(object.class_name);
  if (it != orders.end() && it->second >= 2) return it->second;
  if (object.upgrade && object.upgrade->order >= 2) {
    return object.upgrade->order;
  }
  return 0;
}

Feature ToFeature(const MapObjectEstimate& object,
                  const std::map<std::string, int>& orders) {
  Feature feature;
  feature.id = object.id;
  feature.class_name = &object.class_name;
  feature.symmetry = object.symmetry;
  feature.position = object.t_wo;
  if (object.symmetry == SymmetryType::kAsymmetric && !object.poses.empty()) {
    feature.rotations.push_back(
        object.poses.front().q.normalized().toRotationMatrix());
  }
  const int order = OrderOf(object, orders);
  if (object.symmetry == SymmetryType::kDiscrete && order >= 2 &&
      object.axis_o.norm() > 0.5) {
    const Vector3d a_o = object.axis_o.normalized();
    for (const Rigid3d& pose : object.poses) {
      const Matrix3d R = pose.q.normalized().toRotationMatrix();
      for (int m = 0; m < order; ++m) {
        const double turn = 2.0 * kPi * m / order;
        feature.rotations.push_back(
            R * Eigen::AngleAxisd(turn, a_o).toRotationMatrix());
      }
    }
  }
  if (object.symmetry != SymmetryType::kAsymmetric &&
      object.axis_w.norm() > 0.5) {
    feature.axis = object.axis_w.normalized();
  }
  if (object.covariance) {
    const double trace = object.covariance->position.trace();
    if (std::isfinite(trace) && trace > 0.0) {
      feature.sigma = std::sqrt(trace / 3.0);
    }
  }
  return feature;
}

// Same class; continuous objects pair with continuous ones only.
bool Compatible(const Feature& local, const Feature& map) {
  if (*local.class_name != *map.class_name) return false;
  return (local.symmetry == SymmetryType::kContinuous) ==
         (map.symmetry == SymmetryType::kContinuous);
}

double RotationAngle(const Matrix3d& a, const Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// The angle between two lines through the origin, in [0, pi / 2].
double LineAngle(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
}

// The smallest angle between R * (a rotation of `local`) and a rotation
// of `map`; the indices of that pair in `*local_pose` / `*map_pose`.
double ClosestRotation(const Matrix3d& R,
                       const Feature& local,
                       const Feature& map,
                       int* local_pose = nullptr,
                       int* map_pose = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < local.rotations.size(); ++a) {
    for (std::size_t b = 0; b < map.rotations.size(); ++b) {
      const double angle =
          RotationAngle(R * local.rotations[a], map.rotations[b]);
      if (angle < best) {
        best = angle;
        if (local_pose) *local_pose = static_cast<int>(a);
        if (map_pose) *map_pose = static_cast<int>(b);
      }
    }
  }
  return best;
}

struct Candidate {
  int local = 0;
  int map = 0;
};

class Matcher {
 public:
  Matcher(std::vector<Feature> local,
          std::vector<Feature> map,
          const ConstellationMatchOptions& options)
      : local_(std::move(local)), map_(std::move(map)), options_(options) {}

  ConstellationMatchResult Run() {
    ConstellationMatchResult result;
    FindCandidates();
    result.candidates = static_cast<int>(candidates_.size());
    if (result.candidates > options_.max_candidates) {
      result.outcome = ConstellationMatchResult::Outcome::kTooLarge;
      return result;
    }
    if (result.candidates < options_.min_support) {
      result.outcome = ConstellationMatchResult::Outcome::kTooFewCandidates;
      return result;
    }
    const CliqueSearchResult cliques = MaximalCliques(
        ConsistencyGraph(), {options_.min_support, options_.max_cliques});
    result.cliques = static_cast<int>(cliques.cliques.size());
    if (cliques.truncated) {
      // Another transform may be as well supported as any found.
      result.outcome = ConstellationMatchResult::Outcome::kTooManyCliques;
      return result;
    }
    std::vector<Hypothesis> hypotheses;
    for (const std::vector<int>& clique : cliques.cliques) {
      std::optional<Hypothesis> hypothesis = Verify(clique);
      if (hypothesis) hypotheses.push_back(std::move(*hypothesis));
    }
    return Decide(hypotheses, result);
  }

 private:
  // A transform and the candidates it explains.
  struct Hypothesis {
    Rigid3d T;
    std::vector<int> support;  // candidate indices
    double rmse = 0.0;
  };

  void FindCandidates() {
    for (std::size_t i = 0; i < local_.size(); ++i) {
      for (std::size_t j = 0; j < map_.size(); ++j) {
        if (Compatible(local_[i], map_[j])) {
          candidates_.push_back({static_cast<int>(i), static_cast<int>(j)});
        }
      }
    }
  }

  AdjacencyMatrix ConsistencyGraph() const {
    const std::size_t n = candidates_.size();
    AdjacencyMatrix adjacency(n, std::vector<bool>(n, false));
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t b = a + 1; b < n; ++b) {
        const bool consistent = Consistent(candidates_[a], candidates_[b]);
        adjacency[a][b] = consistent;
        adjacency[b][a] = consistent;
      }
    }
    return adjacency;
  }

  double PositionGate(double distance, double sigma_sq) const {
    return options_.position_gate + options_.relative_position_gate * distance +
           3.0 * std::sqrt(sigma_sq);
  }

  // Whether two candidates can both hold under one rigid transform.
  bool Consistent(const Candidate& a, const Candidate& b) const {
    if (a.local == b.local || a.map == b.map) return false;
    const Feature& la = local_[static_cast<std::size_t>(a.local)];
    const Feature& lb = local_[static_cast<std::size_t>(b.local)];
    const Feature& ma = map_[static_cast<std::size_t>(a.map)];
    const Feature& mb = map_[static_cast<std::size_t>(b.map)];
    const Vector3d d_local = lb.position - la.position;
    const Vector3d d_map = mb.position - ma.position;
    const double distance = 0.5 * (d_local.norm() + d_map.norm());
    const double sigma_sq = la.sigma * la.sigma + lb.sigma * lb.sigma +
                            ma.sigma * ma.sigma + mb.sigma * mb.sigma;
    const double gate = PositionGate(distance, sigma_sq);
    if (std::abs(d_local.norm() - d_map.norm()) > gate) return false;
    const double turned_gate = gate + options_.angle_gate * distance;
    if (!DisplacementAgrees(la, ma, d_local, d_map, turned_gate) ||
        !DisplacementAgrees(lb, mb, -d_local, -d_map, turned_gate)) {
      return false;
    }
    if (la.axis && lb.axis && ma.axis && mb.axis) {
      const double local_angle = LineAngle(*la.axis, *lb.axis);
      const double map_angle = LineAngle(*ma.axis, *mb.axis);
      if (std::abs(local_angle - map_angle) > 2.0 * options_.angle_gate) {
        return false;
      }
    }
    if (la.rotations.size() == 1 && lb.rotations.size() == 1 &&
        ma.rotations.size() == 1 && mb.rotations.size() == 1) {
      const Matrix3d local_relative =
          la.rotations[0].transpose() * lb.rotations[0];
      const Matrix3d map_relative =
          ma.rotations[0].transpose() * mb.rotations[0];
      if (RotationAngle(local_relative, map_relative) >
          2.0 * options_.angle_gate) {
        return false;
      }
    }
    return true;
  }

  // The displacement to the other object seen from this object's own
  // frame (modulo its symmetry) or along its axis, in both frames.
  static bool DisplacementAgrees(const Feature& local,
                                 const Feature& map,
                                 const Vector3d& d_local,
                                 const Vector3d& d_map,
                                 double gate) {
    if (!local.rotations.empty() && !map.rotations.empty()) {
      for (const Matrix3d& R_local : local.rotations) {
        for (const Matrix3d& R_map : map.rotations) {
          if ((R_local.transpose() * d_local - R_map.transpose() * d_map)
                  .norm() <= gate) {
            return true;
          }
        }
      }
      return false;
    }
    if (local.axis && map.axis) {
      return std::abs(std::abs(local.axis->dot(d_local)) -
                      std::abs(map.axis->dot(d_map))) <= gate;
    }
    return true;
  }

  using Pairs = std::vector<std::pair<Vector3d, Vector3d>>;

  // Weighted Kabsch: the rotation R minimising sum |R u - v|^2 over the
  // pairs (u, v); nullopt when the pairs leave it undetermined (the second
  // singular value of sum u v^T below 5 % of the first).
  static std::optional<Matrix3d> Kabsch(const Pairs& pairs) {
    Matrix3d H = Matrix3d::Zero();
    for (const auto& [u, v] : pairs) H += u * v.transpose();
    const Eigen::JacobiSVD<Matrix3d> svd(
        H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Vector3d s = svd.singularValues();
    if (!(s(0) > 0.0) || s(1) < 0.05 * s(0)) return std::nullopt;
    Matrix3d fix = Matrix3d::Identity();
    fix(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0
                    ? -1.0
                    : 1.0;
    return svd.matrixV() * fix * svd.matrixU().transpose();
  }

  // The transform of a set of candidates (weighted Kabsch). First from
  // what has no ambiguity: the positions about their centroids (scaled by
  // their spread, so that they weigh like the unit directions) and the
  // columns of single rotations; if that leaves the rotation free, also
  // from the axes with their signs made to agree, both relative signs
  // tried. Then each axis's sign and each discrete object's pose are the
  // ones closest under that fit, and the fit is made again with them.
  std::optional<Rigid3d> EstimateTransform(
      const std::vector<int>& subset) const {
    Vector3d c_local = Vector3d::Zero();
    Vector3d c_map = Vector3d::Zero();
    for (int index : subset) {
      c_local += LocalOf(index).position;
      c_map += MapOf(index).position;
    }
    c_local /= static_cast<double>(subset.size());
    c_map /= static_cast<double>(subset.size());
    double spread_sq = 0.0;
    for (int index : subset) {
      spread_sq += (LocalOf(index).position - c_local).squaredNorm() +
                   (MapOf(index).position - c_map).squaredNorm();
    }
    const double spread =
        std::sqrt(spread_sq / (2.0 * static_cast<double>(subset.size())));
    Pairs fixed;
    for (int index : subset) {
      const Feature& l = LocalOf(index);
      const Feature& m = MapOf(index);
      if (spread > 1e-9) {
        fixed.emplace_back((l.position - c_local) / spread,
                           (m.position - c_map) / spread);
      }
      if (l.rotations.size() == 1 && m.rotations.size() == 1) {
        AddRotationColumns(l.rotations[0], m.rotations[0], &fixed);
      }
    }
    std::optional<Matrix3d> first = Kabsch(fixed);
    if (!first) first = FitWithAlignedAxes(subset, fixed);
    if (!first) return std::nullopt;  // the rotation about some axis free
    Pairs pairs = fixed;
    for (int index : subset) {
      const Feature& l = LocalOf(index);
      const Feature& m = MapOf(index);
      if (l.axis && m.axis) {
        const double sign = (*first * *l.axis).dot(*m.axis) < 0.0 ? -1.0 : 1.0;
        pairs.emplace_back(sign * *l.axis, *m.axis);
      }
      const bool single = l.rotations.size() == 1 && m.rotations.size() == 1;
      if (!single && !l.rotations.empty() && !m.rotations.empty()) {
        int a = 0;
        int b = 0;
        ClosestRotation(*first, l, m, &a, &b);
        AddRotationColumns(l.rotations[static_cast<std::size_t>(a)],
                           m.rotations[static_cast<std::size_t>(b)],
                           &pairs);
      }
    }
    const Matrix3d R = Kabsch(pairs).value_or(*first);
    return Rigid3d(Eigen::Quaterniond(R).normalized(), c_map - R * c_local);
  }

  // Positions and single rotations leave the rotation free: the axes, each
  // made to agree in sign with the first one of its side, in both relative
  // signs; the determined fit with the smaller residual.
  std::optional<Matrix3d> FitWithAlignedAxes(const std::vector<int>& subset,
                                             const Pairs& fixed) const {
    std::optional<Vector3d> first_local;
    std::optional<Vector3d> first_map;
    Pairs axes;
    for (int index : subset) {
      const Feature& l = LocalOf(index);
      const Feature& m = MapOf(index);
      if (!l.axis || !m.axis) continue;
      if (!first_local) {
        first_local = *l.axis;
        first_map = *m.axis;
      }
      axes.emplace_back(l.axis->dot(*first_local) < 0.0 ? -*l.axis : *l.axis,
                        m.axis->dot(*first_map) < 0.0 ? -*m.axis : *m.axis);
    }
    if (axes.empty()) return std::nullopt;
    std::optional<Matrix3d> best;
    double best_residual = std::numeric_limits<double>::infinity();
    for (double sign : {1.0, -1.0}) {
      Pairs pairs = fixed;
      for (const auto& [u, v] : axes) pairs.emplace_back(sign * u, v);
      const std::optional<Matrix3d> R = Kabsch(pairs);
      if (!R) continue;
      double residual = 0.0;
      for (const auto& [u, v] : pairs) residual += (*R * u - v).squaredNorm();
      if (residual < best_residual) {
        best = R;
        best_residual = residual;
      }
    }
    return best;
  }

  static void AddRotationColumns(const Matrix3d& local,
                                 const Matrix3d& map,
                                 Pairs* pairs) {
    for (int c = 0; c < 3; ++c) {
      pairs->emplace_back(local.col(c), map.col(c));
    }
  }

  // Whether `T` explains candidate `index`: its position within the gate,
  // its rotation (modulo symmetry) or axis within the angle gate.
  bool Explains(const Rigid3d& T, int index, double* squared_error) const {
    const Feature& l = LocalOf(index);
    const Feature& m = MapOf(index);
    const double error = (T * l.position - m.position).norm();
    if (error > PositionGate(0.0, l.sigma * l.sigma + m.sigma * m.sigma)) {
      return false;
    }
    const Matrix3d R = T.q.toRotationMatrix();
    if (!l.rotations.empty() &&
        ClosestRotation(R, l, m) > options_.angle_gate) {
      return false;
    }
    if (l.axis && m.axis &&
        LineAngle(R * *l.axis, *m.axis) > options_.angle_gate) {
      return false;
    }
    *squared_error = error * error;
    return true;
  }

  // A clique's transform, refined on the candidates it explains until they
  // no longer change; nullopt if fewer than min_support remain.
  std::optional<Hypothesis> Verify(const std::vector<int>& clique) const {
    std::vector<int> subset = clique;
    for (int iteration = 0; iteration < 3; ++iteration) {
      const std::optional<Rigid3d> T = EstimateTransform(subset);
      if (!T) return std::nullopt;
      Hypothesis hypothesis;
      hypothesis.T = *T;
      double sum_sq = 0.0;
      for (int index : clique) {
        double squared_error = 0.0;
        if (Explains(*T, index, &squared_error)) {
          hypothesis.support.push_back(index);
          sum_sq += squared_error;
        }
      }
      if (static_cast<int>(hypothesis.support.size()) < options_.min_support) {
        return std::nullopt;
      }
      hypothesis.rmse =
          std::sqrt(sum_sq / static_cast<double>(hypothesis.support.size()));
      if (hypothesis.support == subset) return hypothesis;
      subset = hypothesis.support;
    }
    return std::nullopt;  // did not settle
  }

  bool SameTransform(const Hypothesis& a, const Hypothesis& b) const {
    if (a.T.q.angularDistance(b.T.q) > options_.angle_gate) return false;
    for (int index : a.support) {
      const Vector3d& p = LocalOf(index).position;
      if ((a.T * p - b.T * p).norm() > options_.position_gate) return false;
    }
    return true;
  }

  ConstellationMatchResult Decide(std::vector<Hypothesis>& hypotheses,
                                  ConstellationMatchResult result) const {
    if (hypotheses.empty()) {
      result.outcome = ConstellationMatchResult::Outcome::kNoConsistentSet;
      return result;
    }
    std::sort(hypotheses.begin(),
              hypotheses.end(),
              [](const Hypothesis& a, const Hypothesis& b) {
                if (a.support.size() != b.support.size()) {
                  return a.support.size() > b.support.size();
                }
                return a.rmse < b.rmse;
              });
    const Hypothesis& best = hypotheses.front();
    for (const Hypothesis& other : hypotheses) {
      if (!SameTransform(best, other)) {
        result.runner_up_support = static_cast<int>(other.support.size());
        break;
      }
    }
    const int best_support = static_cast<int>(best.support.size());
    if (result.runner_up_support >= options_.min_support &&
        result.runner_up_support >= best_support - options_.ambiguity_margin) {
      result.outcome = ConstellationMatchResult::Outcome::kAmbiguous;
      return result;
    }
    ConstellationMatch match;
    match.T_map_local = best.T;
    match.position_rmse = best.rmse;
    for (int index : best.support) {
      match.correspondences.push_back({LocalOf(index).id, MapOf(index).id});
    }
    std::sort(match.correspondences.begin(),
              match.correspondences.end(),
              [](const ObjectCorrespondence& a, const ObjectCorrespondence& b) {
                return a.local < b.local;
              });
    result.outcome = ConstellationMatchResult::Outcome::kMatched;
    result.match = std::move(match);
    return result;
  }

  const Feature& LocalOf(int candidate) const {
    return local_[static_cast<std::size_t>(
        candidates_[static_cast<std::size_t>(candidate)].local)];
  }
  const Feature& MapOf(int candidate) const {
    return map_[static_cast<std::size_t>(
        candidates_[static_cast<std::size_t>(candidate)].map)];
  }

  std::vector<Feature> local_;
  std::vector<Feature> map_;
  const ConstellationMatchOptions& options_;
  std::vector<Candidate> candidates_;
};

std::vector<Feature> ToFeatures(const std::vector<MapObjectEstimate>& objects,
                                const std::map<std::string, int>& orders) {
  std::vector<Feature> features;
  features.reserve(objects.size());
  for (const MapObjectEstimate& object : objects) {
    features.push_back(ToFeature(object, orders));
  }
  return features;
}

}  // namespace

const char* ToString(ConstellationMatchResult::Outcome outcome) {
  switch (outcome) {
    case ConstellationMatchResult::Outcome::kMatched:
      return "matched";
    case ConstellationMatchResult::Outcome::kTooFewCandidates:
      return "too few candidates";
    case ConstellationMatchResult::Outcome::kNoConsistentSet:
      return "no consistent set";
    case ConstellationMatchResult::Outcome::kAmbiguous:
      return "ambiguous";
    case ConstellationMatchResult::Outcome::kTooLarge:
      return "too many candidates";
    case ConstellationMatchResult::Outcome::kTooManyCliques:
      return "too many cliques";
  }
  return "unknown";
}

ConstellationMatchResult MatchConstellation(
    const std::vector<MapObjectEstimate>& local,
    const std::vector<MapObjectEstimate>& map,
    const ConstellationMatchOptions& options) {
  return Matcher(ToFeatures(local, options.symmetry_orders),
                 ToFeatures(map, options.symmetry_orders),
                 options)
      .Run();
}

}  // namespace symba
