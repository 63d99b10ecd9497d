// The keyframe graph's noise calibration for its covariances
// (src/backend/graph_noise_calibration.h): each group's variance factor is
// the mean squared whitened residual per degree of freedom, inflated for
// residuals that persist, at least kMinVarianceFactor where the estimate
// was held by something else and at least 1 where not.
#include "backend/graph_noise_calibration.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "symba/geometry/so3.h"
#include "test_support/random.h"

namespace symba::internal {
namespace {

constexpr double kStatedT = 0.02;  // m
constexpr double kStatedR = 0.01;  // rad

Matrix6d Information(double weight) {
  Matrix6d information = Matrix6d::Zero();
  information.topLeftCorner<3, 3>().diagonal().setConstant(
      weight / (kStatedT * kStatedT));
  information.bottomRightCorner<3, 3>().diagonal().setConstant(
      weight / (kStatedR * kStatedR));
  return information;
}

// A chain of `errors.size()` steps of 1 m along x, the poses exact and each
// step measured off by errors[i] = (translation, rotation vector), every
// step stated at kStatedT, kStatedR; roles in one group "steps", chained.
struct Chain {
  PoseGraph graph;
  std::vector<GraphEdgeRole> roles;
};

Chain MakeChain(const std::vector<Vector6<double>>& errors, bool held) {
  Chain chain;
  const int n = static_cast<int>(errors.size());
  for (int k = 0; k <= n; ++k) {
    chain.graph.poses[k] =
        Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(k, 0.0, 0.0));
  }
  chain.graph.fixed.insert(0);
  for (int i = 0; i < n; ++i) {
    const Rigid3d truth(Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(1.0, 0.0, 0.0));
    const Rigid3d error(ExpSO3(Eigen::Vector3d(errors[i].tail<3>())),
                        errors[i].head<3>());
    chain.graph.edges.push_back({i, i + 1, truth * error, Information(1.0)});
    GraphEdgeRole role;
    role.group = "steps";
    role.held_by_others = held;
    role.previous = i - 1;
    chain.roles.push_back(role);
  }
  return chain;
}

std::vector<Vector6<double>> WhiteErrors(int n,
                                         double sigma_t,
                                         double sigma_r,
                                         unsigned seed) {
  testing::TestRandom random(seed);
  std::vector<Vector6<double>> errors(n);
  for (Vector6<double>& e : errors) {
    e << random.NormalVector(sigma_t), random.NormalVector(sigma_r);
  }
  return errors;
}

struct Calibration {
  std::vector<EdgeNoiseFactors> factors;
  std::vector<CovarianceNoiseGroup> groups;
};

Calibration Calibrate(const Chain& chain) {
  Calibration c;
  CalibrateGraphNoise(chain.graph, chain.roles, &c.factors, &c.groups);
  return c;
}

TEST(GraphNoiseCalibration, AHeldGroupGetsTheNoiseItsResidualsShow) {
  // Steps whose noise is half what they state: variance factor 0.25.
  const Calibration c =
      Calibrate(MakeChain(WhiteErrors(600, 0.5 * kStatedT, 0.5 * kStatedR, 3),
                          /*held=*/true));
  ASSERT_EQ(c.groups.size(), 1u);
  EXPECT_EQ(c.groups[0].name, "steps");
  EXPECT_EQ(c.groups[0].edges, 600);
  EXPECT_EQ(c.groups[0].residuals, 600);
  EXPECT_TRUE(c.groups[0].held_by_others);
  // 1800 degrees of freedom: the mean of chi-square / dof within 4 % (1 sd).
  EXPECT_NEAR(c.groups[0].factor_t, 0.25, 0.25 * 0.15);
  EXPECT_NEAR(c.groups[0].factor_r, 0.25, 0.25 * 0.15);
  EXPECT_LT(c.groups[0].correlation_t, 0.1);
  ASSERT_EQ(c.factors.size(), 600u);
  EXPECT_EQ(c.factors[17].translation, c.groups[0].factor_t);
  EXPECT_EQ(c.factors[17].rotation, c.groups[0].factor_r);
}

TEST(GraphNoiseCalibration, AnUnheldGroupIsNeverFoundBetterThanStated) {
  // The same residuals where nothing else held the estimate: they bound
  // the noise from below only. Twice the stated noise shows.
  const Calibration better =
      Calibrate(MakeChain(WhiteErrors(600, 0.5 * kStatedT, 0.5 * kStatedR, 3),
                          /*held=*/false));
  EXPECT_EQ(better.groups[0].factor_t, 1.0);
  EXPECT_EQ(better.groups[0].factor_r, 1.0);
  EXPECT_NEAR(better.groups[0].residual_t, 0.25, 0.25 * 0.15);
  const Calibration worse = Calibrate(MakeChain(
      WhiteErrors(600, 2.0 * kStatedT, 2.0 * kStatedR, 4), /*held=*/false));
  EXPECT_NEAR(worse.groups[0].factor_t, 4.0, 4.0 * 0.15);
  EXPECT_NEAR(worse.groups[0].factor_r, 4.0, 4.0 * 0.15);
}

TEST(GraphNoiseCalibration, ErrorsThatPersistAreInflated) {
  // An AR(1) error e_i = a e_{i-1} + sqrt(1 - a^2) n_i with a = 0.8 and the
  // stated noise as its marginal: the variance factor of its sums is
  // (1 + a) / (1 - a) = 9.
  constexpr double a = 0.8;
  testing::TestRandom random(5);
  std::vector<Vector6<double>> errors(4000);
  Vector6<double> e;
  e << random.NormalVector(kStatedT), random.NormalVector(kStatedR);
  for (Vector6<double>& out : errors) {
    Vector6<double> n;
    n << random.NormalVector(kStatedT), random.NormalVector(kStatedR);
    e = a * e + std::sqrt(1.0 - a * a) * n;
    out = e;
  }
  const Calibration c = Calibrate(MakeChain(errors, /*held=*/true));
  EXPECT_NEAR(c.groups[0].correlation_t, a, 0.03);
  EXPECT_NEAR(c.groups[0].correlation_r, a, 0.03);
  EXPECT_NEAR(c.groups[0].residual_t, 1.0, 0.15);
  EXPECT_NEAR(c.groups[0].factor_t, 9.0, 9.0 * 0.25);
  EXPECT_NEAR(c.groups[0].factor_r, 9.0, 9.0 * 0.25);
}

TEST(GraphNoiseCalibration, ExactValuesOfWeighedEdgesAndTheirBounds) {
  // Ten edges of one object, each standing for 4 detections (information
  // 4 / s^2), all off by (e, 0, 0) with e = s / 2 and no rotation measured:
  // residual_t = (4 e^2 / s^2) / 4 / 3 = 1 / 12; identical consecutive
  // residuals correlate fully: rho clamped to 0.98, factor 99 / 12.
  Chain chain =
      MakeChain(std::vector<Vector6<double>>(10, Vector6<double>::Zero()),
                /*held=*/true);
  for (size_t i = 0; i < chain.graph.edges.size(); ++i) {
    PoseGraphEdge& edge = chain.graph.edges[i];
    edge.T_ab.t.x() += 0.5 * kStatedT;
    edge.information = Information(4.0);
    chain.roles[i].group = "detections chair";
    chain.roles[i].weight = 4.0;
    chain.roles[i].rotation_dof = 0;
  }
  Calibration c = Calibrate(chain);
  ASSERT_EQ(c.groups.size(), 1u);
  EXPECT_NEAR(c.groups[0].residual_t, 1.0 / 12.0, 1e-12);
  EXPECT_NEAR(c.groups[0].correlation_t, kMaxCorrelation, 1e-12);
  EXPECT_NEAR(c.groups[0].factor_t,
              (1.0 + kMaxCorrelation) / (1.0 - kMaxCorrelation) / 12.0,
              1e-9);
  EXPECT_EQ(c.groups[0].factor_r, 1.0);  // no rotation measured

  // Without predecessors no correlation: 1 / 12 as it is; exact residuals
  // at the floor kMinVarianceFactor.
  for (GraphEdgeRole& role : chain.roles) role.previous = -1;
  c = Calibrate(chain);
  EXPECT_EQ(c.groups[0].correlation_t, 0.0);
  EXPECT_NEAR(c.groups[0].factor_t, 1.0 / 12.0, 1e-12);
  for (PoseGraphEdge& edge : chain.graph.edges) edge.T_ab.t.x() = 1.0;
  c = Calibrate(chain);
  EXPECT_EQ(c.groups[0].factor_t, kMinVarianceFactor);

  // Fewer than kMinGroupResiduals measured residuals: as stated; an edge
  // without a group (a loop closure) too.
  for (size_t i = 0; i < chain.roles.size(); ++i) {
    chain.roles[i].measured = i < kMinGroupResiduals - 1;
  }
  chain.roles[3].group.clear();
  c = Calibrate(chain);
  ASSERT_EQ(c.groups.size(), 1u);
  EXPECT_EQ(c.groups[0].edges, 9);
  EXPECT_EQ(c.groups[0].residuals, kMinGroupResiduals - 2);
  EXPECT_EQ(c.groups[0].factor_t, 1.0);
  EXPECT_EQ(c.factors[3].translation, 1.0);
  EXPECT_EQ(c.factors[3].rotation, 1.0);
}

}  // namespace
}  // namespace symba::internal
