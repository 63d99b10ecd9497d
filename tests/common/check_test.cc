#include "symba/common/check.h"

#include <gtest/gtest.h>

namespace symba {
namespace {

TEST(SymbaCheckDeathTest, FailedCheckPrintsFileLineConditionAndMessage) {
  const int value = 3;
  EXPECT_DEATH(SYMBA_CHECK(value == 4) << "value is " << value,
               "check_test\\.cc:[0-9]+: Check failed: value == 4 value is 3");
}

TEST(SymbaCheckDeathTest, FailedCheckWithoutMessageStillAborts) {
  EXPECT_DEATH(SYMBA_CHECK(1 > 2), "Check failed: 1 > 2");
}

TEST(SymbaCheck, PassingCheckEvaluatesNoMessage) {
  int evaluated = 0;
  const auto count = [&evaluated]() { return ++evaluated; };
  SYMBA_CHECK(2 > 1) << count();
  EXPECT_EQ(evaluated, 0);
}

TEST(SymbaCheck, ConditionIsEvaluatedOnce) {
  int evaluated = 0;
  SYMBA_CHECK(++evaluated == 1);
  EXPECT_EQ(evaluated, 1);
}

TEST(SymbaCheck, WorksAsTheOnlyStatementOfAnIfElse) {
  bool reached_else = false;
  if (false)
    SYMBA_CHECK(false) << "never";
  else
    reached_else = true;
  EXPECT_TRUE(reached_else);
}

}  // namespace
}  // namespace symba
