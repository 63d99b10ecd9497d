// Map objects' covariances (src/backend/object_covariances.h) on problems
// whose answer is known: n detections of an object from a keyframe held
// constant, each with isotropic noise sigma_t, sigma_r, give a position
// covariance sigma_t^2 / n I and a rotation covariance sigma_r^2 / n I
// (rad^2, world frame), whether the object is in the last solve or only in
// the prior its marginalised detections left. The edge's error is
// Log(T_co_measured T_co^-1), whose translation carries the rotation error
// times the object's distance from the camera: the cameras here are at the
// object's origin, so position and rotation are uncorrelated.
#include "backend/object_covariances.h"

#include <memory>
#include <vector>

#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "backend/object_edges.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/manifolds/axis_manifold.h"

namespace symba::internal {
namespace {

constexpr double kSigmaT = 0.1;  // m
constexpr double kSigmaR = 0.2;  // rad

// Cameras turning about the object's origin.
Rigid3d Camera(int k) {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * k, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(2, 1, 0));
}
Rigid3d ObjectPose() {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(2, 1, 0));
}

class ObjectCovariancesTest : public ::testing::Test {
 protected:
  // n keyframes with exact odometry; one object of `type` at
  // ObjectPose().
  void Build(int n, SymmetryType type) {
    graph_ = std::make_unique<FactorGraph>(
        options_, keyframes_, objects_, points_, &statistics_);
    edges_ = std::make_unique<ObjectEdges>(
        options_, keyframes_, &objects_, graph_.get());
    for (int k = 0; k < n; ++k) {
      keyframes_.push_back(std::make_unique<KeyframeState>());
      WritePose(Camera(k), keyframes_[k]->q, keyframes_[k]->t);
      graph_->SetManifold(keyframes_[k]->q, &quaternion_);
      if (k == 0) continue;
      FactorRecord odometry;
      odometry.cost.reset(RelativePoseFactor::Create(
          Camera(k - 1).Inverse() * Camera(k), Matrix6d::Identity() * 100.0));
      odometry.blocks = {keyframes_[k - 1]->q,
                         keyframes_[k - 1]->t,
                         keyframes_[k]->q,
                         keyframes_[k]->t};
      odometry.keyframe = k;
      odometry.keyframe2 = k - 1;
      graph_->Add(std::move(odometry));
    }
    auto object = std::make_unique<ObjectState>();
    object->type = type;
    WritePose(ObjectPose(), object->q, object->t);
    if (type != SymmetryType::kAsymmetric) {
      object->a_o = Eigen::Vector3d::UnitZ();
      object->anchor =
          SymmetryAnchor::FromObjectRotation(ObjectPose().q, object->a_o);
      Eigen::Map<Eigen::Vector3d>(object->a_w) = object->anchor.a_w0;
      object->thetas.push_back(std::make_unique<double>(0.0));
    }
    graph_->SetManifold(object->q, &quaternion_);
    graph_->SetManifold(object->a_w, &axis_);
    objects_.push_back(std::move(object));
  }

  // A detection of the object from keyframe k, exactly where it is.
  void Detect(int k) {
    ObjectObservation observation;
    observation.keyframe = k;
    observation.T_co_best = Camera(k).Inverse() * ObjectPose();
    PoseComponent component;
    component.T_co = observation.T_co_best;
    component.sqrt_info = IsotropicPoseSqrtInfo(kSigmaT, kSigmaR);
    observation.components = {component};
    observation.sigma_t = kSigmaT;
    observation.sigma_r = kSigmaR;
    observation.claimed_t = observation.claimed_r = true;
    if (objects_[0]->type == SymmetryType::kDiscrete) observation.angle = 0;
    edges_->Add(0, observation);
  }

  MapObjectCovariance Covariance() {
    std::vector<MapObjectCovariance> covariances;
    const Status status =
        ObjectCovariances(objects_, graph_.get(), &covariances);
    EXPECT_TRUE(status.ok()) << status.message();
    EXPECT_EQ(covariances.size(), 1u);
    return covariances.empty() ? MapObjectCovariance() : covariances[0];
  }

  BackendOptions options_;
  KeyframeList keyframes_;
  ObjectList objects_;
  PointList points_;
  BackendStatistics statistics_;
  ceres::EigenQuaternionManifold quaternion_;
  AxisManifold axis_;
  std::unique_ptr<FactorGraph> graph_;
  std::unique_ptr<ObjectEdges> edges_;
};

// Four detections from the gauge keyframe (held constant).
TEST_F(ObjectCovariancesTest, AnAsymmetricObjectInTheSolve) {
  Build(1, SymmetryType::kAsymmetric);
  for (int i = 0; i < 4; ++i) Detect(0);
  SolveOutcome outcome;
  graph_->SolveWindow(0, &outcome);
  const MapObjectCovariance c = Covariance();
  EXPECT_EQ(c.source, MapObjectCovariance::Source::kSolve);
  EXPECT_LT(
      (c.position - Eigen::Matrix3d::Identity() * kSigmaT * kSigmaT / 4).norm(),
      1e-9);
  ASSERT_TRUE(c.rotation.has_value());
  EXPECT_LT((*c.rotation - Eigen::Matrix3d::Identity() * kSigmaR * kSigmaR / 4)
                .norm(),
            1e-9);
  EXPECT_FALSE(c.axis.has_value());
}

// Edges rebuilt after the solve (here as re-anchoring or a noise update
// would) are in the covariance: the problem is synced again first.
TEST_F(ObjectCovariancesTest, EdgesRebuiltAfterTheSolveCount) {
  Build(1, SymmetryType::kAsymmetric);
  for (int i = 0; i < 4; ++i) Detect(0);
  SolveOutcome outcome;
  graph_->SolveWindow(0, &outcome);
  edges_->Rebuild(0);
  Detect(0);  // a fifth, added since
  const MapObjectCovariance c = Covariance();
  EXPECT_EQ(c.source, MapObjectCovariance::Source::kSolve);
  EXPECT_LT(
      (c.position - Eigen::Matrix3d::Identity() * kSigmaT * kSigmaT / 5).norm(),
      1e-9);
}

// Keyframes 0 and 1 see the object and leave the window (marginalize): the
// window (2, 3) does not hold it, its prior does, with the information of
// both detections on the object alone.
TEST_F(ObjectCovariancesTest, AnObjectOutsideTheWindowFromItsPrior) {
  Build(4, SymmetryType::kAsymmetric);
  Detect(0);
  Detect(1);
  SolveOutcome outcome;
  graph_->SolveWindow(2, &outcome);
  const MapObjectCovariance c = Covariance();
  EXPECT_EQ(c.source, MapObjectCovariance::Source::kPrior);
  EXPECT_LT(
      (c.position - Eigen::Matrix3d::Identity() * kSigmaT * kSigmaT / 2).norm(),
      1e-9);
  ASSERT_TRUE(c.rotation.has_value());
  EXPECT_LT((*c.rotation - Eigen::Matrix3d::Identity() * kSigmaR * kSigmaR / 2)
                .norm(),
            1e-9);
}

// A discrete object: its position as above, an axis covariance tangent to
// the axis (rank 2) and its angle's variance.
TEST_F(ObjectCovariancesTest, ADiscreteObjectsAxisAndAngle) {
  Build(1, SymmetryType::kDiscrete);
  for (int i = 0; i < 2; ++i) Detect(0);
  SolveOutcome outcome;
  graph_->SolveWindow(0, &outcome);
  const MapObjectCovariance c = Covariance();
  EXPECT_LT(
      (c.position - Eigen::Matrix3d::Identity() * kSigmaT * kSigmaT / 2).norm(),
      1e-9);
  ASSERT_TRUE(c.axis.has_value());
  const Eigen::Vector3d a_w = objects_[0]->axis_w();
  EXPECT_LT((*c.axis * a_w).norm(), 1e-12);
  // Tilting the axis is a rotation of the object about a horizontal axis:
  // sigma_r^2 / 2 in each tangent direction.
  EXPECT_NEAR(c.axis->trace(), 2 * kSigmaR * kSigmaR / 2, 1e-9);
  ASSERT_EQ(c.angle_variances.size(), 1u);
  ASSERT_TRUE(c.angle_variances[0].has_value());
  EXPECT_NEAR(*c.angle_variances[0], kSigmaR * kSigmaR / 2, 1e-9);
  EXPECT_FALSE(c.rotation.has_value());
}

// Nothing solved yet: no covariance, no error.
TEST_F(ObjectCovariancesTest, NoSolveNoCovariance) {
  Build(1, SymmetryType::kAsymmetric);
  Detect(0);
  std::vector<MapObjectCovariance> covariances;
  EXPECT_TRUE(ObjectCovariances(objects_, graph_.get(), &covariances).ok());
  EXPECT_TRUE(covariances.empty());
}

}  // namespace
}  // namespace symba::internal
