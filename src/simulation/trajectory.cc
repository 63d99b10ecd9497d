// The simulator's camera path before noise (src/simulation/trajectory.h).
#include "simulation/trajectory.h"

#include <cmath>
#include <vector>

#include "symba/geometry/angle.h"

namespace symba {
namespace {

// Keyframe k of the orbit about the origin.
CameraView OrbitView(const SimulationOptions& options, int k) {
  const double phi = options.start_angle + kTwoPi * static_cast<double>(k) /
                                               options.keyframes_per_loop;
  CameraView view;
  view.eye = Eigen::Vector3d(options.orbit_radius * std::cos(phi),
                             options.orbit_radius * std::sin(phi),
                             options.camera_height);
  view.target = Eigen::Vector3d(0.0, 0.0, options.look_at_height);
  view.bearing = phi;
  return view;
}

// One visit of a route: the place, its centre and the radius it is
// circled at.
struct Visit {
  int place = 0;
  Eigen::Vector2d centre;
  double radius = 0.0;
};

// a mod b in [0, b), for b > 0.
int Modulo(int a, int b) { return ((a % b) + b) % b; }

// Visit i of the route (i >= -1; visit -1 ends the lap before the first
// and fixes where the first circle is entered). Even laps follow the
// tour, odd laps run it backwards; both start at tour[0].
Visit RouteVisit(const Scene& scene, const SimulationOptions& options, int i) {
  const int n = static_cast<int>(scene.tour.size());
  const int position = Modulo(i, n);
  const int lap = (i - position) / n;
  const bool reverse = Modulo(lap, 2) == 1;
  const int place = scene.tour[reverse ? (n - position) % n : position];
  const int w = Modulo(lap + position, 3) - 1;  // -1, 0 or 1
  return {place,
          scene.places[place],
          options.visit_radius * (1.0 + options.visit_radius_variation * w)};
}

// The common tangent from circle a to circle b, both driven
// counter-clockwise: the camera leaves a at angle heading - pi/2 about
// a's centre, drives `length` m along heading and meets b at the same
// angle about b's centre. With d = c_b - c_a and the right-hand normal
// n = (sin h, -cos h), the ends c_a + r_a n and c_b + r_b n differ along
// the heading only if d.n = r_a - r_b:
//   h = atan2(d) + asin((r_a - r_b) / |d|),  length = |d| cos(asin(...)).
struct Tangent {
  double heading = 0.0;  // rad
  double length = 0.0;   // m
};

// Whether the tangent exists: the centres are farther apart than the
// radii differ.
bool Joinable(const Visit& a, const Visit& b) {
  return (b.centre - a.centre).norm() > std::abs(a.radius - b.radius);
}

// Requires Joinable(a, b).
Tangent CommonTangent(const Visit& a, const Visit& b) {
  const Eigen::Vector2d d = b.centre - a.centre;
  const double distance = d.norm();
  const double beta = std::asin((a.radius - b.radius) / distance);
  return {std::atan2(d.y(), d.x()) + beta, distance * std::cos(beta)};
}

// The counter-clockwise turn from angle `from` to angle `to`, wrapped
// into [min_arc, min_arc + 2 pi) (rad).
double ArcSweep(double from, double to, double min_arc) {
  double sweep = std::fmod(to - from - min_arc, kTwoPi);
  if (sweep < 0.0) sweep += kTwoPi;
  return min_arc + sweep;
}

// Puts keyframe k at arc length k * route_step along the route, whose
// segments are fed in order.
class RouteSampler {
 public:
  RouteSampler(const SimulationOptions& options, std::vector<CameraView>* views)
      : options_(options), views_(views) {}

  bool Done() const {
    return static_cast<int>(views_->size()) >= options_.num_keyframes;
  }

  // The circle about `visit` from angle `start` counter-clockwise through
  // `sweep` rad, looking at the centre.
  void Arc(const Visit& visit, double start, double sweep) {
    Sample(visit.radius * sweep, [&](double s) {
      const double theta = start + s / visit.radius;
      const Eigen::Vector2d eye =
          visit.centre +
          visit.radius * Eigen::Vector2d(std::cos(theta), std::sin(theta));
      return View(eye, visit.centre, theta, visit.place);
    });
  }

  // The tangent from a to b, looking sideways (along -n) at a point that
  // slides from a's centre to b's.
  void Line(const Visit& a, const Visit& b, const Tangent& tangent) {
    const double h = tangent.heading;
    const Eigen::Vector2d u(std::cos(h), std::sin(h));
    const Eigen::Vector2d n(u.y(), -u.x());
    Sample(tangent.length, [&](double s) {
      const Eigen::Vector2d eye = a.centre + a.radius * n + s * u;
      const Eigen::Vector2d target =
          a.centre + (s / tangent.length) * (b.centre - a.centre);
      const int place = s < 0.5 * tangent.length ? a.place : b.place;
      return View(eye, target, h - 0.5 * kPi, place);
    });
  }

 private:
  // Adds the views of the keyframes whose arc length falls into the next
  // `length` m; view_at maps the arc length from the segment's start.
  template <typename ViewAt>
  void Sample(double length, const ViewAt& view_at) {
    while (!Done()) {
      const double s =
          static_cast<double>(views_->size()) * options_.route_step - start_;
      if (s >= length) break;
      views_->push_back(view_at(s));
    }
    start_ += length;
  }

  CameraView View(const Eigen::Vector2d& eye,
                  const Eigen::Vector2d& target,
                  double bearing,
                  int place) const {
    CameraView view;
    view.eye = Eigen::Vector3d(eye.x(), eye.y(), options_.camera_height);
    view.target =
        Eigen::Vector3d(target.x(), target.y(), options_.look_at_height);
    view.bearing = bearing;
    view.place = place;
    return view;
  }

  const SimulationOptions& options_;
  std::vector<CameraView>* views_;
  double start_ = 0.0;  // arc length where the next segment begins (m)
};

Status RouteViews(const Scene& scene,
                  const SimulationOptions& options,
                  std::vector<CameraView>* views) {
  if (scene.tour.size() < 2) {
    return Status::Error("simulation: a route needs at least two places");
  }
  // The route repeats after 6 laps (directions alternate, radii cycle
  // through 3): if one period's visits can be joined, all can.
  const int period = 6 * static_cast<int>(scene.tour.size());
  for (int i = -1; i < period; ++i) {
    if (!Joinable(RouteVisit(scene, options, i),
                  RouteVisit(scene, options, i + 1))) {
      return Status::Error(
          "simulation: two consecutive places of the route are too close "
          "for their visit radii");
    }
  }
  RouteSampler sampler(options, views);
  Visit current = RouteVisit(scene, options, 0);
  Tangent incoming = CommonTangent(RouteVisit(scene, options, -1), current);
  for (int i = 0; !sampler.Done(); ++i) {
    const Visit next = RouteVisit(scene, options, i + 1);
    const Tangent outgoing = CommonTangent(current, next);
    // On a circle driven counter-clockwise, heading h is at angle h - pi/2.
    const double entry = incoming.heading - 0.5 * kPi;
    const double exit = outgoing.heading - 0.5 * kPi;
    sampler.Arc(current, entry, ArcSweep(entry, exit, options.min_visit_arc));
    sampler.Line(current, next, outgoing);
    current = next;
    incoming = outgoing;
  }
  return Status::Ok();
}

}  // namespace

Status TrajectoryViews(const Scene& scene,
                       const SimulationOptions& options,
                       std::vector<CameraView>* views) {
  views->clear();
  views->reserve(static_cast<size_t>(options.num_keyframes));
  if (!scene.places.empty()) return RouteViews(scene, options, views);
  for (int k = 0; k < options.num_keyframes; ++k) {
    views->push_back(OrbitView(options, k));
  }
  return Status::Ok();
}

}  // namespace symba
