// The ground-truth object list of symba eval --gt-trajectory: what it reads
// and the exact message for each bad line.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/evaluation/evaluate_trajectory.h"

namespace symba {
namespace {

namespace fs = std::filesystem;

class GroundTruthObjectListTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One file per test: ctest runs this fixture's tests as concurrent
    // processes, which must not write the same file.
    const std::string test =
        ::testing::UnitTest::GetInstance()->current_test_info()->name();
    path_ = (fs::path(::testing::TempDir()) / ("gt_objects_" + test + ".txt"))
                .string();
  }
  void TearDown() override { fs::remove(path_); }

  Status Read(const std::string& text) {
    std::ofstream(path_, std::ios::binary) << text;
    return ReadGroundTruthObjectList(path_, &objects_);
  }

  std::string path_;
  std::vector<GroundTruthObjectPose> objects_;
};

TEST_F(GroundTruthObjectListTest, ReadsClassesAndPoses) {
  const Status status = Read(
      "# CLASS tx ty tz qx qy qz qw\n"
      "\n"
      "mug 1 2 3 0 0 0 1\n"
      "  box\t-1 0 0.5 0 0 0 2.0001e0\n");
  // 2.0001 is not a unit quaternion: the first error is on line 4.
  EXPECT_EQ(status.message(), path_ + ":4: quaternion norm 2.0001 is not 1");
  ASSERT_TRUE(Read("mug 1 2 3 0 0 0 1\nbox -1 0 0.5 0 0 1 0\n").ok());
  ASSERT_EQ(objects_.size(), 2u);
  EXPECT_EQ(objects_[0].class_name, "mug");
  EXPECT_EQ(objects_[0].T_wo.t, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(objects_[1].line, 2);
  EXPECT_EQ(objects_[1].T_wo.q.z(), 1.0);
}

TEST_F(GroundTruthObjectListTest, BadLinesAreNamed) {
  EXPECT_EQ(Read("mug 1 2 3\n").message(),
            path_ +
                ":1: expected a class and 7 numbers (CLASS tx ty tz qx qy qz "
                "qw), found 4 fields");
  EXPECT_EQ(Read("mug 1 2 x 0 0 0 1\n").message(),
            path_ + ":1: \"x\" is not a finite number");
  EXPECT_EQ(Read("# nothing\n").message(), path_ + ": no objects");
  EXPECT_EQ(ReadGroundTruthObjectList(path_ + ".none", &objects_).message(),
            path_ + ".none: cannot open");
}

}  // namespace
}  // namespace symba
