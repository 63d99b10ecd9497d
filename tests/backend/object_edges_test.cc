// The object edges on their own (src/backend/object_edges.h): the factor
// each observation gets, its blocks per object type, what a rebuild
// retires, and the noise an edge is weighed with once its class has an
// estimate (a detection's own sigma is kept; otherwise the larger of the
// observation's and the estimate).
#include "backend/object_edges.h"

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "symba/factors/pose_component.h"

namespace symba::internal {
namespace {

ClassNoise Noise(std::optional<double> sigma_t,
                 std::optional<double> sigma_r,
                 std::optional<double> white_sigma_t = std::nullopt) {
  ClassNoise noise;
  noise.sigma_t = sigma_t;
  noise.sigma_r = sigma_r;
  noise.white_sigma_t = white_sigma_t;
  return noise;
}

class ObjectEdgesTest : public ::testing::Test {
 protected:
  ObjectEdgesTest()
      : graph_(options_, keyframes_, objects_, points_, &statistics_),
        edges_(options_, keyframes_, &objects_, &graph_) {
    // One camera at the origin and one asymmetric object of class "box"
    // 1 m in front of it (z), seen 0.1 m off along x by its detections.
    keyframes_.push_back(std::make_unique<KeyframeState>());
    graph_.SetManifold(keyframes_[0]->q, &quaternion_);
    auto object = std::make_unique<ObjectState>();
    object->class_name = "box";
    WritePose(Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1)),
              object->q,
              object->t);
    graph_.SetManifold(object->q, &quaternion_);
    objects_.push_back(std::move(object));
  }

  // A detection at t_co = (0.1, 0, 1) with its components weighed by
  // `component_sigma_t` and the observation's noise sigma_t (claimed or
  // not).
  static ObjectObservation Observation(double component_sigma_t,
                                       double sigma_t,
                                       bool claimed) {
    ObjectObservation observation;
    observation.keyframe = 0;
    observation.T_co_best =
        Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0, 1));
    PoseComponent component;
    component.T_co = observation.T_co_best;
    component.sqrt_info = IsotropicPoseSqrtInfo(component_sigma_t, 0.1);
    observation.components = {component};
    observation.sigma_t = sigma_t;
    observation.sigma_r = 0.1;
    observation.claimed_t = claimed;
    observation.claimed_r = claimed;
    return observation;
  }

  // The norm of the translation part of observation i's residual at the
  // current estimate (0.1 m off): 0.1 / the sigma it is weighed with.
  double TranslationResidual(int i) const {
    const FactorRecord& record =
        graph_.factor(objects_[0]->observations[i].factor);
    std::vector<double> residuals(record.cost->num_residuals());
    std::vector<const double*> blocks(record.blocks.begin(),
                                      record.blocks.end());
    EXPECT_TRUE(
        record.cost->Evaluate(blocks.data(), residuals.data(), nullptr));
    return Eigen::Map<const Eigen::Vector3d>(residuals.data()).norm();
  }

  BackendOptions options_;
  KeyframeList keyframes_;
  ObjectList objects_;
  PointList points_;
  BackendStatistics statistics_;
  ceres::EigenQuaternionManifold quaternion_;
  FactorGraph graph_;
  ObjectEdges edges_;
};

TEST_F(ObjectEdgesTest, AnAsymmetricObjectsEdgeJoinsCameraAndObjectPoses) {
  edges_.Add(0, Observation(0.05, 0.05, true));
  ASSERT_EQ(objects_[0]->observations.size(), 1u);
  const int f = objects_[0]->observations[0].factor;
  ASSERT_GE(f, 0);
  const FactorRecord& record = graph_.factor(f);
  EXPECT_EQ(record.object, 0);
  EXPECT_EQ(record.observation, 0);
  EXPECT_EQ(record.keyframe, 0);
  const std::vector<double*> blocks = {
      keyframes_[0]->q, keyframes_[0]->t, objects_[0]->q, objects_[0]->t};
  EXPECT_EQ(record.blocks, blocks);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.05, 1e-9);
}

TEST_F(ObjectEdgesTest, ADiscreteObjectsEdgeHoldsItsAngle) {
  ObjectState& object = *objects_[0];
  object.type = SymmetryType::kDiscrete;
  object.a_o = Eigen::Vector3d::UnitZ();
  object.anchor = SymmetryAnchor::FromObjectRotation(
      Eigen::Quaterniond::Identity(), object.a_o);
  object.thetas.push_back(std::make_unique<double>(0.0));
  object.thetas.push_back(std::make_unique<double>(1.0));
  ObjectObservation observation = Observation(0.05, 0.05, true);
  observation.angle = 1;
  edges_.Add(0, observation);
  const std::vector<double*> blocks = {keyframes_[0]->q,
                                       keyframes_[0]->t,
                                       object.t,
                                       object.a_w,
                                       object.thetas[1].get()};
  EXPECT_EQ(graph_.factor(object.observations[0].factor).blocks, blocks);
}

// A rebuild retires the old factor for a new one.
TEST_F(ObjectEdgesTest, RebuildReplacesEveryLiveEdge) {
  edges_.Add(0, Observation(0.05, 0.05, true));
  edges_.Add(0, Observation(0.05, 0.05, true));
  const int first = objects_[0]->observations[0].factor;
  const int second = objects_[0]->observations[1].factor;
  edges_.Rebuild(0);
  EXPECT_TRUE(graph_.factor(first).retired);
  EXPECT_TRUE(graph_.factor(second).retired);
  EXPECT_EQ(objects_[0]->observations[0].factor, second + 1);
  EXPECT_EQ(objects_[0]->observations[1].factor, second + 2);
  EXPECT_FALSE(graph_.factor(second + 1).retired);
  EXPECT_EQ(objects_[0]->stale_observations, 0);
}

// A merge appended an observation older than the last: the order by
// keyframe is restored, and each edge names its observation's new index.
TEST_F(ObjectEdgesTest, RestoreKeyframeOrderSortsAndRenumbersTheEdges) {
  for (int k = 1; k <= 2; ++k) {
    keyframes_.push_back(std::make_unique<KeyframeState>());
    graph_.SetManifold(keyframes_[k]->q, &quaternion_);
  }
  for (int k : {0, 2, 1}) {
    ObjectObservation observation = Observation(0.05, 0.05, true);
    observation.keyframe = k;
    edges_.Add(0, observation);
  }
  const int last_before = objects_[0]->observations[2].factor;
  edges_.RestoreKeyframeOrder(0);
  const std::vector<ObjectObservation>& observations =
      objects_[0]->observations;
  ASSERT_EQ(observations.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(observations[i].keyframe, i);
    const FactorRecord& record = graph_.factor(observations[i].factor);
    EXPECT_FALSE(record.retired);
    EXPECT_EQ(record.observation, i);
    EXPECT_EQ(record.keyframe, i);
    EXPECT_GT(observations[i].factor, last_before);
  }
  // In order already: nothing is rebuilt.
  const int first = observations[0].factor;
  edges_.RestoreKeyframeOrder(0);
  EXPECT_EQ(observations[0].factor, first);
}

// noise_update_ratio 1.25: the first estimate applies, one within the ratio
// does not, one beyond it does.
TEST_F(ObjectEdgesTest, NoiseAppliesOnlyWhenItMovesBeyondTheRatio) {
  EXPECT_FALSE(edges_.AppliedNoise("box").sigma_t.has_value());
  EXPECT_TRUE(edges_.ApplyNoise("box", Noise(0.2, std::nullopt)));
  EXPECT_EQ(edges_.AppliedNoise("box").sigma_t, 0.2);
  EXPECT_FALSE(edges_.ApplyNoise("box", Noise(0.24, std::nullopt)));
  EXPECT_EQ(edges_.AppliedNoise("box").sigma_t, 0.2);
  EXPECT_TRUE(edges_.ApplyNoise("box", Noise(0.26, 0.3)));
  EXPECT_EQ(edges_.AppliedNoise("box").sigma_t, 0.26);
  EXPECT_EQ(edges_.AppliedNoise("box").sigma_r, 0.3);
  EXPECT_FALSE(edges_.ApplyNoise("box", ClassNoise{}));
  EXPECT_FALSE(edges_.AppliedNoise("chair").sigma_t.has_value());
  // A white part that moves beyond the ratio applies too.
  EXPECT_TRUE(edges_.ApplyNoise("box", Noise(0.26, 0.3, 0.01)));
  EXPECT_EQ(edges_.AppliedNoise("box").white_sigma_t, 0.01);
  EXPECT_FALSE(edges_.ApplyNoise("box", Noise(0.26, 0.3, 0.011)));
  EXPECT_EQ(edges_.AppliedNoise("box").white_sigma_t, 0.01);
}

// An observation weighed by its hypotheses' scatter is held to the class's
// white part sigma_I, never to the persistence-inflated estimate or the
// floor.
TEST_F(ObjectEdgesTest, AScatterIsHeldToTheWhitePartOnly) {
  ObjectObservation small = Observation(0.02, 0.02, false);
  small.from_scatter = true;
  ObjectObservation large = Observation(0.08, 0.08, false);
  large.from_scatter = true;
  edges_.Add(0, small);
  edges_.Add(0, large);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.02, 1e-9);
  EXPECT_NEAR(TranslationResidual(1), 0.1 / 0.08, 1e-9);
  // Estimate 2 m (a drifting front end's levels), white part 0.05 m.
  ASSERT_TRUE(edges_.ApplyNoise("box", Noise(2.0, 3.0, 0.05)));
  edges_.Rebuild(0);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.05, 1e-9);
  EXPECT_NEAR(TranslationResidual(1), 0.1 / 0.08, 1e-9);
  const EdgeSigmas sigmas = EffectiveNoise(small, edges_.AppliedNoise("box"));
  EXPECT_DOUBLE_EQ(sigmas.t, 0.05);
  EXPECT_DOUBLE_EQ(sigmas.r, 0.1);  // no white rotation part: its own
}

// Before the class has an estimate the components weigh as the detection
// gave them; after, an unclaimed observation weighs with the larger of its
// own sigma and the estimate, a claimed one with its own.
TEST_F(ObjectEdgesTest, EdgesWeighWithTheEstimateUnlessTheDetectionClaims) {
  edges_.Add(0, Observation(0.05, 0.01, false));  // estimate wins
  edges_.Add(0, Observation(0.05, 2.0, false));   // its own (a floor) wins
  edges_.Add(0, Observation(0.05, 0.02, true));   // claimed: its own
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(TranslationResidual(i), 0.1 / 0.05, 1e-9) << i;
  }
  ASSERT_TRUE(edges_.ApplyNoise("box", Noise(0.5, 0.2)));
  edges_.Rebuild(0);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.5, 1e-9);
  EXPECT_NEAR(TranslationResidual(1), 0.1 / 2.0, 1e-9);
  EXPECT_NEAR(TranslationResidual(2), 0.1 / 0.02, 1e-9);
}

// Each edge records what it weighs with (the noise report's
// ClassNoiseEstimate::weights): the translation sigma its residual is
// divided by, before and after the class's estimate, and the rotation
// sigma only where the edge weighs the rotation with it. A turned-away view
// weighs nothing: its 10 cm is a residual of 1e-4 whatever the noise, and
// it records no sigma.
TEST_F(ObjectEdgesTest, AnEdgeRecordsTheSigmasItWeighsWith) {
  edges_.Add(0, Observation(0.05, 0.01, false));
  edges_.Add(0, Observation(0.05, 0.02, true));
  ObjectObservation turned_away = Observation(0.05, 2.0, false);
  turned_away.turned_away = true;
  edges_.Add(0, turned_away);
  const auto expect_recorded = [&](const std::vector<double>& t,
                                   const std::vector<double>& r) {
    for (int i = 0; i < 3; ++i) {
      const ObjectObservation& o = objects_[0]->observations[i];
      EXPECT_DOUBLE_EQ(o.edge_sigma_t, t[i]) << i;
      EXPECT_NEAR(TranslationResidual(i),
                  i < 2 ? 0.1 / o.edge_sigma_t : 0.1 / kUninformativeSigma,
                  1e-9)
          << i;
      EXPECT_DOUBLE_EQ(o.edge_sigma_r, r[i]) << i;
    }
  };
  // Before the estimate: the components' 5 cm and 0.1 rad.
  expect_recorded({0.05, 0.05, 0.0}, {0.1, 0.1, 0.0});
  ASSERT_TRUE(edges_.ApplyNoise("box", Noise(0.5, 0.2)));
  edges_.Rebuild(0);
  expect_recorded({0.5, 0.02, 0.0}, {0.2, 0.1, 0.0});
  // A continuous object weighs its axis with axis_sigma, not sigma_r.
  objects_[0]->type = SymmetryType::kContinuous;
  objects_[0]->a_o = Eigen::Vector3d::UnitZ();
  edges_.Rebuild(0);
  EXPECT_DOUBLE_EQ(objects_[0]->observations[0].edge_sigma_t, 0.5);
  EXPECT_DOUBLE_EQ(objects_[0]->observations[0].edge_sigma_r, 0.0);
  // A merged copy's view without its hypotheses gets no edge.
  ObjectObservation freed = Observation(0.05, 0.05, true);
  freed.components.clear();
  freed.edge_sigma_t = 0.05;
  edges_.Add(0, freed);
  EXPECT_EQ(objects_[0]->observations[3].factor, -1);
  EXPECT_EQ(objects_[0]->observations[3].edge_sigma_t, 0.0);
}

// claimed_noise_tolerance 1.5: a claim scale of 1.4 leaves claimed
// observations as they claimed (nothing to rebuild), one of 4 weighs them
// four times their claim and moves the gate's factor; unclaimed ones are
// untouched.
TEST_F(ObjectEdgesTest, AClaimContradictedBeyondTheToleranceIsScaled) {
  edges_.Add(0, Observation(0.05, 0.02, true));
  edges_.Add(0, Observation(0.05, 0.2, false));
  ClassNoise noise = Noise(0.1, 0.2);
  noise.claim_scale_t = 1.4;
  noise.claim_scale_r = 1.4;
  ASSERT_TRUE(edges_.ApplyNoise("box", noise));  // the estimate is new
  EXPECT_FALSE(edges_.AppliedNoise("box").claim_scale_t.has_value());  // 1
  edges_.Rebuild(0);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.02, 1e-9);
  noise.claim_scale_t = 4.0;
  ASSERT_TRUE(edges_.ApplyNoise("box", noise));
  EXPECT_EQ(edges_.AppliedNoise("box").claim_scale_t, 4.0);
  EXPECT_EQ(edges_.AppliedNoise("box").claim_scale_r, 1.0);
  edges_.Rebuild(0);
  EXPECT_NEAR(TranslationResidual(0), 0.1 / 0.08, 1e-9);
  EXPECT_NEAR(TranslationResidual(1), 0.1 / 0.2, 1e-9);
  const EdgeSigmas sigmas =
      EffectiveNoise(Observation(0.05, 0.02, true), edges_.AppliedNoise("box"));
  EXPECT_DOUBLE_EQ(sigmas.t, 0.08);
  EXPECT_DOUBLE_EQ(sigmas.r, 0.1);
  // Within noise_update_ratio of the applied factor: nothing moves.
  noise.claim_scale_t = 4.4;
  EXPECT_FALSE(edges_.ApplyNoise("box", noise));
}

// Whatever the applied noise (a loaded map's may hold any positive sigma
// and any claim factor), the effective sigma stays within [kMinNoiseSigma,
// kMaxNoiseSigma]: the edges and the keyframe graph both read it.
TEST_F(ObjectEdgesTest, TheEffectiveSigmaStaysWithinTheGivenRange) {
  ClassNoise extreme = Noise(1e300, 1e300);
  extreme.claim_scale_t = 1e300;
  extreme.claim_scale_r = 1e300;
  for (const bool claimed : {true, false}) {
    const EdgeSigmas sigmas =
        EffectiveNoise(Observation(0.05, 0.05, claimed), extreme);
    EXPECT_EQ(sigmas.t, kMaxNoiseSigma) << claimed;
    EXPECT_EQ(sigmas.r, kMaxNoiseSigma) << claimed;
  }
}

// A scale that wobbles about the tolerance (1.5) switches the factor on
// once and keeps it: 1.45 leaves the claims, 1.55 scales them, then 1.45
// and 1.55 in turn move nothing; only a scale that falls to 1 or below
// (beyond noise_update_ratio) takes the factor back to 1.
TEST_F(ObjectEdgesTest, AClaimFactorDoesNotFlapAboutTheTolerance) {
  ClassNoise noise = Noise(0.1, 0.2);
  noise.claim_scale_t = 1.45;
  ASSERT_TRUE(edges_.ApplyNoise("box", noise));  // the estimate is new
  EXPECT_FALSE(edges_.AppliedNoise("box").claim_scale_t.has_value());
  noise.claim_scale_t = 1.55;
  EXPECT_TRUE(edges_.ApplyNoise("box", noise));
  EXPECT_EQ(edges_.AppliedNoise("box").claim_scale_t, 1.55);
  for (const double scale : {1.45, 1.55, 1.45, 1.3}) {
    noise.claim_scale_t = scale;
    EXPECT_FALSE(edges_.ApplyNoise("box", noise)) << scale;
    EXPECT_EQ(edges_.AppliedNoise("box").claim_scale_t, 1.55) << scale;
  }
  noise.claim_scale_t = 0.9;
  EXPECT_TRUE(edges_.ApplyNoise("box", noise));
  EXPECT_EQ(edges_.AppliedNoise("box").claim_scale_t, 1.0);
}

}  // namespace
}  // namespace symba::internal
