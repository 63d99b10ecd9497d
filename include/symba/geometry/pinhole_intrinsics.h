// The intrinsics of a pinhole camera (pixels). A point p_c in the camera
// frame (x right, y down, z forward) projects to
//   u = [fx p_c.x / p_c.z + cx, fy p_c.y / p_c.z + cy].
// Used by the log format's header, the backend, the simulator and the
// reprojection factor (symba/factors/reprojection_factor.h).
#ifndef SYMBA_GEOMETRY_PINHOLE_INTRINSICS_H_
#define SYMBA_GEOMETRY_PINHOLE_INTRINSICS_H_

namespace symba {

struct PinholeIntrinsics {
  double fx = 1.0;
  double fy = 1.0;
  double cx = 0.0;
  double cy = 0.0;
};

}  // namespace symba

#endif  // SYMBA_GEOMETRY_PINHOLE_INTRINSICS_H_
