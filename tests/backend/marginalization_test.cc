// The marginalisation prior (symba/factors/marginal_prior_factor.h) and the
// Schur complement that builds it (src/backend/marginalization.h):
//   - the tangent differences are the manifolds' own Minus;
//   - the prior's Jacobians pass ceres::GradientChecker away from x0, on
//     quaternion, unit-axis and Euclidean blocks;
//   - its information is symmetric positive semi-definite;
//   - on a linear Gaussian problem, where marginalisation is exact, a
//     fixed-lag smoother over a long sequence ends at the batch solution to
//     1e-6 (window states and landmarks);
//   - an ambiguous max-mixture is dropped, a clear one is linearised, and
//     components of one mode are no rivals.
#include "backend/marginalization.h"

#include <cmath>
#include <memory>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/marginal_prior_factor.h"
#include "symba/geometry/angle.h"
#include "symba/manifolds/axis_manifold.h"
#include "test_support/random.h"

namespace symba::internal {
namespace {

using symba::testing::TestRandom;

// ---------------------------------------------------------------------------
// The prior factor.

TEST(PriorTangentDifference, IsTheManifoldsMinus) {
  TestRandom random(3);
  const ceres::EigenQuaternionManifold quaternion;
  const AxisManifold axis;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Quaterniond x0 = random.Rotation();
    const Eigen::Quaterniond y =
        random.RotationOfAngle(random.Uniform(0, 2.5)) * x0;
    double expected[3];
    double delta[3];
    ASSERT_TRUE(
        quaternion.Minus(y.coeffs().data(), x0.coeffs().data(), expected));
    ASSERT_TRUE(PriorTangentDifference(PriorBlockKind::kQuaternion,
                                       4,
                                       y.coeffs().data(),
                                       x0.coeffs().data(),
                                       delta,
                                       nullptr));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(delta[i], expected[i], 1e-12);

    const Eigen::Vector3d a0 = random.UnitVector();
    const Eigen::Vector3d a = (a0 + random.NormalVector(0.5)).normalized();
    ASSERT_TRUE(axis.Minus(a.data(), a0.data(), expected));
    ASSERT_TRUE(PriorTangentDifference(
        PriorBlockKind::kUnitAxis, 3, a.data(), a0.data(), delta, nullptr));
    for (int i = 0; i < 2; ++i) EXPECT_NEAR(delta[i], expected[i], 1e-12);
  }
}

// A prior on a quaternion, a unit axis and a 2-vector with a random A, e.
std::unique_ptr<MarginalPriorFactor> RandomPrior(TestRandom* random,
                                                 const Eigen::Quaterniond& q0,
                                                 const Eigen::Vector3d& a0,
                                                 const Eigen::Vector2d& v0) {
  std::vector<PriorBlock> blocks(3);
  blocks[0] = {PriorBlockKind::kQuaternion, q0.coeffs()};
  blocks[1] = {PriorBlockKind::kUnitAxis, a0};
  blocks[2] = {PriorBlockKind::kEuclidean, v0};
  Eigen::MatrixXd A(7, 7);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = random->Normal(1.0);
  Eigen::VectorXd e(7);
  for (int i = 0; i < 7; ++i) e[i] = random->Normal(1.0);
  std::unique_ptr<MarginalPriorFactor> prior;
  EXPECT_TRUE(MarginalPriorFactor::Create(blocks, A, e, &prior).ok());
  return prior;
}

TEST(MarginalPriorFactor, JacobiansPassTheGradientCheckerAwayFromX0) {
  TestRandom random(7);
  const ceres::EigenQuaternionManifold quaternion;
  const AxisManifold axis;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, &axis, nullptr};
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-3;
  int probes = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::Quaterniond q0 = random.Rotation();
    const Eigen::Vector3d a0 = random.UnitVector();
    const Eigen::Vector2d v0(random.Normal(1.0), random.Normal(1.0));
    const auto prior = RandomPrior(&random, q0, a0, v0);
    // At x0 and up to about 70 degrees / 1 away from it.
    const double spread = trial == 0 ? 0.0 : 0.6;
    Eigen::Quaterniond q =
        trial == 0 ? q0 : random.RotationOfAngle(spread * 2.0) * q0;
    Eigen::Vector3d a = (a0 + random.NormalVector(spread)).normalized();
    Eigen::Vector2d v =
        v0 + Eigen::Vector2d(random.Normal(spread), random.Normal(spread));
    const double* parameters[] = {q.coeffs().data(), a.data(), v.data()};
    const ceres::GradientChecker checker(prior.get(), &manifolds, options);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters, 1e-7, &results)) << results.error_log;
    ++probes;
  }
  EXPECT_EQ(probes, 30);
}

TEST(MarginalPriorFactor, ResidualIsLinearInTheTangentDifference) {
  // r(x0 [+] d) = A d + e exactly (Minus(Plus(x0, d), x0) = d).
  TestRandom random(11);
  const Eigen::Quaterniond q0 = random.Rotation();
  const Eigen::Vector3d a0 = random.UnitVector();
  const Eigen::Vector2d v0(0.5, -1.0);
  const auto prior = RandomPrior(&random, q0, a0, v0);
  Eigen::VectorXd d(7);
  for (int i = 0; i < 7; ++i) d[i] = random.Normal(0.3);
  const ceres::EigenQuaternionManifold quaternion;
  const AxisManifold axis;
  Eigen::Quaterniond q;
  Eigen::Vector3d a;
  ASSERT_TRUE(quaternion.Plus(q0.coeffs().data(), d.data(), q.coeffs().data()));
  ASSERT_TRUE(axis.Plus(a0.data(), d.data() + 3, a.data()));
  const Eigen::Vector2d v = v0 + d.tail<2>();
  const double* parameters[] = {q.coeffs().data(), a.data(), v.data()};
  Eigen::VectorXd r(7);
  ASSERT_TRUE(prior->Evaluate(parameters, r.data(), nullptr));
  const Eigen::VectorXd expected = prior->A() * d + prior->e();
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(r[i], expected[i], 1e-12);
}

TEST(MarginalPriorFactor, RefusesBadInput) {
  std::unique_ptr<MarginalPriorFactor> prior;
  std::vector<PriorBlock> blocks = {
      {PriorBlockKind::kQuaternion, Eigen::Vector4d(0, 0, 0, 2)}};
  EXPECT_FALSE(MarginalPriorFactor::Create(blocks,
                                           Eigen::MatrixXd::Identity(3, 3),
                                           Eigen::VectorXd::Zero(3),
                                           &prior)
                   .ok());  // not unit
  blocks[0].x0 = Eigen::Vector4d(0, 0, 0, 1);
  EXPECT_FALSE(MarginalPriorFactor::Create(blocks,
                                           Eigen::MatrixXd::Identity(4, 4),
                                           Eigen::VectorXd::Zero(4),
                                           &prior)
                   .ok());  // 4 columns for a tangent of 3
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  A(1, 1) = std::nan("");
  EXPECT_FALSE(
      MarginalPriorFactor::Create(blocks, A, Eigen::VectorXd::Zero(3), &prior)
          .ok());
  EXPECT_TRUE(MarginalPriorFactor::Create(blocks,
                                          Eigen::MatrixXd::Identity(3, 3),
                                          Eigen::VectorXd::Zero(3),
                                          &prior)
                  .ok());
}

// ---------------------------------------------------------------------------
// The Schur complement on a linear Gaussian problem.

// r = (x_b - x_a - d) / sigma, x in R^3 (odometry, or a landmark seen from
// a state with x_a the state and x_b the landmark).
struct Difference {
  Difference(const Eigen::Vector3d& d, double sigma) : d(d), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = (b[i] - a[i] - T(d[i])) / T(sigma);
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& d, double sigma) {
    return new ceres::AutoDiffCostFunction<Difference, 3, 3, 3>(
        new Difference(d, sigma));
  }
  Eigen::Vector3d d;
  double sigma;
};

// r = (x - p) / sigma.
struct Anchor {
  Anchor(const Eigen::Vector3d& p, double sigma) : p(p), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* x, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = (x[i] - T(p[i])) / T(sigma);
    return true;
  }
  Eigen::Vector3d p;
  double sigma;
};

struct LinearFactor {
  std::unique_ptr<ceres::CostFunction> cost;
  int state_a = -1;  // the older state (or -1)
  int state_b = -1;  // the newer state
  int landmark = -1;
};

ceres::Solver::Options ExactOptions() {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.max_num_iterations = 20;
  options.logging_type = ceres::SILENT;
  return options;
}

TEST(Marginalize, FixedLagSmootherMatchesTheBatchOnALinearProblem) {
  constexpr int kStates = 120;
  constexpr int kLandmarks = 5;
  constexpr int kWindow = 6;
  TestRandom random(5);
  // Truth: a random walk and landmarks around it; measurements noisy.
  std::vector<Eigen::Vector3d> truth(kStates);
  truth[0] = Eigen::Vector3d::Zero();
  for (int k = 1; k < kStates; ++k) {
    truth[k] = truth[k - 1] + Eigen::Vector3d(0.3, 0.1 * std::sin(k), 0.0);
  }
  std::vector<Eigen::Vector3d> landmark_truth(kLandmarks);
  for (int j = 0; j < kLandmarks; ++j) {
    landmark_truth[j] = random.NormalVector(2.0);
  }
  std::vector<LinearFactor> factors;
  auto add = [&](ceres::CostFunction* cost, int a, int b, int landmark) {
    factors.push_back(
        {std::unique_ptr<ceres::CostFunction>(cost), a, b, landmark});
  };
  add(new ceres::AutoDiffCostFunction<Anchor, 3, 3>(
          new Anchor(truth[0] + random.NormalVector(0.01), 0.01)),
      -1,
      0,
      -1);
  for (int k = 1; k < kStates; ++k) {
    add(Difference::Create(truth[k] - truth[k - 1] + random.NormalVector(0.05),
                           0.05),
        k - 1,
        k,
        -1);
    // Every state sees two landmarks; they are revisited all along.
    for (int j : {k % kLandmarks, (k / 3) % kLandmarks}) {
      add(Difference::Create(
              landmark_truth[j] - truth[k] + random.NormalVector(0.1), 0.1),
          -1,
          k,
          j);
    }
  }
  std::vector<double*> no_blocks;
  auto blocks_of = [](const LinearFactor& f,
                      std::vector<Eigen::Vector3d>* x,
                      std::vector<Eigen::Vector3d>* l) {
    std::vector<double*> blocks;
    if (f.landmark >= 0) {
      blocks = {(*x)[f.state_b].data(), (*l)[f.landmark].data()};
    } else if (f.state_a >= 0) {
      blocks = {(*x)[f.state_a].data(), (*x)[f.state_b].data()};
    } else {
      blocks = {(*x)[f.state_b].data()};
    }
    return blocks;
  };

  // Batch: everything at once.
  std::vector<Eigen::Vector3d> x_batch(kStates, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> l_batch(kLandmarks, Eigen::Vector3d::Zero());
  {
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    for (const LinearFactor& f : factors) {
      problem.AddResidualBlock(
          f.cost.get(), nullptr, blocks_of(f, &x_batch, &l_batch));
    }
    ceres::Solver::Summary summary;
    ceres::Solve(ExactOptions(), &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable());
  }

  // Fixed-lag smoother: states enter one by one; when a state leaves the
  // window its factors are marginalised with the previous prior.
  std::vector<Eigen::Vector3d> x(kStates, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> l(kLandmarks, Eigen::Vector3d::Zero());
  std::vector<char> marginalised(factors.size(), 0);
  std::unique_ptr<MarginalPriorFactor> prior;
  std::vector<double*> prior_blocks;
  size_t next_factor = 0;
  for (int k = 0; k < kStates; ++k) {
    if (k > 0) x[k] = x[k - 1];
    const int leaving = k - kWindow;
    if (leaving >= 0) {
      std::vector<MarginalizationTerm> terms;
      for (size_t f = 0; f < next_factor; ++f) {
        if (marginalised[f]) continue;
        const LinearFactor& factor = factors[f];
        if (factor.state_a != leaving && factor.state_b != leaving) continue;
        terms.push_back(
            {factor.cost.get(), nullptr, blocks_of(factor, &x, &l)});
        marginalised[f] = 1;
      }
      if (prior) terms.push_back({prior.get(), nullptr, prior_blocks});
      const double* own = x[leaving].data();
      MarginalizationResult result;
      ASSERT_TRUE(Marginalize(
                      terms,
                      [own](const double* block) {
                        BlockDescription d;
                        d.role = block == own ? BlockRole::kEliminate
                                              : BlockRole::kKeep;
                        return d;
                      },
                      MarginalizationOptions(),
                      &result)
                      .ok());
      ASSERT_NE(result.prior, nullptr);
      const Eigen::MatrixXd info = result.prior->Information();
      EXPECT_LT((info - info.transpose()).cwiseAbs().maxCoeff(), 1e-9);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(info);
      EXPECT_GT(eig.eigenvalues().minCoeff(),
                -1e-9 * eig.eigenvalues().maxCoeff());
      prior = std::move(result.prior);
      prior_blocks = result.blocks;
    }
    while (next_factor < factors.size() && factors[next_factor].state_b <= k) {
      ++next_factor;
    }
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    for (size_t f = 0; f < next_factor; ++f) {
      if (!marginalised[f]) {
        problem.AddResidualBlock(
            factors[f].cost.get(), nullptr, blocks_of(factors[f], &x, &l));
      }
    }
    if (prior) problem.AddResidualBlock(prior.get(), nullptr, prior_blocks);
    ceres::Solver::Summary summary;
    ceres::Solve(ExactOptions(), &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
  }
  // The window's states and the landmarks are the batch solution.
  for (int k = kStates - kWindow; k < kStates; ++k) {
    EXPECT_LT((x[k] - x_batch[k]).norm(), 1e-6) << "state " << k;
  }
  for (int j = 0; j < kLandmarks; ++j) {
    EXPECT_LT((l[j] - l_batch[j]).norm(), 1e-6) << "landmark " << j;
  }
  // ... and not trivially so: the marginalised states were frozen early.
  double frozen_difference = 0.0;
  for (int k = 0; k < kStates - kWindow; ++k) {
    frozen_difference = std::max(frozen_difference, (x[k] - x_batch[k]).norm());
  }
  EXPECT_GT(frozen_difference, 1e-3);
}

// ---------------------------------------------------------------------------
// Max-mixtures: the winner, or nothing.

TEST(Marginalize, DropsAnAmbiguousMixtureAndKeepsAClearOne) {
  // An asymmetric object edge with two components 180 degrees apart about
  // z, of equal weight, from a camera at the identity: an object rotated by
  // 90 degrees is equally far from both; one at 0 degrees is clearly the
  // first.
  const Eigen::Quaterniond R0 = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond R180(
      Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()));
  std::vector<PoseComponent> components(2);
  components[0].T_co = Rigid3d(R0, Eigen::Vector3d(0, 0, 2));
  components[1].T_co = Rigid3d(R180, Eigen::Vector3d(0, 0, 2));
  for (PoseComponent& c : components) {
    c.sqrt_info = IsotropicPoseSqrtInfo(0.05, 0.1);
    c.weight = 0.5;
  }
  std::unique_ptr<AsymmetricObjectEdge> edge;
  ASSERT_TRUE(
      CreateAsymmetricObjectEdge(components, MixtureOptions(), &edge).ok());
  double q_wc[4] = {0, 0, 0, 1};
  double t_wc[3] = {0, 0, 0};
  double t_wo[3] = {0, 0, 2};
  const ceres::EigenQuaternionManifold quaternion;
  auto describe = [&](const double* block) {
    BlockDescription d;
    d.role = (block == q_wc || block == t_wc) ? BlockRole::kConstant
                                              : BlockRole::kKeep;
    d.manifold = block == t_wo ? nullptr : &quaternion;
    return d;
  };
  for (double angle : {kPi / 2, 0.1}) {
    const Eigen::Quaterniond R_wo(
        Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
    double q_wo[4] = {R_wo.x(), R_wo.y(), R_wo.z(), R_wo.w()};
    auto describe_here = [&](const double* block) {
      BlockDescription d = describe(block);
      if (block == q_wo) d.manifold = &quaternion;
      return d;
    };
    MarginalizationResult result;
    ASSERT_TRUE(Marginalize({{edge.get(), nullptr, {q_wc, t_wc, q_wo, t_wo}}},
                            describe_here,
                            MarginalizationOptions(),
                            &result)
                    .ok());
    if (angle > 1.0) {
      EXPECT_EQ(result.ambiguous, 1);
      EXPECT_EQ(result.prior, nullptr);
    } else {
      EXPECT_EQ(result.ambiguous, 0);
      EXPECT_EQ(result.linearized, 1);
      ASSERT_NE(result.prior, nullptr);
      EXPECT_EQ(result.prior->A().cols(), 6);  // q_wo (3) and t_wo (3)
    }
  }
}

TEST(Marginalize, ComponentsOfOneModeAreNoRivals) {
  // Two hypotheses of one mode, 0.05 rad apart about z (half a sigma), and
  // an object half-way: both cost the same, yet their whitened residuals
  // differ by 0.5 only, so the edge is linearised unless rival_distance is
  // below that.
  std::vector<PoseComponent> components(2);
  components[0].T_co =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 2));
  components[1].T_co = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0, 0, 2));
  for (PoseComponent& c : components) {
    c.sqrt_info = IsotropicPoseSqrtInfo(0.05, 0.1);
    c.weight = 0.5;
  }
  std::unique_ptr<AsymmetricObjectEdge> edge;
  ASSERT_TRUE(
      CreateAsymmetricObjectEdge(components, MixtureOptions(), &edge).ok());
  double q_wc[4] = {0, 0, 0, 1};
  double t_wc[3] = {0, 0, 0};
  const Eigen::Quaterniond R_wo(
      Eigen::AngleAxisd(0.025, Eigen::Vector3d::UnitZ()));
  double q_wo[4] = {R_wo.x(), R_wo.y(), R_wo.z(), R_wo.w()};
  double t_wo[3] = {0, 0, 2};
  const ceres::EigenQuaternionManifold quaternion;
  auto describe = [&](const double* block) {
    BlockDescription d;
    d.role = (block == q_wc || block == t_wc) ? BlockRole::kConstant
                                              : BlockRole::kKeep;
    d.manifold = block == t_wo ? nullptr : &quaternion;
    return d;
  };
  for (double rival_distance : {5.0, 0.4}) {
    MarginalizationOptions options;
    options.rival_distance = rival_distance;
    MarginalizationResult result;
    ASSERT_TRUE(Marginalize({{edge.get(), nullptr, {q_wc, t_wc, q_wo, t_wo}}},
                            describe,
                            options,
                            &result)
                    .ok());
    EXPECT_EQ(result.ambiguous, rival_distance > 0.5 ? 0 : 1) << rival_distance;
    EXPECT_EQ(result.linearized, rival_distance > 0.5 ? 1 : 0)
        << rival_distance;
  }
}

// Three components of equal weight about z: A at 0, B at -0.001 rad (A's
// mode: their whitened residuals differ by 0.01) and C at pi (another
// mode). At an object angle just below pi / 2 A wins, B is next and C,
// within the margin, third. B must not hide C: the margin is C's cost over
// A's, exactly as on an edge without B.
TEST(Marginalize, ACloserNonRivalDoesNotHideARival) {
  auto component = [](double angle) {
    PoseComponent c;
    c.T_co = Rigid3d(
        Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())),
        Eigen::Vector3d(0, 0, 2));
    c.sqrt_info = IsotropicPoseSqrtInfo(0.05, 0.1);
    c.weight = 1.0;
    return c;
  };
  std::unique_ptr<AsymmetricObjectEdge> abc;
  std::unique_ptr<AsymmetricObjectEdge> ac;
  ASSERT_TRUE(CreateAsymmetricObjectEdge(
                  {component(0.0), component(-0.001), component(kPi)},
                  MixtureOptions(),
                  &abc)
                  .ok());
  ASSERT_TRUE(CreateAsymmetricObjectEdge(
                  {component(0.0), component(kPi)}, MixtureOptions(), &ac)
                  .ok());
  double q_wc[4] = {0, 0, 0, 1};
  double t_wc[3] = {0, 0, 0};
  const Eigen::Quaterniond R_wo(
      Eigen::AngleAxisd(kPi / 2 - 0.003, Eigen::Vector3d::UnitZ()));
  double q_wo[4] = {R_wo.x(), R_wo.y(), R_wo.z(), R_wo.w()};
  double t_wo[3] = {0, 0, 2};
  const double* parameters[4] = {q_wc, t_wc, q_wo, t_wo};
  double without_b = 0.0;
  double with_b = 0.0;
  double b_as_rival = 0.0;
  bool null_won = true;
  ASSERT_TRUE(ac->WinnerMargin(parameters, 5.0, &without_b, &null_won));
  EXPECT_FALSE(null_won);
  ASSERT_TRUE(abc->WinnerMargin(parameters, 5.0, &with_b, &null_won));
  ASSERT_TRUE(abc->WinnerMargin(parameters, 0.001, &b_as_rival, &null_won));
  EXPECT_GT(without_b, 0.0);
  EXPECT_LT(without_b, MarginalizationOptions().min_winner_margin);
  EXPECT_NEAR(with_b, without_b, 1e-9);
  EXPECT_GT(b_as_rival, 0.0);
  EXPECT_LT(b_as_rival, without_b);  // B's cost is between A's and C's
}

}  // namespace
}  // namespace symba::internal
