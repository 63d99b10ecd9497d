// Scenes and options of the simulator (docs/simulation.md): the paper's
// simulation experiment (Sec. VI-A), a camera orbiting objects at the centre
// of a room whose one side is feature-rich and whose other side is
// featureless, rebuilt so that every knob that makes it harder or easier is
// a documented field with a default; and a long scene for scale, a camera
// touring several places of objects lap after lap.
//
// World frame: z up, the floor is z = 0, the orbit's centre is the origin.
// Objects stand on the floor; T_wo places an object's frame at the centre of
// its bounding box. Camera frames follow docs/conventions.md (x right,
// y down, z forward).
//
// Scenes (MakeScene):
//   disc    a rectangular table ("table", discrete, order 2, axis z) at the
//           centre: the paper's sim(disc)
//   cts     a round table ("round_table", continuous, axis z): sim(cts)
//   asym    a chair ("chair", asymmetric)
//   square  a square table ("square_table", discrete, order 4, axis z)
//   room    a rectangular table at the centre, two round tables 1.3 m
//           apart, a chair, and a three-fold "prism" lying with its
//           symmetry axis (object x) tilted 30 degrees above the floor
//   long    23 objects of every kind at six places of 3-5 objects (a 3 x 2
//           grid, 7 m apart), toured by the camera lap after lap (the
//           route of SimulationOptions); 10,000 keyframes by default
#ifndef SYMBA_SIMULATION_SCENE_H_
#define SYMBA_SIMULATION_SCENE_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/pinhole_intrinsics.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// One object of a scene: its class, its symmetry and its true pose.
struct SimulatedObject {
  std::string class_name;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  int order = 0;  // discrete: the symmetry order k (>= 2); else 0
  // Symmetry axis in the object frame, unit (unused for asymmetric).
  Eigen::Vector3d axis_o = Eigen::Vector3d::UnitZ();
  Rigid3d T_wo;
};

struct Scene {
  std::string name;
  std::string description;  // one line, for --help and the docs
  std::vector<SimulatedObject> objects;
  // Route scenes: the places' centres on the floor (x, y in m) and one lap
  // of the tour, as indices into places. Empty: the camera orbits the
  // origin.
  std::vector<Eigen::Vector2d> places;
  std::vector<int> tour;
  // The keyframes `symba simulate` writes when --keyframes is not given.
  // Simulate itself always simulates SimulationOptions::num_keyframes.
  int default_num_keyframes = 72;
};

// The scene names MakeScene accepts, in a fixed order.
std::vector<std::string> SceneNames();

// The scene called `name`; an error naming the known scenes otherwise.
Status MakeScene(const std::string& name, Scene* scene);

// Every parameter that shapes the difficulty of a simulated sequence. Units
// are metres, radians and seconds (the command line takes degrees).
struct SimulationOptions {
  // --- Trajectory -------------------------------------------------------
  // Orbit scenes (no places): keyframe k sits at orbit angle
  // start_angle + 2 pi k / keyframes_per_loop
  // on a circle of orbit_radius about the origin, camera_height above the
  // floor, looking at (0, 0, look_at_height). 72 keyframes are two loops of
  // 36 (10 degrees apart): the second loop returns to the rich side after
  // the drift of the first featureless half, and revisits the objects.
  int num_keyframes = 72;
  int keyframes_per_loop = 36;
  double orbit_radius = 2.5;    // m
  double camera_height = 1.6;   // m above the floor
  double look_at_height = 0.4;  // m above the floor
  double start_angle = 0.0;     // rad, orbit angle of keyframe 0
  double seconds_per_keyframe = 0.5;

  // --- Route (scenes with places: long) ---------------------------------
  // The camera tours the places lap after lap: even laps visit scene.tour
  // in order, odd laps in reverse, every lap starting at tour[0]. At each
  // visit it circles the place counter-clockwise on a circle of radius
  //   r = visit_radius (1 + visit_radius_variation w),
  //   w = (lap + position in the lap) mod 3 - 1,
  // camera_height above the floor, looking at the place's centre at
  // look_at_height, through the turn to the next place wrapped into
  // [min_visit_arc, min_visit_arc + 2 pi) (a place passed straight by is
  // circled once). It then leaves along the common tangent to the next
  // place's circle, looking sideways at a point sliding from the one
  // centre to the other. Keyframes are route_step apart along the path
  // (on a circle, route_step / r rad of rotation; orbit options unused).
  double route_step = 0.35;                   // m
  double visit_radius = 2.5;                  // m
  double visit_radius_variation = 0.15;       // relative, in [0, 1)
  double min_visit_arc = 60.0 * kPi / 180.0;  // rad

  // --- Feature-rich and featureless sides -------------------------------
  // A keyframe's bearing is the azimuth of the camera seen from the point
  // it looks at: the orbit angle on the orbit, the angle about the place
  // on a route's circle. Keyframes whose bearing lies in [rich_arc_start,
  // rich_arc_start + rich_arc) (modulo 2 pi) are "rich": they look at a
  // textured wall behind the objects and see map points. The others look
  // at a blank wall.
  double rich_arc_start = 0.0;  // rad
  double rich_arc = kPi;        // rad; pi = half the orbit

  // --- Front end (visual odometry) --------------------------------------
  // The front end integrates its relative motion, which is accurate on the
  // rich side and drifts in yaw about the world vertical on the featureless
  // side:
  //   T_wc_fe(k) = T_wc_fe(k-1) * T_{k-1,k} * E_k,   T_wc_fe(0) = T_wc(0)
  //   rich         E_k = (Exp(n_r), n_t),  n ~ N(0, rich_sigma^2 I)
  //   featureless  E_k = (Rot(a_c, yaw_bias + N(0, yaw_noise^2)) Exp(n_r),
  //                       n_t),  n ~ N(0, featureless_sigma^2 I)
  // with a_c the world vertical in camera k. The drift is kept: the front
  // end does not snap back on the rich side unless relocalize_on_rich.
  double rich_sigma_t = 0.005;              // m per axis
  double rich_sigma_r = 0.1 * kPi / 180.0;  // rad per axis
  double yaw_bias = 2.0 * kPi / 180.0;      // rad per featureless keyframe
  double yaw_noise = 0.5 * kPi / 180.0;     // rad
  double featureless_sigma_t = 0.01;        // m per axis
  double featureless_sigma_r = 0.2 * kPi / 180.0;  // rad per axis
  // On the rich side, reset the front end to the truth (plus the rich
  // noise) instead of integrating: a relocalising front end whose relative
  // motion then jumps by the accumulated drift when it re-enters.
  bool relocalize_on_rich = false;
  // Also write the front end's relative motion as `odometry` (the pose
  // T_wc is always written) with the standard deviations the front end
  // claims: odometry_sigma_* on rich keyframes, featureless_odometry_sigma_*
  // on featureless ones (a front end that has lost its features knows it).
  // The defaults are about twice the true per-axis noise, and on the
  // featureless side just above the yaw bias, which the claim cannot
  // know as a bias. Off, the backend uses its own frontend_sigma_*.
  bool with_odometry = true;
  double odometry_sigma_t = 0.01;              // m
  double odometry_sigma_r = 0.005;             // rad
  double featureless_odometry_sigma_t = 0.02;  // m
  double featureless_odometry_sigma_r = 0.04;  // rad

  // --- Map points --------------------------------------------------------
  // Orbit scenes: num_points points on a vertical cylinder of wall_radius
  // about the origin, between wall_z_min and wall_z_max, on the arc facing
  // the rich cameras (the rich bearings turned by pi). Route scenes:
  // points_per_place such points about each place, on a cylinder of
  // place_wall_radius about its centre. Rich keyframes observe the
  // points in front of them (depth >= min_point_depth) whose noisy pixel
  // lies inside the image; featureless keyframes report no points. With
  // depth_every_observation (an RGB-D front end, the paper's setting) every
  // observation carries the point's noisy depth, otherwise only its first.
  int num_points = 300;
  double wall_radius = 5.0;  // m
  int points_per_place = 80;
  double place_wall_radius = 3.6;  // m
  double wall_z_min = 0.0;         // m
  double wall_z_max = 2.0;         // m
  double pixel_sigma = 1.0;        // px per axis
  double depth_sigma = 0.02;       // m
  bool depth_every_observation = false;
  double min_point_depth = 0.3;  // m
  PinholeIntrinsics intrinsics{525.0, 525.0, 319.5, 239.5};
  int image_width = 640;   // px
  int image_height = 480;  // px

  // --- Detector ------------------------------------------------------------
  // An object is detected when its centre lies in front of the camera
  // within max_detection_range and projects into the image, unless the
  // detection is missed (miss_probability). A detection has num_hypotheses
  // hypotheses T_co:
  //   inlier j   T_cw T_wo (Rot(a_o, phi_j), 0) (Exp(r_j), s_j),
  //              r_j ~ N(0, rotation_sigma^2 I),
  //              s_j ~ N(0, translation_sigma^2 I)
  //     discrete    phi_j = 2 pi m / k for the view's visible modes m in
  //                 turn: with subset_view_probability the view shows a
  //                 random proper subset of 1 .. k-1 modes, else all k
  //     continuous  phi_0 ~ U(-s/2, s/2) (s = continuous_dominant_spread),
  //                 phi_j = phi_0 + U(-arc/2, arc/2) (arc = continuous_arc)
  //     asymmetric  phi_j = 0
  //   outlier j  rotation uniform on SO(3),
  //              translation + N(0, outlier_translation_sigma^2 I);
  //              round(outlier_fraction N) of them
  // Weights: the inliers of the view's dominant mode (a random visible
  // mode, kept from the previous view with dominant_mode_persistence;
  // continuous: hypothesis 0) get dominant_weight, all others other_weight,
  // each times 1 + U(-weight_jitter, weight_jitter). The hypotheses are
  // shuffled. The dominant mode flipping between views is what breaks the
  // single-hypothesis baseline; views that show only some modes break the
  // multi-hypothesis one (docs/simulation.md).
  //
  // With single_hypothesis (most 6-DoF detectors: one pose per object per
  // image) a detection is one hypothesis instead: with probability
  // outlier_fraction an outlier as above, else an inlier at a random one
  // of the object's symmetric poses,
  //     discrete    phi = 2 pi m / k, m the dominant mode (uniform over all
  //                 k modes, kept with dominant_mode_persistence)
  //     continuous  phi ~ U(-arc/2, arc/2) (arc = continuous_arc)
  //     asymmetric  phi = 0
  // with the inlier noise, weight dominant_weight (1 + U(-weight_jitter,
  // weight_jitter)). num_hypotheses, subset_view_probability, other_weight
  // and continuous_dominant_spread are then unused.
  bool single_hypothesis = false;
  int num_hypotheses = 30;
  double rotation_sigma = 3.0 * kPi / 180.0;  // rad per axis
  double translation_sigma = 0.03;            // m per axis
  double outlier_fraction = 0.1;
  double outlier_translation_sigma = 0.1;  // m per axis
  double subset_view_probability = 0.5;
  double dominant_mode_persistence = 0.0;
  double dominant_weight = 1.0;
  double other_weight = 0.7;
  double weight_jitter = 0.05;
  double continuous_arc = 2.0 * kPi;                       // rad
  double continuous_dominant_spread = 30.0 * kPi / 180.0;  // rad
  double miss_probability = 0.05;
  double max_detection_range = 6.0;  // m
  // Write the detector noise (translation_sigma, rotation_sigma) as each
  // detection's sigma_t, sigma_r.
  bool write_detection_sigmas = true;
  // Write the true class symmetries as `classes` priors in the log header
  // (off: everything is inferred from the hypotheses, the paper's default).
  bool write_class_priors = false;

  // OK, or which option is out of range and why.
  Status Validate() const;
};

}  // namespace symba

#endif  // SYMBA_SIMULATION_SCENE_H_
