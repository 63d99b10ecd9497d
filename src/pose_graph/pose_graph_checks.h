// Internal to the g2o reader and the pose-graph solver: the checks and
// messages they share. Not installed.
#ifndef SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_CHECKS_H_
#define SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_CHECKS_H_

#include <string>

#include "symba/factors/pose_component.h"

namespace symba::internal {

// Quaternions whose norm is within this of 1 are normalised, others rejected
// (the same rule as for every file symba reads, docs/conventions.md).
inline constexpr double kQuaternionNormTolerance = 1e-3;

// "information matrix is not positive definite (smallest eigenvalue X)".
std::string NotPositiveDefinite(const Matrix6d& information);

}  // namespace symba::internal

#endif  // SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_CHECKS_H_
