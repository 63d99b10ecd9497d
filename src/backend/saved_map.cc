// A map that lasts (docs/map-format.md): Backend::Impl::SaveMap and
// LoadMap, and the checks a map passes before anything is loaded.
#include <cmath>
#include <set>
#include <string>

#include "backend/backend_impl.h"
#include "backend/object_covariances.h"

namespace symba {
namespace {

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

bool Unit(const Eigen::Vector3d& v) {
  return v.allFinite() && std::abs(v.norm() - 1.0) <= 1e-3;
}

Status ObjectError(const MapObjectEstimate& o, const std::string& what) {
  return Status::Error("map object " + std::to_string(o.id) + ": " + what);
}

Status ValidateCovariance(const MapObjectEstimate& o) {
  const MapObjectCovariance& c = *o.covariance;
  const bool finite = c.position.allFinite() &&
                      (!c.rotation || c.rotation->allFinite()) &&
                      (!c.axis || c.axis->allFinite());
  if (!finite) return ObjectError(o, "covariance is not finite");
  for (const std::optional<double>& v : c.angle_variances) {
    if (v && !(std::isfinite(*v) && *v >= 0.0)) {
      return ObjectError(o, "angle variance is not a finite number >= 0");
    }
  }
  if (c.rotation && o.symmetry != SymmetryType::kAsymmetric) {
    return ObjectError(o,
                       "only an asymmetric object has a rotation covariance");
  }
  if (c.axis && o.symmetry == SymmetryType::kAsymmetric) {
    return ObjectError(o, "only a symmetric object has an axis covariance");
  }
  if (!c.angle_variances.empty() &&
      c.angle_variances.size() != o.angles.size()) {
    return ObjectError(o, "expected one angle variance per angle");
  }
  return Status::Ok();
}

Status ValidateObject(const MapObjectEstimate& o) {
  if (o.id < 0 || o.id >= kMaxMapObjectId) {
    return ObjectError(
        o, "id must be in [0, " + std::to_string(kMaxMapObjectId) + ")");
  }
  if (o.class_name.empty()) return ObjectError(o, "empty class name");
  if (!Finite(o.t_wo)) return ObjectError(o, "position is not finite");
  if (o.observations < 0) return ObjectError(o, "negative observations");
  const size_t poses =
      o.symmetry == SymmetryType::kDiscrete ? o.angles.size() : 1;
  if (o.poses.size() != poses || poses == 0) {
    return ObjectError(o,
                       o.symmetry == SymmetryType::kDiscrete
                           ? "expected one pose per angle (at least one)"
                           : "expected one pose");
  }
  for (const Rigid3d& pose : o.poses) {
    if (!pose.q.coeffs().allFinite() || std::abs(pose.q.norm() - 1.0) > 1e-3 ||
        !Finite(pose.t)) {
      return ObjectError(o, "pose is not finite or not a unit quaternion");
    }
  }
  if (o.symmetry != SymmetryType::kDiscrete && !o.angles.empty()) {
    return ObjectError(o, "only a discrete object has angles");
  }
  for (double angle : o.angles) {
    if (!std::isfinite(angle)) return ObjectError(o, "angle is not finite");
  }
  if (!o.angle_evidence.empty() && o.angle_evidence.size() != o.angles.size()) {
    return ObjectError(o, "expected no angle evidence or one per angle");
  }
  for (double evidence : o.angle_evidence) {
    if (!(std::isfinite(evidence) && evidence >= 0.0)) {
      return ObjectError(o, "angle evidence is not a finite number >= 0");
    }
  }
  if (o.symmetry != SymmetryType::kAsymmetric &&
      (!Unit(o.axis_w) || !Unit(o.axis_o))) {
    return ObjectError(o, "axis_w and axis_o must be unit vectors");
  }
  return o.covariance ? ValidateCovariance(o) : Status::Ok();
}

Status ValidateSavedMap(const SavedMap& map) {
  std::set<int> ids;
  for (const MapObjectEstimate& o : map.objects) {
    Status status = ValidateObject(o);
    if (!status.ok()) return status;
    if (!ids.insert(o.id).second) return ObjectError(o, "duplicate id");
  }
  std::set<std::string> classes;
  for (const SavedClassNoise& n : map.noise) {
    if (!classes.insert(n.class_name).second) {
      return Status::Error("map noise: class \"" + n.class_name +
                           "\" given twice");
    }
    for (const std::optional<double>& sigma :
         {n.sigma_t, n.sigma_r, n.white_sigma_t, n.white_sigma_r}) {
      if (sigma && !(std::isfinite(*sigma) && *sigma > 0.0)) {
        return Status::Error("map noise of class \"" + n.class_name +
                             "\": a sigma must be positive and finite");
      }
    }
    for (const std::optional<double>& factor :
         {n.claim_factor_t, n.claim_factor_r}) {
      if (factor && !(std::isfinite(*factor) && *factor >= 1.0)) {
        return Status::Error("map noise of class \"" + n.class_name +
                             "\": a claim factor must be finite and at "
                             "least 1");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Status Backend::Impl::SaveMap(SavedMap* map) {
  SavedMap saved;
  saved.objects = Objects();
  // The solve's covariances, not the world frame's (ObjectCovariances):
  // loaded, each becomes an object's prior of its own, and the cameras'
  // uncertainty that the world frame's adds is common to the map's objects
  // (it moves them together); as independent priors it would let them move
  // apart (docs/map-format.md).
  std::vector<MapObjectCovariance> covariances;
  if (internal::ObjectCovariances(map_.objects(), &graph_, &covariances).ok()) {
    for (MapObjectCovariance& c : covariances) {
      for (MapObjectEstimate& o : saved.objects) {
        if (o.id == c.id) o.covariance = std::move(c);
      }
    }
  }
  for (const auto& [name, noise] : edges_.applied_noise()) {
    SavedClassNoise n;
    n.class_name = name;
    n.sigma_t = noise.sigma_t;
    n.sigma_r = noise.sigma_r;
    n.white_sigma_t = noise.white_sigma_t;
    n.white_sigma_r = noise.white_sigma_r;
    n.claim_factor_t = noise.claim_scale_t;  // applied: the factors
    n.claim_factor_r = noise.claim_scale_r;
    saved.noise.push_back(std::move(n));
  }
  *map = std::move(saved);
  return Status::Ok();
}

void Backend::Impl::RestoreNoise(const std::vector<SavedClassNoise>& noise) {
  if (!options_.estimate_noise) return;
  for (const SavedClassNoise& n : noise) {
    // As the saving run last applied it; the run's own estimates take over
    // as they move away from it (ObjectEdges::ApplyNoise).
    internal::ClassNoise applied;
    applied.sigma_t = n.sigma_t;
    applied.sigma_r = n.sigma_r;
    applied.white_sigma_t = n.white_sigma_t;
    applied.white_sigma_r = n.white_sigma_r;
    applied.claim_scale_t = n.claim_factor_t;
    applied.claim_scale_r = n.claim_factor_r;
    edges_.RestoreNoise(n.class_name, applied);
  }
}

Status Backend::Impl::LoadMap(const SavedMap& map) {
  if (!trajectory_.keyframes().empty() || map_loaded_) {
    return Status::Error(
        "a map is loaded before the first keyframe, into an empty backend");
  }
  Status status = ValidateSavedMap(map);
  if (!status.ok()) return status;
  std::vector<const MapObjectEstimate*> by_id;
  for (const MapObjectEstimate& o : map.objects) by_id.push_back(&o);
  std::sort(by_id.begin(), by_id.end(), [](const auto* a, const auto* b) {
    return a->id < b->id;
  });
  for (const MapObjectEstimate* o : by_id) map_.Load(*o);
  RestoreNoise(map.noise);
  map_loaded_ = true;
  return Status::Ok();
}

}  // namespace symba
