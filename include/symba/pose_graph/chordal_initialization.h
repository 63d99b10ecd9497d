// A pose graph's initial guess from its measurements alone (Carlone et al.,
// "Initialization Techniques for 3D SLAM: a Survey on Rotation Estimation
// and its Use in Pose Graph Optimization", ICRA 2015): chordal relaxation
// of the rotations, then the translations by linear least squares. Both
// are linear problems with a unique solution, so the guess does not depend
// on where the vertices started, and Levenberg-Marquardt from it reaches
// the global optimum where a drifted start ends in a local one
// (docs/pose-graphs.md, "Initialisation").
#ifndef SYMBA_POSE_GRAPH_CHORDAL_INITIALIZATION_H_
#define SYMBA_POSE_GRAPH_CHORDAL_INITIALIZATION_H_

#include <vector>

#include <Eigen/Core>

#include "symba/geometry/rigid3.h"

namespace symba {

// One relative measurement between the vertices a and b (indices into the
// poses), with SE-Sync's isotropic weights of its information (tau for the
// translation, kappa for the rotation; pose_graph.h IsotropicInformation).
struct ChordalEdge {
  int a = 0;
  int b = 0;
  Rigid3d T_ab;  // unit quaternion
  double tau = 1.0;
  double kappa = 1.0;
};

// Replaces the poses of the vertices that are not `held` by the chordal
// estimate; held vertices keep theirs and fix the gauge. Every connected
// component of the edges must hold at least one vertex (else false,
// nothing changed).
//   Rotations: minimise sum kappa |M_b - M_a R_ab|_F^2 over 3x3 matrices
//   M_v (M_v = R_v for held vertices). Row r of every M is independent of
//   the other rows: u_b - R_ab^T u_a = 0 with u_v = (row r of M_v)^T, one
//   sparse system (the same matrix for the three rows). Each M_v is then
//   projected onto SO(3) (SVD: U diag(1, 1, det(U V^T)) V^T).
//   Translations: with those rotations, minimise
//   sum tau |t_b - t_a - R_a t_ab|^2 (a weighted graph Laplacian, one
//   system for the three coordinates).
bool ChordalInitialization(const std::vector<ChordalEdge>& edges,
                           const std::vector<bool>& held,
                           std::vector<Rigid3d>* poses);

}  // namespace symba

#endif  // SYMBA_POSE_GRAPH_CHORDAL_INITIALIZATION_H_
