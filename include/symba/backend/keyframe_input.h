// What a front end hands the backend for one keyframe: its pose estimate
// and/or odometry, its multi-hypothesis detections and its point
// observations. Mirrors a keyframe line of the log format v1
// (docs/log-format.md); everything is keyed by ids, never by pointers.
#ifndef SYMBA_BACKEND_KEYFRAME_INPUT_H_
#define SYMBA_BACKEND_KEYFRAME_INPUT_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/ids.h"
#include "symba/detection/pose_hypothesis.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// The pose of this keyframe in the previous keyframe's frame, T_{prev,cur},
// with isotropic standard deviations.
struct Odometry {
  Rigid3d T_prev_cur;
  double sigma_t = 0.01;   // m
  double sigma_r = 0.005;  // rad
};

struct DetectionInput {
  std::string id;                          // unique per log, e.g. "17/0"
  std::string class_name;                  // e.g. "table"
  std::vector<PoseHypothesis> hypotheses;  // T_co, at least one
  std::optional<double> sigma_t;           // m; default from the options
  std::optional<double> sigma_r;           // rad
  double score = 1.0;
};

struct PointObservation {
  PointId id = 0;                                // stable across keyframes
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // pixels
  std::optional<double> depth;                   // m, along the optical axis
};

// A relative pose the host system knows between an earlier keyframe and
// this one (its own loop closure, docs/loop-closure.md): this keyframe's
// pose in the earlier one's frame, T_{earlier,this}, with isotropic
// standard deviations.
struct LoopClosureInput {
  KeyframeId keyframe = 0;  // the earlier keyframe
  Rigid3d T;
  double sigma_t = 0.05;  // m
  double sigma_r = 0.02;  // rad
};

struct KeyframeInput {
  KeyframeId id = 0;                 // strictly increasing
  double timestamp = 0.0;            // s
  std::optional<Rigid3d> T_wc;       // the front end's estimate
  std::optional<Odometry> odometry;  // from the previous keyframe
  std::vector<DetectionInput> detections;
  std::vector<PointObservation> points;
  std::vector<LoopClosureInput> loop_closures;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_KEYFRAME_INPUT_H_
