// ReplayLog's modes: the window solve after every keyframe, and the batch
// solve after the last one (alone, or after the window run).
#include "symba/replay/replay.h"

#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "symba/simulation/scene.h"
#include "symba/simulation/simulator.h"

namespace symba {
namespace {

namespace fs = std::filesystem;

class ReplayTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The process id keeps two runs of the suite apart.
    dir_ = fs::temp_directory_path() /
           ("symba_replay_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    SimulationOptions options;
    options.num_keyframes = 30;
    SimulatedSequence sequence;
    ASSERT_TRUE(Simulate("disc", options, 1, &sequence).ok());
    ASSERT_TRUE(WriteSimulation(sequence, dir_.string()).ok());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Log() const { return (dir_ / "log.jsonl").string(); }

 private:
  fs::path dir_;
};

TEST_F(ReplayTest, FinalBatchSolvesEveryKeyframeAfterTheWindowRun) {
  ReplayOptions options;
  options.backend.window_size = 5;
  ReplayResult window;
  ASSERT_TRUE(ReplayLog(Log(), options, &window).ok());
  EXPECT_EQ(window.last_solve.free_keyframes, 5);

  options.final_batch = true;
  ReplayResult smoothed;
  ASSERT_TRUE(ReplayLog(Log(), options, &smoothed).ok());
  // Keyframe 0 is the gauge; every other keyframe is free in the batch.
  EXPECT_EQ(smoothed.last_solve.free_keyframes, 29);
  // The same window run decided the associations.
  ASSERT_EQ(smoothed.assignments.size(), window.assignments.size());
  for (size_t i = 0; i < window.assignments.size(); ++i) {
    EXPECT_EQ(smoothed.assignments[i].object, window.assignments[i].object);
  }
  EXPECT_EQ(smoothed.statistics.solves, window.statistics.solves + 1);
}

}  // namespace
}  // namespace symba
