// The simulator's camera path before noise (docs/simulation.md,
// "Trajectory"): the orbit about the origin of the orbit scenes, and the
// route through the places of a route scene, lap after lap.
#ifndef SYMBA_SRC_SIMULATION_TRAJECTORY_H_
#define SYMBA_SRC_SIMULATION_TRAJECTORY_H_

#include <vector>

#include <Eigen/Core>

#include "symba/common/status.h"
#include "symba/simulation/scene.h"

namespace symba {

// Where the camera of one keyframe is and what it looks at (world, m).
struct CameraView {
  Eigen::Vector3d eye;
  Eigen::Vector3d target;
  // Azimuth of the camera seen from the target, atan2 of (eye - target)
  // in the floor plane (rad, not wrapped): what decides rich or not.
  double bearing = 0.0;
  // Route scenes: the place looked at, whose wall the front end tracks
  // (the place circled; on a tangent, the place whose centre is nearer the
  // target). -1 on the orbit.
  int place = -1;
};

// The options.num_keyframes views of `scene`: the orbit if it has no
// places, its route otherwise. Errors: a route whose consecutive visits
// are too close for their circles to be joined by a tangent.
Status TrajectoryViews(const Scene& scene,
                       const SimulationOptions& options,
                       std::vector<CameraView>* views);

}  // namespace symba

#endif  // SYMBA_SRC_SIMULATION_TRAJECTORY_H_
