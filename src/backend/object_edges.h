// The edges between keyframes and map objects in the factor graph
// (docs/architecture.md): one per object observation, built for the
// object's current type, anchor and its class's detection noise, and
// rebuilt when any of these changes. It owns the noise each class's edges
// are built with and the objects' loss; it changes only the observations'
// factor bookkeeping (ObjectObservation::factor, stale_observations). Not
// installed.
#ifndef SYMBA_SRC_BACKEND_OBJECT_EDGES_H_
#define SYMBA_SRC_BACKEND_OBJECT_EDGES_H_

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include "backend/backend_state.h"
#include "backend/detection_noise.h"
#include "backend/factor_graph.h"

namespace symba::internal {

// The noise of a turned-away view's edge (m and rad,
// ObjectObservation::turned_away): so large that the view carries no
// information (a rotation residual of at most pi / 1000 whitened, a
// position residual of 1 m of 1e-3), while the square-root information stays
// invertible, as the mixture's normaliser needs.
constexpr double kUninformativeSigma = 1000.0;

// The sigmas (m) of LineOfSightRows.
struct SightSigmas {
  double along = 0.0;
  double across = 0.0;
};

struct EdgeSigmas {
  double t = 0.0;  // m
  double r = 0.0;  // rad
};

// The sigmas an observation's edge is weighed with once its class has an
// applied noise (EffectiveSigma): its detection's claim times the class's
// claim factor (1 unless the data contradicts the claims); its
// hypotheses' scatter held to the class's frame-to-frame noise; otherwise
// the larger of the floor and the class's estimate.
EdgeSigmas EffectiveNoise(const ObjectObservation& observation,
                          const ClassNoise& applied);

// The axis a symmetric object's detection measured, in the camera frame
// (unit): the detection's own axis, or its representative pose's turn of the
// object's axis a_o; turned to the side of the object's world axis, given
// the keyframe's rotation q_wc. The continuous edge and the keyframe graph
// take it.
Eigen::Vector3d MeasuredAxis(const ObjectState& object,
                             const ObjectObservation& observation,
                             const Eigen::Quaterniond& q_wc);

class ObjectEdges {
 public:
  // The containers and the graph are the backend's and must outlive this.
  ObjectEdges(const BackendOptions& options,
              const KeyframeList& keyframes,
              ObjectList* objects,
              FactorGraph* graph);

  // Object o's next observation and its edge (none if its hypotheses were
  // freed: a merged duplicate's observation from a keyframe that left the
  // window without keep_history).
  void Add(int o, ObjectObservation observation);
  // Rebuilds the edges of object o's observations still in the window (all
  // under condition); the older ones become stale (ObjectState).
  void Rebuild(int o);
  // Puts object o's observations back in keyframe order (stable) if they
  // are not, and then rebuilds every edge it can (each edge names its
  // observation's index): a merge of two copies of one object that were
  // detected in turn appends observations older than the last.
  void RestoreKeyframeOrder(int o);
  // The batch solve first rebuilds every stale edge.
  void RebuildStale();
  // The noise the edges of `class_name` are built with from now on, if it
  // moved by more than noise_update_ratio from the applied one; true if so:
  // the class's edges must then be rebuilt.
  bool ApplyNoise(const std::string& class_name, const ClassNoise& estimate);
  // Sets the class's applied noise as it is (a loaded map's: the claim
  // scales are the factors, not estimates to test against the tolerance).
  // Nothing is rebuilt: called before the first keyframe only
  // (Backend::LoadMap refuses a backend that has one).
  void RestoreNoise(const std::string& class_name, const ClassNoise& applied) {
    applied_noise_[class_name] = applied;
  }
  // The noise applied to the class's edges (empty sigmas: none yet).
  ClassNoise AppliedNoise(const std::string& class_name) const;
  // Every class's applied noise, by name.
  const std::map<std::string, ClassNoise>& applied_noise() const {
    return applied_noise_;
  }

 private:
  // The edge of object o's observation i.
  void AddFactor(int o, int i);
  void Rebuild(int o, int begin, int end);
  // `sigmas`: what it weighs the detection with (BuildNoise). With
  // LineOfSightRows where SightNoise gives sigmas.
  std::unique_ptr<ceres::CostFunction> BuildEdge(
      KeyframeState* keyframe,
      ObjectState* object,
      const ObjectObservation& observation,
      std::vector<double*>* blocks,
      EdgeSigmas* sigmas) const;
  // The noise along and across the line of sight of an observation whose
  // edge the floor weighs (undeclared, no scatter, the class's estimate
  // below the floor): the floor along it, the class's estimate across it;
  // none otherwise, or before the class has an estimate.
  std::optional<SightSigmas> SightNoise(
      const ObjectState& object, const ObjectObservation& observation) const;
  // The edge for the object's type alone.
  std::unique_ptr<ceres::CostFunction> BuildMixtureEdge(
      KeyframeState* keyframe,
      ObjectState* object,
      const ObjectObservation& observation,
      std::vector<double*>* blocks,
      EdgeSigmas* sigmas) const;
  // The sigmas the edge of `observation` (of `object`, its hypotheses not
  // freed) is built with: EffectiveNoise once the class has an applied
  // noise, before that the detection's as its components carry them
  // (InitialSqrtInfo).
  EdgeSigmas BuildNoise(const ObjectState& object,
                        const ObjectObservation& observation) const;

  const BackendOptions& options_;
  const KeyframeList& keyframes_;
  ObjectList& objects_;
  FactorGraph* graph_;
  std::unique_ptr<ceres::LossFunction> loss_;
  std::map<std::string, ClassNoise> applied_noise_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_EDGES_H_
