// Marginal covariances of pose-graph vertices
// (symba/pose_graph/pose_graph_covariance.h) against the linear propagation
// worked out by hand for a chain whose measurements the poses reproduce:
//
//   vertex 0 (fixed) -> 1 at (1, 0, 0) -> 2 at (1, 1, 0), all rotations the
//   identity, each edge measuring the pose of its end with information
//   diag(I / s_t^2, I / s_r^2) (rotation rows in radians).
//
// To first order, with each vertex's error (dt, w) in the world frame
// (t <- t + dt, R <- Exp(w) R) and each edge's noise (n_t, n_r):
//   dt_1 = n_t1,                    w_1 = n_r1
//   dt_2 = dt_1 + w_1 x d + n_t2,   w_2 = w_1 + n_r2,   d = t_2 - t_1
// so Cov(t_1) = s_t^2 I, Cov(w_1) = s_r^2 I, Cov(t_1, w_1) = 0,
//    Cov(t_2) = 2 s_t^2 I + s_r^2 Hat(d) Hat(d)^T, Cov(w_2) = 2 s_r^2 I,
//    Cov(t_2, w_2) = -s_r^2 Hat(d)  (w x d = -Hat(d) w).
#include "symba/pose_graph/pose_graph_covariance.h"

#include <gtest/gtest.h>

#include "symba/geometry/so3.h"

namespace symba {
namespace {

constexpr double kSigmaT = 0.1;   // m
constexpr double kSigmaR = 0.02;  // rad

Matrix6d Information() {
  Matrix6d information = Matrix6d::Zero();
  information.topLeftCorner<3, 3>() =
      Eigen::Matrix3d::Identity() / (kSigmaT * kSigmaT);
  information.bottomRightCorner<3, 3>() =
      Eigen::Matrix3d::Identity() / (kSigmaR * kSigmaR);
  return information;
}

PoseGraph Chain() {
  PoseGraph graph;
  const Eigen::Quaterniond I = Eigen::Quaterniond::Identity();
  graph.poses[0] = Rigid3d(I, Eigen::Vector3d::Zero());
  graph.poses[1] = Rigid3d(I, Eigen::Vector3d(1, 0, 0));
  graph.poses[2] = Rigid3d(I, Eigen::Vector3d(1, 1, 0));
  graph.edges.push_back(
      {0, 1, Rigid3d(I, Eigen::Vector3d(1, 0, 0)), Information()});
  graph.edges.push_back(
      {1, 2, Rigid3d(I, Eigen::Vector3d(0, 1, 0)), Information()});
  graph.fixed.insert(0);
  return graph;
}

void ExpectNear(const Eigen::MatrixXd& actual,
                const Eigen::MatrixXd& expected) {
  EXPECT_LT((actual - expected).cwiseAbs().maxCoeff(), 1e-9)
      << "actual\n"
      << actual << "\nexpected\n"
      << expected;
}

TEST(PoseGraphCovariances, AChainPropagatesAsWorkedOutByHand) {
  std::vector<Matrix6d> c;
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {1, 2}, {}, &c).ok());
  ASSERT_EQ(c.size(), 2u);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double vt = kSigmaT * kSigmaT;
  const double vr = kSigmaR * kSigmaR;
  ExpectNear(c[0].topLeftCorner<3, 3>(), vt * I);
  ExpectNear(c[0].bottomRightCorner<3, 3>(), vr * I);
  ExpectNear(c[0].topRightCorner<3, 3>(), Eigen::Matrix3d::Zero());
  const Eigen::Matrix3d D = Hat(Eigen::Vector3d(0, 1, 0));
  ExpectNear(c[1].topLeftCorner<3, 3>(), 2 * vt * I + vr * D * D.transpose());
  ExpectNear(c[1].bottomRightCorner<3, 3>(), 2 * vr * I);
  ExpectNear(c[1].topRightCorner<3, 3>(), -vr * D);
  ExpectNear(c[1].bottomLeftCorner<3, 3>(), -vr * D.transpose());
}

TEST(PoseGraphCovariances, InTheWorldFrameWhateverTheVerticesRotation) {
  // The same chain with vertices 1 and 2 turned 90 degrees about z (the
  // measurements turned with them). The edges' information is isotropic,
  // so the world-frame covariances are those above; in a vertex's own
  // frame (GTSAM's Pose3 marginals) vertex 2's would be turned by R^T:
  // Hat(d) Hat(d)^T = diag(1, 0, 1) would read diag(0, 1, 1).
  PoseGraph graph = Chain();
  const Eigen::Quaterniond Rz(Eigen::AngleAxisd(0.5 * 3.14159265358979323846,
                                                Eigen::Vector3d::UnitZ()));
  graph.poses[1].q = Rz;
  graph.poses[2].q = Rz;
  graph.edges[0].T_ab = graph.poses[0].Inverse() * graph.poses[1];
  graph.edges[1].T_ab = graph.poses[1].Inverse() * graph.poses[2];
  std::vector<Matrix6d> turned;
  std::vector<Matrix6d> straight;
  ASSERT_TRUE(PoseGraphCovariances(graph, {1, 2}, {}, &turned).ok());
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {1, 2}, {}, &straight).ok());
  ExpectNear(turned[0], straight[0]);
  ExpectNear(turned[1], straight[1]);
}

TEST(PoseGraphCovariances, TheGaugeIsZeroAndARequestTwiceIsAnswered) {
  std::vector<Matrix6d> c;
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {0, 2, 2}, {}, &c).ok());
  ASSERT_EQ(c.size(), 3u);
  EXPECT_TRUE(c[0].isZero(0.0));
  ExpectNear(c[1], c[2]);
  EXPECT_GT(c[1](0, 0), 0.0);
}

TEST(PoseGraphCovariances, AHeldRotationIsKnown) {
  // Vertex 1's rotation held: vertex 2's position no longer gets its
  // lever arm, and vertex 2's rotation only its own edge's noise.
  PoseGraphCovarianceOptions options;
  options.rotation_held = {1};
  std::vector<Matrix6d> c;
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {1, 2}, options, &c).ok());
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double vt = kSigmaT * kSigmaT;
  const double vr = kSigmaR * kSigmaR;
  ExpectNear(c[0].bottomRightCorner<3, 3>(), Eigen::Matrix3d::Zero());
  ExpectNear(c[0].topLeftCorner<3, 3>(), vt * I);
  ExpectNear(c[1].topLeftCorner<3, 3>(), 2 * vt * I);
  ExpectNear(c[1].bottomRightCorner<3, 3>(), vr * I);
}

TEST(PoseGraphCovariances, WithoutAFixedVertexTheSmallestIdIsTheGauge) {
  PoseGraph graph = Chain();
  graph.fixed.clear();
  std::vector<Matrix6d> fixed;
  std::vector<Matrix6d> smallest;
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {2}, {}, &fixed).ok());
  ASSERT_TRUE(PoseGraphCovariances(graph, {2}, {}, &smallest).ok());
  ExpectNear(smallest[0], fixed[0]);
}

TEST(PoseGraphCovariances, RefusesWhatItCannotAnswer) {
  std::vector<Matrix6d> c = {Matrix6d::Identity()};
  PoseGraph graph = Chain();
  graph.poses[7] = Rigid3d();
  Status s = PoseGraphCovariances(graph, {7}, {}, &c);
  EXPECT_EQ(s.message(), "pose graph covariance: vertex 7 has no edge");
  graph.edges[1].information(0, 0) = -1.0;
  s = PoseGraphCovariances(graph, {1}, {}, &c);
  EXPECT_NE(s.message().find("pose graph: edge 1 (1 -> 2)"), std::string::npos)
      << s.message();
  PoseGraphCovarianceOptions options;
  options.num_threads = 0;
  s = PoseGraphCovariances(Chain(), {1}, options, &c);
  EXPECT_EQ(s.message(), "pose graph covariance: num_threads = 0 is below 1");
  ASSERT_EQ(c.size(), 1u);  // untouched
  EXPECT_TRUE(c[0].isIdentity(0.0));
}

// The chain with a third edge 0 -> 2 that agrees with the other two, so that
// every vertex has more than one path to the gauge.
PoseGraph ChainWithShortcut() {
  PoseGraph graph = Chain();
  graph.edges.push_back(
      {0, 2, graph.poses[0].Inverse() * graph.poses[2], 2.0 * Information()});
  return graph;
}

std::vector<EdgeNoiseFactors> Factors(size_t edges,
                                      double translation,
                                      double rotation) {
  return std::vector<EdgeNoiseFactors>(edges, {translation, rotation});
}

void ExpectRelativelyNear(const Matrix6d& actual, const Matrix6d& expected) {
  EXPECT_LT((actual - expected).cwiseAbs().maxCoeff(),
            1e-9 * expected.cwiseAbs().maxCoeff())
      << "actual\n"
      << actual << "\nexpected\n"
      << expected;
}

TEST(PoseGraphCovariances, NoiseAsItsInformationSaysGivesTheInverse) {
  // Factors of one: H^-1 (J^T J) H^-1 = H^-1, by another route (Eigen's
  // sparse LDL^T against Ceres's covariance); factors of c: c H^-1.
  const PoseGraph graph = ChainWithShortcut();
  std::vector<Matrix6d> inverse;
  ASSERT_TRUE(PoseGraphCovariances(graph, {1, 2}, {}, &inverse).ok());
  PoseGraphCovarianceOptions options;
  options.noise_factors = Factors(graph.edges.size(), 1.0, 1.0);
  std::vector<Matrix6d> sandwich;
  ASSERT_TRUE(PoseGraphCovariances(graph, {1, 2}, options, &sandwich).ok());
  ASSERT_EQ(sandwich.size(), 2u);
  ExpectRelativelyNear(sandwich[0], inverse[0]);
  ExpectRelativelyNear(sandwich[1], inverse[1]);
  options.noise_factors = Factors(graph.edges.size(), 2.5, 2.5);
  ASSERT_TRUE(PoseGraphCovariances(graph, {1, 2}, options, &sandwich).ok());
  ExpectRelativelyNear(sandwich[0], 2.5 * inverse[0]);
  ExpectRelativelyNear(sandwich[1], 2.5 * inverse[1]);
  // A held rotation and the gauge, as without factors.
  options.rotation_held = {1};
  PoseGraphCovarianceOptions held;
  held.rotation_held = {1};
  ASSERT_TRUE(PoseGraphCovariances(graph, {0, 1, 2}, held, &inverse).ok());
  ASSERT_TRUE(PoseGraphCovariances(graph, {0, 1, 2}, options, &sandwich).ok());
  EXPECT_TRUE(sandwich[0].isZero(0.0));
  EXPECT_TRUE((sandwich[1].bottomRightCorner<3, 3>().isZero(0.0)));
  ExpectRelativelyNear(sandwich[1], 2.5 * inverse[1]);
  ExpectRelativelyNear(sandwich[2], 2.5 * inverse[2]);
}

TEST(PoseGraphCovariances,
     TwoEdgesWeighedAlikeButNoisyUnlikeAverageTheirNoise) {
  // Vertex 1 measured twice from the fixed vertex 0 with one information
  // (sigmas s_t, s_r), the second measurement's noise nine times the
  // variance its information says. The estimate is the mean of the two:
  // variance (s^2 + 9 s^2) / 4 = 2.5 s^2 per axis, where H^-1 says s^2 / 2.
  // Translation factors only: the rotation keeps s_r^2 / 2.
  PoseGraph graph;
  const Rigid3d T_w1(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 2, 0));
  graph.poses[0] = Rigid3d();
  graph.poses[1] = T_w1;
  graph.edges.push_back({0, 1, T_w1, Information()});
  graph.edges.push_back({0, 1, T_w1, Information()});
  graph.fixed.insert(0);
  PoseGraphCovarianceOptions options;
  options.noise_factors = {{1.0, 1.0}, {9.0, 1.0}};
  std::vector<Matrix6d> c;
  ASSERT_TRUE(PoseGraphCovariances(graph, {1}, options, &c).ok());
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  ExpectNear(c[0].topLeftCorner<3, 3>(), 2.5 * kSigmaT * kSigmaT * I);
  ExpectNear(c[0].bottomRightCorner<3, 3>(), 0.5 * kSigmaR * kSigmaR * I);
  ExpectNear(c[0].topRightCorner<3, 3>(), Eigen::Matrix3d::Zero());
}

TEST(PoseGraphCovariances, EachEdgesFactorsReachItsOwnRows) {
  // The chain worked out by hand with the second edge's translation noise
  // c times its information's: vertex 1 (the first edge only) keeps its
  // covariance; vertex 2's translation gets c s_t^2 instead of s_t^2 from
  // that edge; the rotations keep theirs.
  constexpr double c = 5.0;
  PoseGraphCovarianceOptions options;
  options.noise_factors = {{1.0, 1.0}, {c, 1.0}};
  std::vector<Matrix6d> got;
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {1, 2}, options, &got).ok());
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double vt = kSigmaT * kSigmaT;
  const double vr = kSigmaR * kSigmaR;
  ExpectNear(got[0].topLeftCorner<3, 3>(), vt * I);
  ExpectNear(got[0].bottomRightCorner<3, 3>(), vr * I);
  const Eigen::Matrix3d D = Hat(Eigen::Vector3d(0, 1, 0));
  ExpectNear(got[1].topLeftCorner<3, 3>(),
             (1.0 + c) * vt * I + vr * D * D.transpose());
  ExpectNear(got[1].bottomRightCorner<3, 3>(), 2 * vr * I);
  ExpectNear(got[1].topRightCorner<3, 3>(), -vr * D);
  // The same factor on the first edge instead: both vertices get it.
  options.noise_factors = {{c, 1.0}, {1.0, 1.0}};
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {1, 2}, options, &got).ok());
  ExpectNear(got[0].topLeftCorner<3, 3>(), c * vt * I);
  ExpectNear(got[1].topLeftCorner<3, 3>(),
             (1.0 + c) * vt * I + vr * D * D.transpose());
  // Only held or gauge vertices asked for: known, as by the inverse.
  ASSERT_TRUE(PoseGraphCovariances(Chain(), {0}, options, &got).ok());
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(got[0].isZero(0.0));
}

TEST(PoseGraphCovariances, RefusesNoiseFactorsItCannotUse) {
  std::vector<Matrix6d> c = {Matrix6d::Identity()};
  PoseGraphCovarianceOptions options;
  options.noise_factors = Factors(1, 1.0, 1.0);
  Status s = PoseGraphCovariances(Chain(), {1}, options, &c);
  EXPECT_EQ(s.message(), "pose graph covariance: 1 noise factors for 2 edges");
  options.noise_factors = {{1.0, 1.0}, {1.0, 0.0}};
  s = PoseGraphCovariances(Chain(), {1}, options, &c);
  EXPECT_EQ(s.message(),
            "pose graph covariance: edge 1's noise factor 0.000000 is not "
            "finite and positive");
  // A rotation nothing measures: rank deficient by this route too.
  PoseGraph graph = Chain();
  graph.edges[1].information.bottomRightCorner<3, 3>() *= 1e-30;
  options.noise_factors = Factors(2, 1.0, 1.0);
  s = PoseGraphCovariances(graph, {2}, options, &c);
  EXPECT_NE(s.message().find("rank deficient"), std::string::npos)
      << s.message();
  ASSERT_EQ(c.size(), 1u);  // untouched
  EXPECT_TRUE(c[0].isIdentity(0.0));
}

}  // namespace
}  // namespace symba
