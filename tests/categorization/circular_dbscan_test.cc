#include "symba/categorization/circular_dbscan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "symba/geometry/angle.h"
#include "test_support/random.h"

namespace symba {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr int kNoise = CircularDbscanResult::kNoiseLabel;

CircularDbscanOptions Options(double eps, int min_points) {
  CircularDbscanOptions options;
  options.eps = eps;
  options.min_points = min_points;
  return options;
}

// Brute-force DBSCAN on the circle (the textbook definition, O(N^2)), for
// comparison: returns for every pair of points whether they share a
// cluster, and which points are noise.
struct Reference {
  std::vector<bool> noise;
  std::vector<std::vector<bool>> together;
};

Reference BruteForce(const std::vector<double>& angles,
                     double eps,
                     int min_points) {
  const int n = static_cast<int>(angles.size());
  std::vector<bool> core(n, false);
  for (int i = 0; i < n; ++i) {
    int count = 0;
    for (int j = 0; j < n; ++j) {
      if (CircularDistance(angles[i], angles[j]) <= eps) ++count;
    }
    core[i] = count >= min_points;
  }
  // Connected components of core points.
  std::vector<int> component(n, -1);
  int num = 0;
  for (int i = 0; i < n; ++i) {
    if (!core[i] || component[i] >= 0) continue;
    std::vector<int> stack = {i};
    component[i] = num;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      for (int q = 0; q < n; ++q) {
        if (core[q] && component[q] < 0 &&
            CircularDistance(angles[p], angles[q]) <= eps) {
          component[q] = num;
          stack.push_back(q);
        }
      }
    }
    ++num;
  }
  Reference ref;
  ref.noise.assign(n, false);
  std::vector<int> label(n, -1);
  for (int i = 0; i < n; ++i) {
    if (core[i]) {
      label[i] = component[i];
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j) {
      const double d = CircularDistance(angles[i], angles[j]);
      if (core[j] && d <= eps && d < best) {
        best = d;
        label[i] = component[j];
      }
    }
    ref.noise[i] = label[i] < 0;
  }
  ref.together.assign(n, std::vector<bool>(n, false));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      ref.together[i][j] = label[i] >= 0 && label[i] == label[j];
    }
  }
  return ref;
}

TEST(CircularDbscanTest, EmptyInputHasNoClusters) {
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan({}, Options(0.2, 3), &result).ok());
  EXPECT_TRUE(result.labels.empty());
  EXPECT_TRUE(result.clusters.empty());
  EXPECT_EQ(result.num_noise, 0);
}

TEST(CircularDbscanTest, RejectsInvalidOptionsAndNonFiniteAngles) {
  CircularDbscanResult result;
  EXPECT_FALSE(CircularDbscan({0.0}, Options(0.0, 3), &result).ok());
  EXPECT_FALSE(CircularDbscan({0.0}, Options(kPi, 3), &result).ok());
  EXPECT_FALSE(CircularDbscan({0.0}, Options(0.2, 0), &result).ok());
  const Status status =
      CircularDbscan({0.0, std::numeric_limits<double>::quiet_NaN()},
                     Options(0.2, 1),
                     &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("angle 1"), std::string::npos);
  EXPECT_TRUE(result.labels.empty());
  EXPECT_FALSE(CircularDbscan({std::numeric_limits<double>::infinity()},
                              Options(0.2, 1),
                              &result)
                   .ok());
}

TEST(CircularDbscanTest, SinglePointIsClusterOrNoise) {
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan({1.0}, Options(0.2, 1), &result).ok());
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_EQ(result.labels[0], 0);
  EXPECT_DOUBLE_EQ(result.clusters[0].mean, 1.0);
  EXPECT_DOUBLE_EQ(result.clusters[0].extent, 0.0);
  EXPECT_FALSE(result.clusters[0].ring);
  ASSERT_TRUE(CircularDbscan({1.0}, Options(0.2, 2), &result).ok());
  EXPECT_TRUE(result.clusters.empty());
  EXPECT_EQ(result.labels[0], kNoise);
  EXPECT_EQ(result.num_noise, 1);
}

TEST(CircularDbscanTest, IdenticalAnglesFormOneCompactCluster) {
  CircularDbscanResult result;
  const std::vector<double> angles(30, -2.0);
  ASSERT_TRUE(CircularDbscan(angles, Options(0.2, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_EQ(result.clusters[0].size, 30);
  EXPECT_DOUBLE_EQ(result.clusters[0].extent, 0.0);
  EXPECT_DOUBLE_EQ(result.clusters[0].mean, -2.0);
  EXPECT_EQ(result.num_noise, 0);
}

TEST(CircularDbscanTest, ClusterAcrossPlusMinusPiIsOne) {
  // Angles on both sides of +-pi are neighbours on the circle.
  const std::vector<double> angles = {
      kPi - 0.05, -kPi + 0.05, kPi, -kPi + 0.1, kPi - 0.1, 0.0};
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(0.12, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_EQ(result.labels[5], kNoise);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(result.labels[i], 0) << i;
  const CircularCluster& c = result.clusters[0];
  EXPECT_EQ(c.size, 5);
  EXPECT_NEAR(c.start, kPi - 0.1, 1e-12);
  EXPECT_NEAR(c.extent, 0.2, 1e-12);
  EXPECT_NEAR(std::abs(c.mean), kPi, 1e-12);
  EXPECT_FALSE(c.ring);
}

TEST(CircularDbscanTest, AnglesOutsideMinusPiPiAreWrapped) {
  const std::vector<double> angles = {0.1, 0.1 + kTwoPi, 0.1 - 3 * kTwoPi};
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(0.01, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_NEAR(result.clusters[0].mean, 0.1, 1e-12);
}

TEST(CircularDbscanTest, FourModesWithNoiseAndAnIsolatedOutlier) {
  testing::TestRandom random(11);
  std::vector<double> angles;
  std::vector<int> mode;
  for (int i = 0; i < 28; ++i) {
    const int m = i % 4;
    angles.push_back(WrapToPi(m * kPi / 2 + random.Normal(3 * kDeg)));
    mode.push_back(m);
  }
  angles.push_back(kPi / 4);  // between two modes
  mode.push_back(-1);
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(12 * kDeg, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 4u);
  EXPECT_EQ(result.labels.back(), kNoise);
  EXPECT_EQ(result.num_noise, 1);
  for (int i = 0; i < 28; ++i) {
    for (int j = 0; j < 28; ++j) {
      EXPECT_EQ(result.labels[i] == result.labels[j], mode[i] == mode[j]);
    }
  }
  // Numbered by angle: -pi/2, 0, pi/2, then the one around +-pi.
  EXPECT_NEAR(result.clusters[0].mean, -kPi / 2, 4 * kDeg);
  EXPECT_NEAR(result.clusters[1].mean, 0.0, 4 * kDeg);
  EXPECT_NEAR(result.clusters[2].mean, kPi / 2, 4 * kDeg);
  EXPECT_NEAR(std::abs(result.clusters[3].mean), kPi, 4 * kDeg);
  for (const CircularCluster& c : result.clusters) {
    EXPECT_EQ(c.size, 7);
    EXPECT_LT(c.extent, 25 * kDeg);
  }
}

TEST(CircularDbscanTest, DenseCircleIsOneRing) {
  std::vector<double> angles;
  for (int i = 0; i < 36; ++i) angles.push_back(-kPi + i * 10 * kDeg);
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(11 * kDeg, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_TRUE(result.clusters[0].ring);
  EXPECT_EQ(result.clusters[0].size, 36);
  EXPECT_NEAR(result.clusters[0].extent, kTwoPi - 10 * kDeg, 1e-9);
  // Spacing just above eps: every point is isolated.
  ASSERT_TRUE(CircularDbscan(angles, Options(9 * kDeg, 2), &result).ok());
  EXPECT_TRUE(result.clusters.empty());
  EXPECT_EQ(result.num_noise, 36);
}

TEST(CircularDbscanTest, BorderPointJoinsNearestCore) {
  // Two dense groups; a point within eps of both, nearer the right one.
  std::vector<double> angles = {0.0, 0.01, 0.02, 0.30, 0.31, 0.32, 0.17};
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(0.14, 3), &result).ok());
  ASSERT_EQ(result.clusters.size(), 2u);
  EXPECT_EQ(result.labels[6], result.labels[3]);
  EXPECT_NE(result.labels[6], result.labels[0]);
  EXPECT_NEAR(result.clusters[result.labels[3]].start, 0.17, 1e-12);
}

TEST(CircularDbscanTest, OrderSortsByWrappedAngle) {
  const std::vector<double> angles = {3.0, -1.0, 0.5, -1.0, 7.0};
  CircularDbscanResult result;
  ASSERT_TRUE(CircularDbscan(angles, Options(0.1, 1), &result).ok());
  // 7.0 wraps to 0.717.
  EXPECT_EQ(result.order, (std::vector<int>{1, 3, 2, 4, 0}));
}

TEST(CircularDbscanTest, MatchesBruteForceOnRandomInputs) {
  testing::TestRandom random(5);
  CircularDbscanResult result;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + trial % 40;
    std::vector<double> angles;
    const int groups = 1 + trial % 5;
    for (int i = 0; i < n; ++i) {
      if (random.Uniform(0, 1) < 0.3) {
        angles.push_back(random.Uniform(-kPi, kPi));
      } else {
        const int g = static_cast<int>(random.Uniform(0, groups));
        angles.push_back(
            WrapToPi(g * kTwoPi / groups + kPi * 0.999 + random.Normal(0.1)));
      }
    }
    const double eps = random.Uniform(0.02, 0.5);
    const int min_points = 1 + trial % 4;
    ASSERT_TRUE(CircularDbscan(angles, Options(eps, min_points), &result).ok());
    const Reference ref = BruteForce(angles, eps, min_points);
    int num_noise = 0;
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(result.labels[i] == kNoise, ref.noise[i]) << trial;
      num_noise += ref.noise[i];
      for (int j = 0; j < n; ++j) {
        EXPECT_EQ(
            result.labels[i] != kNoise && result.labels[i] == result.labels[j],
            ref.together[i][j])
            << "trial " << trial << " points " << i << ", " << j;
      }
    }
    EXPECT_EQ(result.num_noise, num_noise);
    // Summaries agree with the members.
    for (int c = 0; c < static_cast<int>(result.clusters.size()); ++c) {
      const CircularCluster& cluster = result.clusters[c];
      int size = 0;
      for (int i = 0; i < n; ++i) {
        if (result.labels[i] != c) continue;
        ++size;
        double offset = WrapToPi(angles[i]) - cluster.start;
        if (offset < 0) offset += kTwoPi;
        EXPECT_LE(offset, cluster.extent + 1e-12);
      }
      EXPECT_EQ(cluster.size, size);
    }
  }
}

}  // namespace
}  // namespace symba
