// The factor graph on its own (src/backend/factor_graph.h): which factors a
// window or batch solve holds, what leaving the window keeps and frees, and
// the solved poses of a small chain whose answer is known, and a point's
// prior moved by a loop closure.
#include "backend/factor_graph.h"

#include <memory>
#include <vector>

#include <ceres/manifold.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "symba/factors/pose_component.h"
#include "symba/factors/pose_prior_factor.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/factors/reprojection_factor.h"

namespace symba::internal {
namespace {

// Keyframes 1 m apart along x; odometry factors between neighbours that
// measure exactly that; an object with one prior-like edge per keyframe in
// `object_keyframes` (a pose prior at the object's true pose, standing in
// for a detection edge).
class FactorGraphTest : public ::testing::Test {
 protected:
  void Build(const BackendOptions& options,
             int n,
             const std::vector<int>& object_keyframes) {
    options_ = options;
    graph_ = std::make_unique<FactorGraph>(
        options_, keyframes_, objects_, points_, &statistics_);
    for (int k = 0; k < n; ++k) {
      auto kf = std::make_unique<KeyframeState>();
      kf->id = k;
      WritePose(Truth(k), kf->q, kf->t);
      keyframes_.push_back(std::move(kf));
      graph_->SetManifold(keyframes_[k]->q, &quaternion_);
      if (k == 0) continue;
      FactorRecord odometry;
      odometry.cost.reset(RelativePoseFactor::Create(
          Truth(k - 1).Inverse() * Truth(k), Matrix6d::Identity() * 10.0));
      odometry.blocks = {keyframes_[k - 1]->q,
                         keyframes_[k - 1]->t,
                         keyframes_[k]->q,
                         keyframes_[k]->t};
      odometry.keyframe = k;
      odometry.keyframe2 = k - 1;
      odometry_.push_back(graph_->Add(std::move(odometry)));
    }
    auto object = std::make_unique<ObjectState>();
    WritePose(ObjectTruth(), object->q, object->t);
    graph_->SetManifold(object->q, &quaternion_);
    objects_.push_back(std::move(object));
    for (int k : object_keyframes) {
      ObjectObservation observation;
      observation.keyframe = k;
      observation.components = {PoseComponent{}};
      FactorRecord edge;
      edge.cost.reset(
          PosePriorFactor::Create(ObjectTruth(), Matrix6d::Identity()));
      edge.blocks = {objects_[0]->q, objects_[0]->t};
      edge.keyframe = k;
      edge.object = 0;
      edge.observation = static_cast<int>(objects_[0]->observations.size());
      observation.factor = graph_->Add(std::move(edge));
      objects_[0]->observations.push_back(std::move(observation));
    }
  }

  static Rigid3d Truth(int k) {
    return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(k, 0, 0));
  }
  static Rigid3d ObjectTruth() {
    return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(2, 1, 0));
  }
  void Perturb(int k) {
    Eigen::Map<Eigen::Vector3d>(keyframes_[k]->t) +=
        Eigen::Vector3d(0.3, -0.2, 0.1);
  }

  BackendOptions options_;
  KeyframeList keyframes_;
  ObjectList objects_;
  PointList points_;
  BackendStatistics statistics_;
  ceres::EigenQuaternionManifold quaternion_;
  std::unique_ptr<FactorGraph> graph_;
  std::vector<int> odometry_;
};

// marginalize: keyframes 0-2 leave; the window holds the odometry factors
// 3->4 and 4->5 and the keyframe prior on keyframe 3's pose, and solves the
// perturbed window back to the truth.
TEST_F(FactorGraphTest, WindowHoldsItsFactorsAndTheKeyframePrior) {
  Build(BackendOptions(), 6, {});
  for (int k = 3; k < 6; ++k) Perturb(k);
  SolveOutcome outcome;
  graph_->SolveWindow(3, &outcome);
  EXPECT_EQ(statistics_.marginalized_keyframes, 3);
  EXPECT_EQ(outcome.residual_blocks, 3);
  EXPECT_EQ(outcome.prior_size, 6);
  EXPECT_EQ(outcome.free_keyframes, 3);
  ASSERT_TRUE(outcome.solved && outcome.usable);
  for (int k = 3; k < 6; ++k) {
    EXPECT_LT((keyframes_[k]->T_wc().t - Truth(k).t).norm(), 1e-6) << k;
  }
  // Keyframes that left keep no factor list.
  EXPECT_TRUE(keyframes_[0]->factors.empty());
  EXPECT_FALSE(keyframes_[4]->factors.empty());
}

// condition: nothing leaves; every keyframe that shares a factor with the
// window is held constant.
TEST_F(FactorGraphTest, ConditionHoldsEarlierKeyframesConstant) {
  BackendOptions options;
  options.window_policy = WindowPolicy::kCondition;
  Build(options, 6, {});
  SolveOutcome outcome;
  graph_->SolveWindow(3, &outcome);
  EXPECT_EQ(statistics_.marginalized_keyframes, 0);
  // 2->3, 3->4 and 4->5: keyframe 2 enters, constant.
  EXPECT_EQ(outcome.residual_blocks, 3);
  EXPECT_EQ(outcome.prior_size, 0);
  EXPECT_EQ(outcome.free_keyframes, 3);
}

// A retired factor and the edges of an object that is not confirmed stay
// out of every solve.
TEST_F(FactorGraphTest, RetiredFactorsAndUnconfirmedObjectsStayOut) {
  Build(BackendOptions(), 4, {1, 2});
  SolveOutcome outcome;
  graph_->SolveWindow(0, &outcome);
  EXPECT_EQ(outcome.residual_blocks, 3 + 2);
  objects_[0]->status = ObjectStatus::kTentative;
  graph_->SolveWindow(0, &outcome);
  EXPECT_EQ(outcome.residual_blocks, 3);
  graph_->Retire(odometry_[1]);
  graph_->SolveWindow(0, &outcome);
  EXPECT_EQ(outcome.residual_blocks, 2);
}

// The object's first live observation follows the window; without
// keep_history the observations that left lose their hypotheses and the
// batch solve is refused; with it they keep them and the batch solves
// every factor (never the priors).
TEST_F(FactorGraphTest, LeavingFreesWhatOnlyTheBatchNeedsUnlessKept) {
  for (bool keep_history : {false, true}) {
    SCOPED_TRACE(keep_history);
    graph_.reset();
    keyframes_.clear();
    objects_.clear();
    odometry_.clear();
    statistics_ = BackendStatistics();
    BackendOptions options;
    options.keep_history = keep_history;
    Build(options, 6, {0, 2, 4});
    EXPECT_EQ(graph_->FirstLiveObservation(*objects_[0]), 0);
    SolveOutcome outcome;
    graph_->SolveWindow(3, &outcome);
    EXPECT_EQ(graph_->FirstLiveObservation(*objects_[0]), 2);
    const auto& observations = objects_[0]->observations;
    EXPECT_EQ(observations[0].components.empty(), !keep_history);
    EXPECT_EQ(observations[1].components.empty(), !keep_history);
    EXPECT_FALSE(observations[2].components.empty());
    const Status batch = graph_->SolveBatch(&outcome);
    EXPECT_EQ(batch.ok(), keep_history) << batch.message();
    if (keep_history) {
      EXPECT_EQ(outcome.residual_blocks, 5 + 3);
      EXPECT_EQ(outcome.prior_size, 0);
    }
  }
}

// A point seen from keyframes 0-2 gets its prior when they leave; a loop
// closure's move with an added variance keeps the prior's mean and leaves
// it the information (L^-1 + var I)^-1.
TEST_F(FactorGraphTest, AMovedPointsPriorLosesTheMovesVariance) {
  Build(BackendOptions(), 6, {});
  PinholeIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 500.0;
  intrinsics.cx = 320.0;
  intrinsics.cy = 240.0;
  const Eigen::Vector3d p_w(2.0, 1.0, 5.0);
  auto point = std::make_unique<PointState>();
  Eigen::Map<Eigen::Vector3d>(point->p) = p_w;
  point->first_keyframe = 0;
  point->last_keyframe = 2;
  points_.push_back(std::move(point));
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d p_c = Truth(k).Inverse() * p_w;
    const Eigen::Vector2d uv(intrinsics.fx * p_c.x() / p_c.z() + intrinsics.cx,
                             intrinsics.fy * p_c.y() / p_c.z() + intrinsics.cy);
    FactorRecord observation;
    observation.cost.reset(ReprojectionFactor::Create(
        intrinsics, uv, Eigen::Matrix2d::Identity()));
    observation.blocks = {keyframes_[k]->q, keyframes_[k]->t, points_[0]->p};
    observation.keyframe = k;
    observation.point = 0;
    graph_->Add(std::move(observation));
  }
  // Off the truth: the prior is made here, and its minimum is not x0.
  Eigen::Map<Eigen::Vector3d>(points_[0]->p) +=
      Eigen::Vector3d(0.05, -0.03, 0.04);
  SolveOutcome outcome;
  graph_->SolveWindow(3, &outcome);
  ASSERT_GE(points_[0]->prior_factor, 0);
  auto prior_of_point = [&]() -> const MarginalPriorFactor& {
    return dynamic_cast<const MarginalPriorFactor&>(
        *graph_->factor(points_[0]->prior_factor).cost);
  };
  const Eigen::Matrix3d L = prior_of_point().Information();
  ASSERT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(L)
                .eigenvalues()
                .minCoeff(),
            0.0);
  // Where the prior has its minimum (a Euclidean block: x0 + d*).
  auto minimum = [](const MarginalPriorFactor& prior) -> Eigen::Vector3d {
    return prior.blocks()[0].x0 +
           prior.A().completeOrthogonalDecomposition().solve(-prior.e());
  };
  const Eigen::Vector3d before = minimum(prior_of_point());
  EXPECT_GT((before - Eigen::Map<const Eigen::Vector3d>(points_[0]->p)).norm(),
            0.01);
  const Rigid3d W(Eigen::Quaterniond(Eigen::AngleAxisd(
                      0.3, Eigen::Vector3d(1, 2, 3).normalized())),
                  Eigen::Vector3d(0.5, -0.2, 0.1));
  const double variance = 0.04;
  graph_->MovePriors(std::vector<Rigid3d>(keyframes_.size()),
                     std::vector<Rigid3d>(objects_.size()),
                     {W},
                     {variance});
  // Moved, then (L^-1 + var I)^-1 in the moved frame: R (.) R^T.
  const Eigen::Matrix3d R = W.q.toRotationMatrix();
  const Eigen::Matrix3d expected =
      R * (L.inverse() + variance * Eigen::Matrix3d::Identity()).inverse() *
      R.transpose();
  EXPECT_LT((prior_of_point().Information() - expected).norm(),
            1e-9 * expected.norm());
  EXPECT_LT((minimum(prior_of_point()) - W * before).norm(), 1e-9);
}

}  // namespace
}  // namespace symba::internal
