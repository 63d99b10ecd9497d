#include "symba/categorization/class_prior.h"

#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "symba/categorization/categorize.h"

namespace symba {
namespace {

using ::testing::HasSubstr;

constexpr double kPriorNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPriorInf = std::numeric_limits<double>::infinity();

ClassPrior Prior(SymmetryType symmetry, int order, Eigen::Vector3d axis_o) {
  ClassPrior prior;
  prior.symmetry = symmetry;
  prior.order = order;
  prior.axis_o = axis_o;
  return prior;
}

TEST(ClassPrior, DefaultAndEveryKnownShapeIsValid) {
  EXPECT_TRUE(ClassPrior().Validate().ok());
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  EXPECT_TRUE(Prior(SymmetryType::kDiscrete, 2, z).Validate().ok());
  EXPECT_TRUE(Prior(SymmetryType::kDiscrete, 0, zero).Validate().ok());
  EXPECT_TRUE(Prior(SymmetryType::kDiscrete, 6, 3.0 * z).Validate().ok());
  EXPECT_TRUE(Prior(SymmetryType::kContinuous, 0, -z).Validate().ok());
}

TEST(ClassPrior, OrderOneIsAnError) {
  const Status status =
      Prior(SymmetryType::kDiscrete, 1, Eigen::Vector3d::UnitZ()).Validate();
  EXPECT_EQ(status.message(),
            "class prior order 1 is neither 0 (unknown) nor >= 2");
}

TEST(ClassPrior, NegativeOrderIsAnError) {
  const Status status =
      Prior(SymmetryType::kDiscrete, -3, Eigen::Vector3d::Zero()).Validate();
  EXPECT_EQ(status.message(),
            "class prior order -3 is neither 0 (unknown) nor >= 2");
}

TEST(ClassPrior, NonFiniteAxisIsAnError) {
  for (const double bad : {kPriorNaN, kPriorInf, -kPriorInf}) {
    const Status status =
        Prior(SymmetryType::kContinuous, 0, Eigen::Vector3d(0.0, bad, 1.0))
            .Validate();
    EXPECT_FALSE(status.ok());
    EXPECT_THAT(status.message(), HasSubstr("class prior axis (0, "));
    EXPECT_THAT(status.message(), HasSubstr(", 1) is not finite"));
  }
}

// Finite but unusable: its norm overflows or underflows when squared (a
// header axis of [1e300, 1e300, 0] used to abort the replay).
TEST(ClassPrior, AnAxisWhoseNormCannotBeTakenIsAnError) {
  for (const Eigen::Vector3d& bad : {Eigen::Vector3d(1e300, 1e300, 0.0),
                                     Eigen::Vector3d(0.0, 0.0, 1e101),
                                     Eigen::Vector3d(1e-300, 0.0, 0.0),
                                     Eigen::Vector3d(0.0, 9e-101, 0.0)}) {
    const Status status = Prior(SymmetryType::kContinuous, 0, bad).Validate();
    EXPECT_FALSE(status.ok()) << bad.transpose();
    EXPECT_THAT(status.message(),
                HasSubstr("must be zero or have a norm in [1e-100, 1e100]"));
  }
  for (const Eigen::Vector3d& good :
       {Eigen::Vector3d(0.0, 0.0, 1e100), Eigen::Vector3d(1e-100, 0.0, 0.0)}) {
    EXPECT_TRUE(Prior(SymmetryType::kContinuous, 0, good).Validate().ok())
        << good.transpose();
  }
}

TEST(ClassPrior, UnknownSymmetryIsAnError) {
  const Status status =
      Prior(static_cast<SymmetryType>(7), 0, Eigen::Vector3d::Zero())
          .Validate();
  EXPECT_EQ(status.message(),
            "class prior symmetry 7 is not asymmetric, discrete or continuous");
}

// Categorize() reports the prior's own message.
TEST(ClassPrior, CategorizeReportsTheValidateMessage) {
  const ClassPrior prior =
      Prior(SymmetryType::kDiscrete, 1, Eigen::Vector3d::UnitZ());
  CategorizedDetection out;
  const Status status =
      Categorize({PoseHypothesis{}}, CategorizationOptions(), &prior, &out);
  EXPECT_EQ(status.message(), "categorize: " + prior.Validate().message());
}

}  // namespace
}  // namespace symba
