// The simulator: trajectory, front end, map points and multi-hypothesis
// detections of a scene (include/symba/simulation/simulator.h).
#include "symba/simulation/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "simulation/trajectory.h"
#include "symba/backend/estimates.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/io/file_output.h"
#include "symba/io/ground_truth_objects.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

// Every random number of a simulation comes from one engine, through these
// draws. Normal and Uniform scale a standard draw, so a zero sigma or an
// empty interval still consumes the engine the same way (changing one
// noise level does not reshuffle the rest of the sequence's draws).
class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}

  double Uniform01() { return uniform_(engine_); }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(); }
  double Normal(double sigma) { return sigma * normal_(engine_); }
  Eigen::Vector3d NormalVector(double sigma) {
    const double x = Normal(sigma);
    const double y = Normal(sigma);
    const double z = Normal(sigma);
    return Eigen::Vector3d(x, y, z);
  }
  bool Bernoulli(double p) { return Uniform01() < p; }
  // Uniform in [0, n).
  int Index(int n) {
    return std::uniform_int_distribution<int>(0, n - 1)(engine_);
  }
  // Uniform on SO(3): a normalised 4-D Gaussian.
  Eigen::Quaterniond Rotation() {
    Eigen::Vector4d v;
    do {
      for (int i = 0; i < 4; ++i) v[i] = normal_(engine_);
    } while (v.squaredNorm() < 1e-12);
    v.normalize();
    return Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
  }
  // Small pose error (Exp(n_r), n_t) with isotropic sigmas.
  Rigid3d PoseNoise(double sigma_t, double sigma_r) {
    const Eigen::Vector3d n_r = NormalVector(sigma_r);
    const Eigen::Vector3d n_t = NormalVector(sigma_t);
    return Rigid3d(ExpSO3<double>(n_r), n_t);
  }
  template <typename T>
  void Shuffle(std::vector<T>* values) {
    for (int i = static_cast<int>(values->size()) - 1; i > 0; --i) {
      std::swap((*values)[i], (*values)[Index(i + 1)]);
    }
  }

 private:
  std::mt19937 engine_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// Camera at `eye` looking at `target`, world z up: camera z forward, x right
// (horizontal), y down.
Rigid3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_wc;
  R_wc << x, y, z;
  return Rigid3d(Eigen::Quaterniond(R_wc).normalized(), eye);
}

// Whether `angle` lies in [start, start + arc) modulo 2 pi; a keyframe that
// lands on the end of the arc up to rounding is outside, one on its start
// inside.
bool InArc(double angle, double start, double arc) {
  constexpr double kEps = 1e-9;
  double d = std::fmod(angle - start, kTwoPi);
  if (d < 0.0) d += kTwoPi;
  if (d > kTwoPi - kEps) d = 0.0;
  return d < arc - kEps;
}

// Pinhole projection; false if behind `min_depth`.
bool Project(const PinholeIntrinsics& K,
             const Eigen::Vector3d& p_c,
             double min_depth,
             Eigen::Vector2d* uv) {
  if (!(p_c.z() >= min_depth)) return false;
  *uv = Eigen::Vector2d(K.fx * p_c.x() / p_c.z() + K.cx,
                        K.fy * p_c.y() / p_c.z() + K.cy);
  return true;
}

bool InImage(const SimulationOptions& options, const Eigen::Vector2d& uv) {
  return uv.x() >= 0.0 && uv.x() < options.image_width && uv.y() >= 0.0 &&
         uv.y() < options.image_height;
}

// The visible modes of one view of a k-fold object, ascending.
std::vector<int> DrawVisibleModes(const SimulationOptions& options,
                                  int order,
                                  Random* random) {
  std::vector<int> modes(order);
  for (int m = 0; m < order; ++m) modes[m] = m;
  const bool subset = random->Bernoulli(options.subset_view_probability);
  if (subset && order >= 2) {
    const int count = 1 + random->Index(order - 1);  // 1 .. order-1
    random->Shuffle(&modes);
    modes.resize(count);
    std::sort(modes.begin(), modes.end());
  }
  return modes;
}

// A detection of `object` without hypotheses: class and claimed noise.
DetectionInput EmptyDetection(const SimulationOptions& options,
                              const SimulatedObject& object) {
  DetectionInput detection;
  detection.class_name = object.class_name;
  if (options.write_detection_sigmas) {
    if (options.translation_sigma > 0.0) {
      detection.sigma_t = options.translation_sigma;
    }
    if (options.rotation_sigma > 0.0) {
      detection.sigma_r = options.rotation_sigma;
    }
  }
  return detection;
}

// The view's dominant mode of a k-fold object: a random one of `visible`,
// or the previous view's with dominant_mode_persistence if still visible.
int DrawDominantMode(const SimulationOptions& options,
                     const std::vector<int>& visible,
                     int previous_dominant,
                     Random* random) {
  const bool keep = random->Bernoulli(options.dominant_mode_persistence);
  const int drawn = visible[random->Index(static_cast<int>(visible.size()))];
  const bool previous_visible =
      std::find(visible.begin(), visible.end(), previous_dominant) !=
      visible.end();
  return keep && previous_visible ? previous_dominant : drawn;
}

// An inlier hypothesis at angle phi about a_o, with the inlier noise:
// T_co (Rot(a_o, phi), 0) (Exp(r), s).
Rigid3d InlierPose(const SimulationOptions& options,
                   const Rigid3d& T_co,
                   const Eigen::Vector3d& a_o,
                   double phi,
                   Random* random) {
  const Eigen::Vector3d r = random->NormalVector(options.rotation_sigma);
  const Eigen::Vector3d s = random->NormalVector(options.translation_sigma);
  const Eigen::Quaterniond q = T_co.q *
                               Eigen::Quaterniond(Eigen::AngleAxisd(phi, a_o)) *
                               ExpSO3<double>(r);
  return Rigid3d(q.normalized(), T_co.t + s);
}

// An outlier hypothesis: any rotation, the translation blurred.
Rigid3d OutlierPose(const SimulationOptions& options,
                    const Rigid3d& T_co,
                    Random* random) {
  const Eigen::Quaterniond q = random->Rotation();
  const Eigen::Vector3d s =
      random->NormalVector(options.outlier_translation_sigma);
  return Rigid3d(q, T_co.t + s);
}

double JitteredWeight(const SimulationOptions& options,
                      double base,
                      Random* random) {
  return base *
         (1.0 + random->Uniform(-options.weight_jitter, options.weight_jitter));
}

// The single-hypothesis detector (SimulationOptions::single_hypothesis).
DetectionInput GenerateSinglePoseDetection(const SimulationOptions& options,
                                           const SimulatedObject& object,
                                           const Rigid3d& T_co,
                                           int previous_dominant,
                                           Random* random,
                                           SimulatedDetectionTruth* truth) {
  const Eigen::Vector3d a_o = object.axis_o.normalized();
  truth->visible_modes = {0};
  truth->dominant_mode = 0;
  double phi = 0.0;
  if (object.symmetry == SymmetryType::kDiscrete) {
    truth->visible_modes.resize(object.order);
    for (int m = 0; m < object.order; ++m) truth->visible_modes[m] = m;
    truth->dominant_mode = DrawDominantMode(
        options, truth->visible_modes, previous_dominant, random);
    phi = WrapToPi(kTwoPi * truth->dominant_mode / object.order);
  } else if (object.symmetry == SymmetryType::kContinuous) {
    phi = WrapToPi(random->Uniform(-0.5, 0.5) * options.continuous_arc);
  }
  PoseHypothesis h;
  const bool outlier = random->Bernoulli(options.outlier_fraction);
  if (outlier) {
    h.T_co = OutlierPose(options, T_co, random);
  } else {
    h.T_co = InlierPose(options, T_co, a_o, phi, random);
  }
  h.weight = JitteredWeight(options, options.dominant_weight, random);
  truth->hypothesis_mode = {outlier ? -1 : truth->dominant_mode};
  truth->hypothesis_angle = {outlier ? 0.0 : phi};
  DetectionInput detection = EmptyDetection(options, object);
  detection.hypotheses.push_back(h);
  return detection;
}

// One detection of `object` seen from T_wc. `previous_dominant` is the
// dominant mode of the previous view of this object (-1: none).
DetectionInput GenerateDetection(const SimulationOptions& options,
                                 const SimulatedObject& object,
                                 const Rigid3d& T_wc,
                                 int previous_dominant,
                                 Random* random,
                                 SimulatedDetectionTruth* truth) {
  const Rigid3d T_co = T_wc.Inverse() * object.T_wo;
  if (options.single_hypothesis) {
    return GenerateSinglePoseDetection(
        options, object, T_co, previous_dominant, random, truth);
  }
  const Eigen::Vector3d a_o = object.axis_o.normalized();
  const bool discrete = object.symmetry == SymmetryType::kDiscrete;
  const bool continuous = object.symmetry == SymmetryType::kContinuous;

  truth->visible_modes = {0};
  truth->dominant_mode = 0;
  if (discrete) {
    truth->visible_modes = DrawVisibleModes(options, object.order, random);
    truth->dominant_mode = DrawDominantMode(
        options, truth->visible_modes, previous_dominant, random);
  }
  const double phi_dominant =
      continuous
          ? random->Uniform(-0.5, 0.5) * options.continuous_dominant_spread
          : 0.0;

  const int n = options.num_hypotheses;
  const int num_outliers =
      static_cast<int>(std::lround(options.outlier_fraction * n));
  const int num_inliers = n - num_outliers;
  const int num_visible = static_cast<int>(truth->visible_modes.size());

  DetectionInput detection = EmptyDetection(options, object);
  truth->hypothesis_mode.clear();
  truth->hypothesis_angle.clear();
  for (int j = 0; j < n; ++j) {
    PoseHypothesis h;
    bool dominant = false;
    if (j < num_inliers) {
      int mode = 0;
      double phi = 0.0;
      if (discrete) {
        mode = truth->visible_modes[j % num_visible];
        phi = WrapToPi(kTwoPi * mode / object.order);
        dominant = mode == truth->dominant_mode;
      } else if (continuous) {
        phi = j == 0 ? phi_dominant
                     : WrapToPi(phi_dominant + random->Uniform(-0.5, 0.5) *
                                                   options.continuous_arc);
        dominant = j == 0;
      } else {
        dominant = true;
      }
      h.T_co = InlierPose(options, T_co, a_o, phi, random);
      truth->hypothesis_mode.push_back(mode);
      truth->hypothesis_angle.push_back(phi);
    } else {
      h.T_co = OutlierPose(options, T_co, random);
      truth->hypothesis_mode.push_back(-1);
      truth->hypothesis_angle.push_back(0.0);
    }
    h.weight = JitteredWeight(
        options,
        dominant ? options.dominant_weight : options.other_weight,
        random);
    detection.hypotheses.push_back(h);
  }
  // Shuffle hypotheses and their truth together.
  for (int i = n - 1; i > 0; --i) {
    const int k = random->Index(i + 1);
    std::swap(detection.hypotheses[i], detection.hypotheses[k]);
    std::swap(truth->hypothesis_mode[i], truth->hypothesis_mode[k]);
    std::swap(truth->hypothesis_angle[i], truth->hypothesis_angle[k]);
  }
  return detection;
}

// `count` points on a vertical cylinder of `radius` about `centre`, on the
// arc that faces the rich bearings (the rich arc turned by pi).
void AddWallPoints(const SimulationOptions& options,
                   const Eigen::Vector2d& centre,
                   double radius,
                   int count,
                   Random* random,
                   std::vector<Eigen::Vector3d>* points_w) {
  const double wall_start = options.rich_arc_start + kPi;
  for (int i = 0; i < count; ++i) {
    const double angle = wall_start + options.rich_arc * random->Uniform01();
    const double z = random->Uniform(options.wall_z_min, options.wall_z_max);
    points_w->emplace_back(centre.x() + radius * std::cos(angle),
                           centre.y() + radius * std::sin(angle),
                           z);
  }
}

// The textured walls: one about the origin for an orbit scene, one about
// every place for a route scene.
std::vector<Eigen::Vector3d> WallPoints(const Scene& scene,
                                        const SimulationOptions& options,
                                        Random* random) {
  std::vector<Eigen::Vector3d> points_w;
  if (scene.places.empty()) {
    AddWallPoints(options,
                  Eigen::Vector2d::Zero(),
                  options.wall_radius,
                  options.num_points,
                  random,
                  &points_w);
  }
  for (const Eigen::Vector2d& centre : scene.places) {
    AddWallPoints(options,
                  centre,
                  options.place_wall_radius,
                  options.points_per_place,
                  random,
                  &points_w);
  }
  return points_w;
}

// The index range [first, last) of the points the front end tracks from
// `view`: all of them on the orbit, the wall of the place looked at on a
// route (WallPoints adds points_per_place points per place, in order).
std::pair<size_t, size_t> TrackedPoints(const SimulationOptions& options,
                                        const CameraView& view,
                                        size_t num_points) {
  if (view.place < 0) return {0, num_points};
  const size_t per_place = static_cast<size_t>(options.points_per_place);
  const size_t first = static_cast<size_t>(view.place) * per_place;
  return {first, first + per_place};
}

// Appends the observations of points_w[first, last) from T_cw: every point
// in front of the camera (depth >= min_point_depth) whose noisy pixel lies
// in the image; with depth on a point's first observation, or on every one
// with depth_every_observation.
void ObservePoints(const SimulationOptions& options,
                   const std::vector<Eigen::Vector3d>& points_w,
                   size_t first,
                   size_t last,
                   const Rigid3d& T_cw,
                   Random* random,
                   std::vector<bool>* point_seen,
                   std::vector<PointObservation>* observations) {
  for (size_t i = first; i < last; ++i) {
    const Eigen::Vector3d p_c = T_cw * points_w[i];
    Eigen::Vector2d uv;
    if (!Project(options.intrinsics, p_c, options.min_point_depth, &uv)) {
      continue;
    }
    const double nu = random->Normal(options.pixel_sigma);
    const double nv = random->Normal(options.pixel_sigma);
    uv += Eigen::Vector2d(nu, nv);
    if (!InImage(options, uv)) continue;
    PointObservation obs;
    obs.id = static_cast<int64_t>(i);
    obs.uv = uv;
    if (options.depth_every_observation || !(*point_seen)[i]) {
      obs.depth = std::max(1e-3, p_c.z() + random->Normal(options.depth_sigma));
      (*point_seen)[i] = true;
    }
    observations->push_back(obs);
  }
}

}  // namespace

std::vector<GroundTruthObject> GroundTruthObjects(
    const SimulatedSequence& sequence) {
  std::vector<GroundTruthObject> objects;
  for (size_t i = 0; i < sequence.objects.size(); ++i) {
    const SimulatedObject& o = sequence.objects[i];
    GroundTruthObject g;
    g.id = static_cast<int>(i);
    g.class_name = o.class_name;
    g.symmetry = o.symmetry;
    g.order = o.symmetry == SymmetryType::kDiscrete ? o.order : 0;
    g.T_wo = Rigid3d(o.T_wo.q.normalized(), o.T_wo.t);
    if (o.symmetry != SymmetryType::kAsymmetric) {
      g.axis_o = o.axis_o.normalized();
      g.axis_w = g.T_wo.q * g.axis_o;
    }
    objects.push_back(std::move(g));
  }
  return objects;
}

namespace {

std::string FormatGroundTruthObjects(const SimulatedSequence& sequence) {
  std::vector<std::pair<std::string, int>> detections;
  for (const auto& truths : sequence.detections) {
    for (const SimulatedDetectionTruth& truth : truths) {
      detections.emplace_back(truth.id, truth.object);
    }
  }
  return FormatGroundTruthObjectsJson(GroundTruthObjects(sequence), detections);
}

}  // namespace

Status Simulate(const std::string& scene_name,
                const SimulationOptions& options,
                uint32_t seed,
                SimulatedSequence* out) {
  Status status = options.Validate();
  if (!status.ok()) return status;
  Scene scene;
  status = MakeScene(scene_name, &scene);
  if (!status.ok()) return status;

  SimulatedSequence seq;
  seq.scene = scene.name;
  seq.seed = seed;
  seq.options = options;
  seq.objects = scene.objects;
  seq.header.camera = options.intrinsics;
  if (options.write_class_priors) {
    for (const SimulatedObject& o : seq.objects) {
      ClassPrior prior;
      prior.symmetry = o.symmetry;
      prior.order = o.symmetry == SymmetryType::kDiscrete ? o.order : 0;
      prior.axis_o = o.symmetry == SymmetryType::kAsymmetric
                         ? Eigen::Vector3d::Zero()
                         : Eigen::Vector3d(o.axis_o.normalized());
      seq.header.classes[o.class_name] = prior;
    }
  }

  std::vector<CameraView> views;
  status = TrajectoryViews(scene, options, &views);
  if (!status.ok()) return status;

  Random random(seed);
  seq.points_w = WallPoints(scene, options, &random);
  std::vector<bool> point_seen(seq.points_w.size(), false);
  std::vector<int> previous_dominant(seq.objects.size(), -1);

  Rigid3d T_wc_fe;
  for (int k = 0; k < options.num_keyframes; ++k) {
    const Rigid3d T_wc = LookAt(views[k].eye, views[k].target);
    const bool rich =
        InArc(views[k].bearing, options.rich_arc_start, options.rich_arc);
    seq.T_wc_true.push_back(T_wc);
    seq.rich.push_back(rich);

    KeyframeInput input;
    input.id = k;
    input.timestamp = k * options.seconds_per_keyframe;

    // Front end.
    if (k == 0) {
      T_wc_fe = T_wc;
    } else {
      const Rigid3d T_prev_cur = seq.T_wc_true[k - 1].Inverse() * T_wc;
      Rigid3d error;
      if (rich) {
        error = random.PoseNoise(options.rich_sigma_t, options.rich_sigma_r);
      } else {
        const Eigen::Vector3d a_c =
            T_wc.q.conjugate() * Eigen::Vector3d::UnitZ();
        const double yaw = options.yaw_bias + random.Normal(options.yaw_noise);
        error = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, a_c)),
                        Eigen::Vector3d::Zero()) *
                random.PoseNoise(options.featureless_sigma_t,
                                 options.featureless_sigma_r);
      }
      Rigid3d motion = T_prev_cur * error;
      motion.q.normalize();
      if (options.relocalize_on_rich && rich) {
        T_wc_fe =
            T_wc * random.PoseNoise(options.rich_sigma_t, options.rich_sigma_r);
      } else {
        T_wc_fe = T_wc_fe * motion;
      }
      if (options.with_odometry) {
        Odometry odometry;
        odometry.T_prev_cur = motion;
        odometry.sigma_t = rich ? options.odometry_sigma_t
                                : options.featureless_odometry_sigma_t;
        odometry.sigma_r = rich ? options.odometry_sigma_r
                                : options.featureless_odometry_sigma_r;
        input.odometry = odometry;
      }
    }
    T_wc_fe.q.normalize();
    input.T_wc = T_wc_fe;

    const Rigid3d T_cw = T_wc.Inverse();
    // Points: rich keyframes only.
    if (rich) {
      const auto [first, last] =
          TrackedPoints(options, views[k], seq.points_w.size());
      ObservePoints(options,
                    seq.points_w,
                    first,
                    last,
                    T_cw,
                    &random,
                    &point_seen,
                    &input.points);
    }

    // Detections.
    std::vector<std::pair<DetectionInput, SimulatedDetectionTruth>> seen;
    for (size_t o = 0; o < seq.objects.size(); ++o) {
      const SimulatedObject& object = seq.objects[o];
      const Eigen::Vector3d p_c = T_cw * object.T_wo.t;
      Eigen::Vector2d uv;
      if (!Project(options.intrinsics, p_c, 0.1, &uv) ||
          !InImage(options, uv) || p_c.norm() > options.max_detection_range) {
        continue;
      }
      if (random.Bernoulli(options.miss_probability)) continue;
      SimulatedDetectionTruth truth;
      truth.object = static_cast<int>(o);
      DetectionInput detection = GenerateDetection(
          options, object, T_wc, previous_dominant[o], &random, &truth);
      previous_dominant[o] = truth.dominant_mode;
      seen.emplace_back(std::move(detection), std::move(truth));
    }
    // The order of a keyframe's detections says nothing about the objects.
    random.Shuffle(&seen);
    std::vector<SimulatedDetectionTruth> truths;
    for (size_t i = 0; i < seen.size(); ++i) {
      const std::string id = std::to_string(k) + "/" + std::to_string(i);
      seen[i].first.id = id;
      seen[i].second.id = id;
      input.detections.push_back(std::move(seen[i].first));
      truths.push_back(std::move(seen[i].second));
    }
    seq.detections.push_back(std::move(truths));
    seq.keyframes.push_back(std::move(input));
  }
  *out = std::move(seq);
  return Status::Ok();
}

Status SimulationFiles(
    const SimulatedSequence& sequence,
    std::vector<std::pair<std::string, std::string>>* files) {
  std::ostringstream log;
  std::unique_ptr<LogWriter> writer;
  Status status =
      LogWriter::OpenStream(&log, "log.jsonl", sequence.header, &writer);
  if (!status.ok()) return status;
  for (const KeyframeInput& keyframe : sequence.keyframes) {
    status = writer->Write(keyframe);
    if (!status.ok()) return status;
  }
  status = writer->Close();
  if (!status.ok()) return status;

  std::vector<KeyframeEstimate> truth;
  for (size_t k = 0; k < sequence.keyframes.size(); ++k) {
    truth.push_back({sequence.keyframes[k].id,
                     sequence.keyframes[k].timestamp,
                     sequence.T_wc_true[k]});
  }
  files->clear();
  files->emplace_back("log.jsonl", log.str());
  files->emplace_back("gt_trajectory.tum", FormatTumTrajectory(truth));
  files->emplace_back("gt_objects.json", FormatGroundTruthObjects(sequence));
  return Status::Ok();
}

Status WriteSimulation(const SimulatedSequence& sequence,
                       const std::string& out_dir) {
  std::vector<std::pair<std::string, std::string>> files;
  Status status = SimulationFiles(sequence, &files);
  if (!status.ok()) return status;
  return WriteDirectoryAtomically(out_dir, files);
}

}  // namespace symba
