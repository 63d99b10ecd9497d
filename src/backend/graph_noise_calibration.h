// The noise of the keyframe graph's edges, calibrated by the residuals of
// the estimate (docs/backend.md "Covariances"), for the covariances only:
// the estimate was made with the stated noise, and its covariance is that
// of an estimate so weighed when the noise is what the residuals show
// (PoseGraphCovarianceOptions::noise_factors). Not installed.
//
// Per group of edges (the camera steps of one stated noise; the detections
// of one class), with r_i the whitened residual of edge i at the estimate
// divided by the square root of the detections it stands for, and d_i its
// degrees of freedom:
//   s   = sum |r_i|^2 / sum d_i                  (translation, rotation)
//   rho = sum r_i . r_prev(i) / sqrt(sum |r_i|^2 sum |r_prev(i)|^2)
//         over the edges with a predecessor in their sequence, in [0,
//         kMaxCorrelation] (detection_noise.h's, 0.98)
//   f   = s (1 + rho) / (1 - rho)                (a run of N errors that
//         persist as an AR(1) process moves an estimate as N (1 - rho) /
//         (1 + rho) independent ones would; the stated noise is white)
// A residual's expected square is the noise's times (1 - its leverage), so
// it shows the noise only where something else held the estimate: a held
// group gets f (at least kMinVarianceFactor), any other at least 1 (its
// residuals can prove its noise larger than stated, never smaller). A group
// of fewer than kMinGroupResiduals measured residuals keeps 1. Every edge
// of a group takes its factors, those whose residual was not measured (a
// step inside the window) too; rotation rows that measure nothing
// (rotation_dof 0) keep 1. An axis edge's rotation rows take the group's
// rotation factor on the turn about the axis too, which nothing measures
// and which is held loosely anyway (kAxisTurnInformation).
//
// Known limitation: an object edge stands for `weight` detections taken as
// independent; the correlation measured between consecutive edges, which
// lie `weight` keyframes apart, is the detections' correlation to that
// power, so errors that persist from keyframe to keyframe are inflated
// less than `weight` consecutive detections would need.
#ifndef SYMBA_SRC_BACKEND_GRAPH_NOISE_CALIBRATION_H_
#define SYMBA_SRC_BACKEND_GRAPH_NOISE_CALIBRATION_H_

#include <string>
#include <vector>

#include "backend/detection_noise.h"
#include "symba/backend/covariance_noise.h"
#include "symba/pose_graph/pose_graph.h"
#include "symba/pose_graph/pose_graph_covariance.h"

namespace symba::internal {

inline constexpr int kMinGroupResiduals = 10;
inline constexpr double kMinVarianceFactor = 0.01;  // sigma at least 0.1x

// One edge of the graph (in graph order).
struct GraphEdgeRole {
  std::string group;            // empty: as stated (a loop closure)
  bool held_by_others = false;  // the group's (see above)
  // Its residual is a measurement's misfit (not an estimate taken as the
  // measurement, as the window's steps are).
  bool measured = true;
  double weight = 1.0;   // the detections it stands for
  int previous = -1;     // the previous edge of its sequence, or -1
  int rotation_dof = 3;  // 0: its rotation rows are not a measurement
};

// `factors` (one per edge) and `groups` (one per group, by name) for the
// graph at its poses. `roles` must have one entry per edge; otherwise every
// edge keeps its stated noise (factors 1, no groups).
void CalibrateGraphNoise(const PoseGraph& graph,
                         const std::vector<GraphEdgeRole>& roles,
                         std::vector<EdgeNoiseFactors>* factors,
                         std::vector<CovarianceNoiseGroup>* groups);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_GRAPH_NOISE_CALIBRATION_H_
