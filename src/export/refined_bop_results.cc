#include "symba/export/refined_bop_results.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "io/text_file.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/swing_twist.h"
#include "symba/io/log_format.h"

namespace symba {
namespace {

// The geodesic angle between two rotations [rad].
double RotationDistance(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

// The hypothesis of highest weight (the first of equal ones).
const PoseHypothesis& BestHypothesis(const DetectionInput& detection) {
  const PoseHypothesis* best = &detection.hypotheses.front();
  for (const PoseHypothesis& h : detection.hypotheses) {
    if (h.weight > best->weight) best = &h;
  }
  return *best;
}

// N for a class named "obj_N" (N digits only, fitting an int).
std::optional<int> ObjIdFromName(const std::string& name) {
  const std::string prefix = "obj_";
  if (name.size() <= prefix.size() || name.compare(0, 4, prefix) != 0) {
    return std::nullopt;
  }
  const std::string_view digits = std::string_view(name).substr(4);
  if (digits.find_first_not_of("0123456789") != std::string_view::npos) {
    return std::nullopt;
  }
  int id = 0;
  if (!internal::ParseInteger(digits, &id)) return std::nullopt;
  return id;
}

// What turns the detections of one keyframe into rows: the replay's poses,
// objects and assignments, looked up by id.
class RowMaker {
 public:
  RowMaker(const ReplayResult& replay, int scene_id)
      : bop_(replay.header.bop),
        classes_(replay.header.classes),
        scene_id_(scene_id) {
    for (const KeyframeEstimate& k : replay.keyframes) T_wc_[k.id] = k.T_wc;
    for (const MapObjectEstimate& o : replay.objects) objects_[o.id] = &o;
    for (const DetectionAssignment& a : replay.assignments) {
      object_of_[{a.keyframe, a.detection}] = a.object;
    }
  }

  Status Add(const KeyframeInput& keyframe, std::vector<BopResult>* rows) {
    const auto pose = T_wc_.find(keyframe.id);
    if (pose == T_wc_.end()) {
      return Status::Error("keyframe " + std::to_string(keyframe.id) +
                           " is not in the replay");
    }
    const Rigid3d T_cw = pose->second.Inverse();
    for (const DetectionInput& detection : keyframe.detections) {
      const MapObjectEstimate* object = ObjectOf(keyframe.id, detection.id);
      if (object == nullptr) continue;
      BopResult row;
      Status status = ImId(keyframe.id, &row.im_id);
      if (status.ok()) status = ObjId(detection.class_name, &row.obj_id);
      if (!status.ok()) return status;
      row.scene_id = scene_id_;
      row.score = detection.score;
      const Rigid3d T_wo = ClosestSymmetricPose(*object,
                                                T_cw,
                                                BestHypothesis(detection).T_co,
                                                PriorOrder(object->class_name));
      row.T_co = T_cw * T_wo;
      rows->push_back(row);
    }
    return Status::Ok();
  }

 private:
  // The class prior's discrete order, 0 when there is none.
  int PriorOrder(const std::string& class_name) const {
    const auto it = classes_.find(class_name);
    return it != classes_.end() &&
                   it->second.symmetry == SymmetryType::kDiscrete
               ? it->second.order
               : 0;
  }

  // The map object a detection went to, or null (an outlier, or tentative).
  const MapObjectEstimate* ObjectOf(int64_t keyframe,
                                    const std::string& detection) const {
    const auto a = object_of_.find({keyframe, detection});
    if (a == object_of_.end() || a->second < 0) return nullptr;
    const auto o = objects_.find(a->second);
    return o == objects_.end() ? nullptr : o->second;
  }

  static Status ImId(int64_t keyframe, int* im_id) {
    if (keyframe < 0 || keyframe > std::numeric_limits<int>::max()) {
      return Status::Error("keyframe " + std::to_string(keyframe) +
                           ": not a BOP im_id (an integer from 0 to " +
                           std::to_string(std::numeric_limits<int>::max()) +
                           ")");
    }
    *im_id = static_cast<int>(keyframe);
    return Status::Ok();
  }

  Status ObjId(const std::string& class_name, int* obj_id) const {
    if (bop_) {
      const auto it = bop_->obj_ids.find(class_name);
      if (it != bop_->obj_ids.end()) {
        *obj_id = it->second;
        return Status::Ok();
      }
    }
    if (const std::optional<int> id = ObjIdFromName(class_name)) {
      *obj_id = *id;
      return Status::Ok();
    }
    return Status::Error("class \"" + class_name + "\": no BOP obj_id: " +
                         (bop_ ? "the log header's bop.obj_ids does not list it"
                               : "the log header has no \"bop\" key") +
                         " and the name is not obj_<id>");
  }

  const std::optional<BopSource>& bop_;
  const std::map<std::string, ClassPrior>& classes_;
  int scene_id_;
  std::map<int64_t, Rigid3d> T_wc_;
  std::map<int, const MapObjectEstimate*> objects_;
  std::map<std::pair<int64_t, std::string>, int> object_of_;
};

Status SceneId(const ReplayResult& replay,
               const RefinedBopResultsOptions& options,
               int* scene_id) {
  if (options.scene_id) {
    if (*options.scene_id < 0) {
      return Status::Error("scene id: must be a non-negative integer, got " +
                           std::to_string(*options.scene_id));
    }
    *scene_id = *options.scene_id;
    return Status::Ok();
  }
  if (replay.header.bop) {
    *scene_id = replay.header.bop->scene_id;
    return Status::Ok();
  }
  return Status::Error(
      "no BOP scene id: the log header has no \"bop\" key (symba import bop "
      "writes one); give the scene id (--bop-scene)");
}

}  // namespace

Rigid3d ClosestSymmetricPose(const MapObjectEstimate& object,
                             const Rigid3d& T_cw,
                             const Rigid3d& T_co_reference,
                             int order) {
  const Eigen::Quaterniond& q_ref = T_co_reference.q;
  if (object.poses.empty()) {  // not from the backend, which gives one
    return Rigid3d(Eigen::Quaterniond::Identity(), object.t_wo);
  }
  if (object.symmetry == SymmetryType::kContinuous) {
    // Turning the object about its world axis a_w through t_wo leaves it
    // unchanged: T_wo(phi) = (Rot(a_w, phi) R_wo0, t_wo), so
    // R_co(phi) = R_cw Rot(a_w, phi) R_wo0. The geodesic angle is
    // bi-invariant: angle(R_co(phi), R_ref) = angle(Rot(a_w, phi), N) with
    // N = R_cw^T R_ref R_wo0^T, and the rotation about a_w nearest to N is
    // N's twist about a_w (it maximises |<q_twist, q_N>|).
    const Rigid3d& base = object.poses.front();
    const Eigen::Quaterniond N =
        T_cw.q.conjugate() * q_ref * base.q.conjugate();
    const Eigen::Quaterniond twist =
        DecomposeSwingTwist(N.normalized(), object.axis_w).twist;
    return Rigid3d((twist * base.q).normalized(), object.t_wo);
  }
  // Asymmetric: one pose; discrete: one per angle, and with a known order
  // each turned by the symmetry, R_wo_i Rot(a_o, 2 pi m / order). Nearest
  // R_cw R_wo.
  const int turns =
      object.symmetry == SymmetryType::kDiscrete && order >= 2 ? order : 1;
  Rigid3d best = object.poses.front();
  double best_angle = std::numeric_limits<double>::infinity();
  for (const Rigid3d& T_wo : object.poses) {
    for (int m = 0; m < turns; ++m) {
      const Eigen::Quaterniond q_wo =
          m == 0 ? T_wo.q
                 : (T_wo.q * Eigen::Quaterniond(Eigen::AngleAxisd(
                                 kTwoPi * m / turns, object.axis_o)))
                       .normalized();
      const double angle = RotationDistance(T_cw.q * q_wo, q_ref);
      if (angle < best_angle) {
        best_angle = angle;
        best = Rigid3d(q_wo, T_wo.t);
      }
    }
  }
  return best;
}

Status RefinedBopResults(const ReplayResult& replay,
                         const std::vector<KeyframeInput>& keyframes,
                         const RefinedBopResultsOptions& options,
                         std::vector<BopResult>* rows) {
  rows->clear();
  int scene_id = 0;
  Status status = SceneId(replay, options, &scene_id);
  if (!status.ok()) return status;
  RowMaker maker(replay, scene_id);
  for (const KeyframeInput& keyframe : keyframes) {
    status = maker.Add(keyframe, rows);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

Status RefinedBopResultsFromLog(const std::string& log_path,
                                const ReplayResult& replay,
                                const RefinedBopResultsOptions& options,
                                std::vector<BopResult>* rows) {
  rows->clear();
  int scene_id = 0;
  Status status = SceneId(replay, options, &scene_id);
  if (!status.ok()) return status;
  std::unique_ptr<LogReader> reader;
  status = LogReader::Open(log_path, &reader);
  if (!status.ok()) return status;
  RowMaker maker(replay, scene_id);
  KeyframeInput keyframe;
  for (;;) {
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (!status.ok() || end) return status;
    status = maker.Add(keyframe, rows);
    if (!status.ok()) {
      return Status::Error(log_path + ":" + std::to_string(reader->line()) +
                           ": " + status.message());
    }
  }
}

}  // namespace symba
