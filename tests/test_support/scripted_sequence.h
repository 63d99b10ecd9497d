// Scripted keyframe sequences for the backend tests: a camera orbiting one or
// more objects, with the ground truth and the KeyframeInputs a front end and a
// multi-hypothesis detector would hand the backend. Header-only, deterministic
// for a seed.
//
// A deliberately independent oracle. The library has its own simulator
// (src/simulation, `symba simulate`), which the end-to-end tools use; the
// backend tests do not. This header uses only the backend's input types
// (KeyframeInput), the symmetry types, the geometry helpers and the other
// test_support headers, never symba/simulation or the log format, and it
// draws its own noise (test_support/random.h, hypothesis_generator.h). So a
// bug in the simulator (a wrong frame convention, mode or noise model) cannot
// produce the same bug in the backend tests' inputs and their ground truth
// and hide it: the two would have to be wrong in the same way independently.
//
// World: z up, the scene centre c at the origin by default. Keyframe k of a
// loop of n sits at orbit angle phi_k = start_angle + 2 pi k / n on a circle
// of `radius` about c, `height` above it, and looks at c (camera x right,
// y down, z forward).
//
// Rich and featureless halves. The first half of every loop is "rich": the
// camera looks at a curved wall of map points (a cylinder of radius
// wall_radius about c, on the side opposite those cameras) and the front end
// is accurate there, T_wc_fe = T_wc * Exp(n), n ~ N(0, fe_sigma^2) (the
// first keyframe exact: it fixes the backend's gauge). The second half is
// featureless: no point observations, and the front end integrates its
// relative motion with a yaw bias about the world vertical,
//     T_wc_fe(k) = T_wc_fe(k-1) * T_{k-1,k} * (Rot(a_c, b + e_k), 0) * Exp(n)
// with a_c = R_wc(k)^T z_w, b = yaw_bias per keyframe and e_k ~ N(0,
// yaw_noise^2), so its trajectory bends away from the truth (back on a rich
// half, a later loop's front end relocalises: accurate again). Optional
// odometry has the same yaw bias (and noise) on the featureless half and
// small noise on the rich half; its translation is accurate.
//
// Points: pinhole projection with `intrinsics` into a width x height image,
// uv + N(0, pixel_sigma^2) per axis, the depth (along z, + N(0, depth_sigma^2))
// on a point's first observation only.
//
// Detections: per object whose centre projects into the image, one
// DetectionInput "<keyframe id>/<object index>" with num_hypotheses T_co:
//   inlier j   R_co^j = R_co Rot(a_o, phi_j) Exp(r_j),  t_co^j = t_co + s_j
//              with T_co = T_cw T_wo the truth, r_j ~ N(0, rotation_sigma^2
//              I), s_j ~ N(0, translation_sigma^2 I)
//     discrete    phi_j = 2 pi m / order, m taking the view's visible modes in
//                 turn; the view shows a random set of between
//                 min_visible_modes and max_visible_modes modes (0 = order),
//                 or the modes mode_script gives for that keyframe
//     continuous  phi_j ~ U(centre - arc/2, centre + arc/2), the centre
//                 uniform per view (arc = 2 pi: the whole circle)
//     asymmetric  phi_j = 0
//   outlier j  the rotation uniform on SO(3), the translation as an inlier's;
//              round(outlier_fraction * N) of them.
// Weights: the inliers of one visible mode per view (the "dominant" mode,
// uniform among the visible ones) have dominant_weight, every other
// hypothesis other_weight, so the detector's highest-weight hypothesis flips
// between the modes from view to view. The hypotheses are shuffled.
#ifndef SYMBA_TESTS_TEST_SUPPORT_SCRIPTED_SEQUENCE_H_
#define SYMBA_TESTS_TEST_SUPPORT_SCRIPTED_SEQUENCE_H_

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/backend/keyframe_input.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/pinhole_intrinsics.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/so3.h"
#include "test_support/hypothesis_generator.h"
#include "test_support/random.h"

namespace symba::testing {

struct ScriptedObject {
  std::string class_name = "table";
  SymmetryType symmetry = SymmetryType::kDiscrete;
  int order = 2;                                      // discrete only
  Eigen::Vector3d axis_o = Eigen::Vector3d::UnitZ();  // object frame
  Rigid3d T_wo;
};

struct ScriptedSequenceSpec {
  std::vector<ScriptedObject> objects;

  // Orbit.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 2.5;  // m
  double height = 1.2;  // m above the centre
  int keyframes_per_loop = 40;
  int num_keyframes = 40;
  double start_angle = 0.0;  // rad
  double seconds_per_keyframe = 0.5;

  // Front end and odometry.
  double fe_sigma_t = 0.005;          // m per axis, rich half
  double fe_sigma_r = 0.1 * kDegree;  // rad per axis
  double yaw_bias = 1.5 * kDegree;    // rad per featureless keyframe
  double yaw_noise = 0.3 * kDegree;   // rad
  bool with_frontend_pose = true;     // set KeyframeInput::T_wc
  bool with_odometry = false;         // set KeyframeInput::odometry
  double odometry_sigma_t = 0.01;     // what the input claims, m
  double odometry_sigma_r = 0.02;     // rad
  double odometry_noise_t = 0.003;    // applied, m per axis
  double odometry_noise_r = 0.1 * kDegree;

  // Map points on the rich half.
  PinholeIntrinsics intrinsics{500.0, 500.0, 320.0, 240.0};
  int image_width = 640;
  int image_height = 480;
  int num_points = 120;
  double wall_radius = 5.0;                    // m
  double wall_half_arc = 120.0 * kDegree;      // about the wall's middle
  double wall_z_min = -1.0, wall_z_max = 1.0;  // m, relative to the centre
  double pixel_sigma = 1.0;                    // px
  double depth_sigma = 0.01;                   // m

  // Detector.
  int num_hypotheses = 30;
  double rotation_sigma = 3.0 * kDegree;  // rad per axis
  double translation_sigma = 0.02;        // m per axis
  double outlier_fraction = 0.1;
  int min_visible_modes = 0;  // 0 = every mode
  int max_visible_modes = 0;
  // If not empty, keyframe k shows the modes mode_script[k % size] of every
  // discrete object instead of a random set.
  std::vector<std::vector<int>> mode_script;
  double continuous_arc = kTwoPi;  // rad
  double dominant_weight = 1.0;
  double other_weight = 0.8;
  // The noise the detector reports (DetectionInput::sigma_t, sigma_r);
  // unset: the backend's defaults apply.
  std::optional<double> detection_sigma_t;
  std::optional<double> detection_sigma_r;

  unsigned seed = 1;
};

// What generated one detection.
struct ScriptedDetectionTruth {
  int object = -1;  // index into spec.objects
  std::string id;   // the DetectionInput's id
  std::vector<int> visible_modes;
  int dominant_mode = 0;
  std::vector<int> hypothesis_mode;  // per hypothesis; -1 = outlier
};

struct ScriptedSequence {
  std::vector<KeyframeInput> keyframes;
  std::vector<Rigid3d> T_wc_true;
  std::vector<bool> rich;
  std::vector<std::vector<ScriptedDetectionTruth>> detections;  // per kf
  std::vector<Eigen::Vector3d> points_w;
  PinholeIntrinsics intrinsics;
};

// Camera at `eye` looking at `target`, world z up (x right, y down, z
// forward).
inline Rigid3d LookAtCamera(const Eigen::Vector3d& eye,
                            const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return Rigid3d(Eigen::Quaterniond(R).normalized(), eye);
}

inline Rigid3d PoseNoise(double sigma_t, double sigma_r, TestRandom* random) {
  return Rigid3d(ExpSO3<double>(random->NormalVector(sigma_r)),
                 random->NormalVector(sigma_t));
}

// The visible modes of one view of a discrete object, ascending.
inline std::vector<int> DrawVisibleModes(const ScriptedSequenceSpec& spec,
                                         int order,
                                         TestRandom* random) {
  const int lo = spec.min_visible_modes > 0 ? spec.min_visible_modes : order;
  const int hi = spec.max_visible_modes > 0 ? spec.max_visible_modes : order;
  const int count =
      std::clamp(std::uniform_int_distribution<int>(
                     std::min(lo, hi), std::max(lo, hi))(random->engine()),
                 1,
                 order);
  std::vector<int> modes(order);
  for (int m = 0; m < order; ++m) modes[m] = m;
  for (int i = order - 1; i > 0; --i) {
    const int j = std::uniform_int_distribution<int>(0, i)(random->engine());
    std::swap(modes[i], modes[j]);
  }
  modes.resize(count);
  std::sort(modes.begin(), modes.end());
  return modes;
}

inline DetectionInput GenerateScriptedDetection(
    const ScriptedSequenceSpec& spec,
    const ScriptedObject& object,
    const Rigid3d& T_wc,
    int keyframe,
    TestRandom* random,
    ScriptedDetectionTruth* truth) {
  const Rigid3d T_co_true = T_wc.Inverse() * object.T_wo;
  const Eigen::Vector3d a_o = object.axis_o.normalized();
  truth->visible_modes = {0};
  if (object.symmetry == SymmetryType::kDiscrete) {
    truth->visible_modes =
        spec.mode_script.empty()
            ? DrawVisibleModes(spec, object.order, random)
            : spec.mode_script[keyframe % spec.mode_script.size()];
  }
  const int num_visible = static_cast<int>(truth->visible_modes.size());
  truth->dominant_mode =
      truth->visible_modes[std::uniform_int_distribution<int>(
          0, num_visible - 1)(random->engine())];
  const double arc_centre = random->Uniform(-kPi, kPi);

  DetectionInput detection;
  detection.class_name = object.class_name;
  detection.sigma_t = spec.detection_sigma_t;
  detection.sigma_r = spec.detection_sigma_r;
  const int n = spec.num_hypotheses;
  const int num_outliers =
      static_cast<int>(std::lround(spec.outlier_fraction * n));
  for (int j = 0; j < n; ++j) {
    PoseHypothesis h;
    h.weight = spec.other_weight;
    const Eigen::Vector3d t =
        T_co_true.t + random->NormalVector(spec.translation_sigma);
    if (j >= n - num_outliers) {
      h.T_co = Rigid3d(random->Rotation(), t);
      truth->hypothesis_mode.push_back(-1);
    } else {
      int mode = 0;
      double phi = 0.0;
      if (object.symmetry == SymmetryType::kDiscrete) {
        mode = truth->visible_modes[j % num_visible];
        phi = kTwoPi * mode / object.order;
      } else if (object.symmetry == SymmetryType::kContinuous) {
        phi = arc_centre + random->Uniform(-0.5, 0.5) * spec.continuous_arc;
      }
      if (mode == truth->dominant_mode) h.weight = spec.dominant_weight;
      const Eigen::Quaterniond q =
          T_co_true.q * Eigen::Quaterniond(Eigen::AngleAxisd(phi, a_o)) *
          ExpSO3<double>(random->NormalVector(spec.rotation_sigma));
      h.T_co = Rigid3d(q.normalized(), t);
      truth->hypothesis_mode.push_back(mode);
    }
    detection.hypotheses.push_back(h);
  }
  for (int i = n - 1; i > 0; --i) {
    const int k = std::uniform_int_distribution<int>(0, i)(random->engine());
    std::swap(detection.hypotheses[i], detection.hypotheses[k]);
    std::swap(truth->hypothesis_mode[i], truth->hypothesis_mode[k]);
  }
  return detection;
}

inline ScriptedSequence GenerateScriptedSequence(
    const ScriptedSequenceSpec& spec) {
  TestRandom random(spec.seed);
  ScriptedSequence seq;
  seq.intrinsics = spec.intrinsics;
  const PinholeIntrinsics& K = spec.intrinsics;
  const int n_loop = std::max(2, spec.keyframes_per_loop);

  // The wall faces the cameras of the rich half: its middle is opposite the
  // middle of that half of the orbit.
  const double wall_middle = spec.start_angle + kPi / 2.0 + kPi;
  for (int i = 0; i < spec.num_points; ++i) {
    const double angle =
        wall_middle + random.Uniform(-spec.wall_half_arc, spec.wall_half_arc);
    seq.points_w.push_back(
        spec.centre +
        Eigen::Vector3d(spec.wall_radius * std::cos(angle),
                        spec.wall_radius * std::sin(angle),
                        random.Uniform(spec.wall_z_min, spec.wall_z_max)));
  }
  std::vector<bool> point_seen(seq.points_w.size(), false);

  auto project = [&](const Rigid3d& T_wc,
                     const Eigen::Vector3d& p_w,
                     Eigen::Vector2d* uv,
                     double* depth) {
    const Eigen::Vector3d p_c = T_wc.Inverse() * p_w;
    if (p_c.z() < 0.3) return false;
    *uv = Eigen::Vector2d(K.fx * p_c.x() / p_c.z() + K.cx,
                          K.fy * p_c.y() / p_c.z() + K.cy);
    *depth = p_c.z();
    return uv->x() >= 0.0 && uv->x() < spec.image_width && uv->y() >= 0.0 &&
           uv->y() < spec.image_height;
  };

  Rigid3d T_wc_fe;
  for (int k = 0; k < spec.num_keyframes; ++k) {
    const double phi = spec.start_angle + kTwoPi * k / n_loop;
    const Eigen::Vector3d eye =
        spec.centre + Eigen::Vector3d(spec.radius * std::cos(phi),
                                      spec.radius * std::sin(phi),
                                      spec.height);
    const Rigid3d T_wc = LookAtCamera(eye, spec.centre);
    const bool rich = (k % n_loop) < n_loop / 2;
    seq.T_wc_true.push_back(T_wc);
    seq.rich.push_back(rich);

    KeyframeInput input;
    input.id = 100 + k;  // ids need not start at 0
    input.timestamp = k * spec.seconds_per_keyframe;

    // Front end and odometry.
    const Eigen::Vector3d a_c = T_wc.q.conjugate() * Eigen::Vector3d::UnitZ();
    const double yaw = spec.yaw_bias + random.Normal(spec.yaw_noise);
    const Rigid3d yaw_error(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, a_c)),
                            Eigen::Vector3d::Zero());
    if (k == 0) {
      T_wc_fe = T_wc;
    } else {
      const Rigid3d T_prev_cur = seq.T_wc_true[k - 1].Inverse() * T_wc;
      if (rich) {
        T_wc_fe = T_wc * PoseNoise(spec.fe_sigma_t, spec.fe_sigma_r, &random);
      } else {
        T_wc_fe = T_wc_fe * T_prev_cur * yaw_error *
                  PoseNoise(spec.fe_sigma_t, spec.fe_sigma_r, &random);
      }
      if (spec.with_odometry) {
        Odometry odometry;
        odometry.T_prev_cur =
            T_prev_cur *
            PoseNoise(spec.odometry_noise_t, spec.odometry_noise_r, &random);
        if (!rich) odometry.T_prev_cur = odometry.T_prev_cur * yaw_error;
        odometry.sigma_t = spec.odometry_sigma_t;
        odometry.sigma_r = spec.odometry_sigma_r;
        input.odometry = odometry;
      }
    }
    T_wc_fe.q.normalize();
    if (spec.with_frontend_pose || k == 0) input.T_wc = T_wc_fe;

    // Points, rich half only.
    if (rich) {
      for (size_t i = 0; i < seq.points_w.size(); ++i) {
        Eigen::Vector2d uv;
        double depth = 0.0;
        if (!project(T_wc, seq.points_w[i], &uv, &depth)) continue;
        PointObservation obs;
        obs.id = static_cast<int64_t>(i);
        obs.uv = uv + Eigen::Vector2d(random.Normal(spec.pixel_sigma),
                                      random.Normal(spec.pixel_sigma));
        if (!point_seen[i]) {
          obs.depth = depth + random.Normal(spec.depth_sigma);
          point_seen[i] = true;
        }
        input.points.push_back(obs);
      }
    }

    // Detections.
    std::vector<ScriptedDetectionTruth> truths;
    for (size_t o = 0; o < spec.objects.size(); ++o) {
      Eigen::Vector2d uv;
      double depth = 0.0;
      if (!project(T_wc, spec.objects[o].T_wo.t, &uv, &depth)) continue;
      ScriptedDetectionTruth truth;
      truth.object = static_cast<int>(o);
      DetectionInput detection = GenerateScriptedDetection(
          spec, spec.objects[o], T_wc, k, &random, &truth);
      detection.id = std::to_string(input.id) + "/" + std::to_string(o);
      truth.id = detection.id;
      input.detections.push_back(std::move(detection));
      truths.push_back(std::move(truth));
    }
    seq.detections.push_back(std::move(truths));
    seq.keyframes.push_back(std::move(input));
  }
  return seq;
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_SCRIPTED_SEQUENCE_H_
