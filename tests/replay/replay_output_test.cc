#include "symba/replay/replay_output.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/io/file_output.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A fresh empty directory under the system temp dir, removed afterwards.
class TempDir {
 public:
  TempDir() {
    path_ =
        fs::temp_directory_path() /
        ("symba_replay_output_test_" +
         std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  // Names in the directory (to check nothing stray was left behind).
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

TEST(ReplayOutputTest, FormatDoubleRoundTripsAndIsShort) {
  EXPECT_EQ(FormatDouble(0.1), "0.1");
  EXPECT_EQ(FormatDouble(-2.0), "-2");
  const double third = 1.0 / 3.0;
  EXPECT_EQ(std::stod(FormatDouble(third)), third);
}

TEST(ReplayOutputTest, TumTrajectoryLineIsTimestampTranslationQuaternionXyzw) {
  KeyframeEstimate kf;
  kf.id = 3;
  kf.timestamp = 1.5;
  kf.T_wc = Rigid3d(Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5),  // w, x, y, z
                    Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(FormatTumTrajectory({kf}), "1.5 1 2 3 0.5 0.5 0.5 0.5\n");
  kf.T_wc.q = Eigen::Quaterniond(1, 0, 0, 0);
  EXPECT_EQ(FormatTumTrajectory({kf}), "1.5 1 2 3 0 0 0 1\n");
}

TEST(ReplayOutputTest, ObjectsJsonHasAxisAndAnglesOnlyWhereTheyApply) {
  MapObjectEstimate chair;
  chair.id = 0;
  chair.class_name = "chair";
  chair.symmetry = SymmetryType::kAsymmetric;
  chair.t_wo = Eigen::Vector3d(1, 0, 0);
  chair.poses = {Rigid3d(Eigen::Quaterniond::Identity(), chair.t_wo)};
  chair.observations = 4;
  MapObjectEstimate table;
  table.id = 1;
  table.class_name = "table";
  table.symmetry = SymmetryType::kDiscrete;
  table.t_wo = Eigen::Vector3d(0, 1, 0);
  table.axis_w = Eigen::Vector3d(0, 0, 1);
  table.angles = {0.0, 3.0};
  table.angle_evidence = {3.0, 1.0};
  table.poses = {Rigid3d(Eigen::Quaterniond::Identity(), table.t_wo),
                 Rigid3d(Eigen::Quaterniond::Identity(), table.t_wo)};
  table.observations = 2;
  const std::string json = FormatObjectsJson({chair, table});
  EXPECT_EQ(
      json,
      "{\n"
      "  \"objects\": [\n"
      "    {\n"
      "      \"id\": 0,\n"
      "      \"class\": \"chair\",\n"
      "      \"symmetry\": \"asymmetric\",\n"
      "      \"t\": [\n        1.0,\n        0.0,\n        0.0\n      ],\n"
      "      \"poses\": [\n"
      "        {\n"
      "          \"t\": [\n            1.0,\n            0.0,\n            "
      "0.0\n"
      "          ],\n"
      "          \"q\": [\n            0.0,\n            0.0,\n            "
      "0.0,\n"
      "            1.0\n          ]\n"
      "        }\n"
      "      ],\n"
      "      \"observations\": 4\n"
      "    },\n"
      "    {\n"
      "      \"id\": 1,\n"
      "      \"class\": \"table\",\n"
      "      \"symmetry\": \"discrete\",\n"
      "      \"t\": [\n        0.0,\n        1.0,\n        0.0\n      ],\n"
      "      \"axis\": [\n        0.0,\n        0.0,\n        1.0\n      ],\n"
      "      \"angles\": [\n        0.0,\n        3.0\n      ],\n"
      "      \"angle_evidence\": [\n        3.0,\n        1.0\n      ],\n"
      "      \"angle_probabilities\": [\n        0.75,\n        0.25\n      "
      "],\n"
      "      \"poses\": [\n"
      "        {\n"
      "          \"t\": [\n            0.0,\n            1.0,\n            "
      "0.0\n"
      "          ],\n"
      "          \"q\": [\n            0.0,\n            0.0,\n            "
      "0.0,\n"
      "            1.0\n          ]\n"
      "        },\n"
      "        {\n"
      "          \"t\": [\n            0.0,\n            1.0,\n            "
      "0.0\n"
      "          ],\n"
      "          \"q\": [\n            0.0,\n            0.0,\n            "
      "0.0,\n"
      "            1.0\n          ]\n"
      "        }\n"
      "      ],\n"
      "      \"observations\": 2\n"
      "    }\n"
      "  ]\n"
      "}\n");
}

TEST(ReplayOutputTest, AssociationsCsvQuotesIdsThatNeedIt) {
  const std::string csv =
      FormatAssociationsCsv({{17, "17/0", 2, SymmetryType::kDiscrete},
                             {18, "a,\"b\"", 0, SymmetryType::kContinuous}});
  EXPECT_EQ(csv,
            "keyframe,detection,object,symmetry\n"
            "17,17/0,2,discrete\n"
            "18,\"a,\"\"b\"\"\",0,continuous\n");
}

TEST(ReplayOutputTest, SummaryJsonReportsTheWindowCounters) {
  ReplayOptions options;
  options.backend.window_policy = WindowPolicy::kMarginalize;
  ReplayResult result;
  result.statistics.keyframes = 40;
  result.statistics.marginalized_keyframes = 30;
  result.statistics.ambiguous_edges_dropped = 4;
  result.last_solve.residual_blocks = 23;
  result.last_solve.parameter_blocks = 31;
  result.last_solve.prior_size = 6;
  const std::string json =
      FormatReplaySummaryJson("log.jsonl", options, result);
  for (const char* member : {"\"marginalized_keyframes\": 30",
                             "\"ambiguous_edges_dropped\": 4",
                             "\"residual_blocks\": 23",
                             "\"parameter_blocks\": 31",
                             "\"prior_size\": 6",
                             "\"window_policy\": \"marginalize\""}) {
    EXPECT_NE(json.find(member), std::string::npos) << member << "\n" << json;
  }
}

// Each of `members` occurs in `json`, in this order.
void ExpectMembersInOrder(const std::string& json,
                          const std::vector<std::string>& members) {
  size_t at = 0;
  for (const std::string& member : members) {
    at = json.find(member, at);
    ASSERT_NE(at, std::string::npos) << member << "\n" << json;
  }
}

TEST(ReplayOutputTest, SummaryJsonReportsWhatTheBackendBelievedOfTheNoise) {
  ReplayResult result;
  ClassNoiseEstimate box;
  box.class_name = "box";
  box.sigma_t = 0.25;
  box.weight_sigma_t = 2.0;
  box.weight_sigma_r = 3.0;
  box.translation.levels = 40;
  box.translation.increments = 30;
  box.translation.sigma_level = 0.125;
  box.translation.sigma_increment = 0.0625;
  box.translation.correlation = 0.75;
  box.translation.inflation = 2.5;
  box.scatter.detections = 12;
  box.scatter.sigma_t = 0.03125;
  box.claims.translation_samples = 25;
  box.claims.rotation_samples = 0;
  box.claims.scale_t = 4.5;
  box.claims.factor_t = 4.5;
  box.track_ratio = 0.375;
  box.weights.scatter = 10;
  box.weights.unstated = 3;
  box.weights.sigma_t = 0.046875;
  result.noise = {box};
  result.motion.odometry_steps = 7;
  result.motion.odometry_sigma_t = 0.005;
  result.motion.odometry_sigma_r = 0.01;
  MotionNoiseReport::Group featureless;
  featureless.stated_sigma_t = 0.02;
  featureless.stated_sigma_r = 0.04;
  featureless.pairs = 36;
  featureless.scale = 1.5;
  featureless.factor = 1.5;
  MotionNoiseReport::Group rich;
  rich.stated_sigma_t = 0.005;
  rich.stated_sigma_r = 0.01;
  rich.pairs = 3;
  result.motion.claims = {rich, featureless};
  const std::string json =
      FormatReplaySummaryJson("log.jsonl", ReplayOptions(), result);
  // In order; no rotation estimate yet: null.
  const std::vector<std::string> members = {"\"noise\": [",
                                            "\"class\": \"box\"",
                                            "\"sigma_t\": 0.25",
                                            "\"sigma_r\": null",
                                            "\"weight_sigma_t\": 2",
                                            "\"weight_sigma_r\": 3",
                                            "\"translation\": {",
                                            "\"levels\": 40",
                                            "\"increments\": 30",
                                            "\"sigma_level\": 0.125",
                                            "\"sigma_increment\": 0.0625",
                                            "\"correlation\": 0.75",
                                            "\"inflation\": 2.5",
                                            "\"rotation\": {",
                                            "\"levels\": 0",
                                            "\"sigma_level\": null",
                                            "\"hypothesis_scatter\": {",
                                            "\"detections\": 12",
                                            "\"sigma_t\": 0.03125",
                                            "\"sigma_r\": null",
                                            "\"claims\": {",
                                            "\"translation_samples\": 25",
                                            "\"rotation_samples\": 0",
                                            "\"scale_t\": 4.5",
                                            "\"scale_r\": null",
                                            "\"factor_t\": 4.5",
                                            "\"factor_r\": 1",
                                            "\"track_ratio\": 0.375",
                                            "\"weights\": {",
                                            "\"declared\": 0",
                                            "\"scatter\": 10",
                                            "\"unstated\": 3",
                                            "\"sigma_t\": 0.046875",
                                            "\"sigma_r\": null",
                                            "\"motion\": {",
                                            "\"odometry\": {",
                                            "\"steps\": 7",
                                            "\"sigma_t\": 0.005",
                                            "\"sigma_r\": 0.01",
                                            "\"frontend_poses\": {",
                                            "\"steps\": 0",
                                            "\"sigma_t\": null",
                                            "\"claims\": [",
                                            "\"stated_sigma_t\": 0.005",
                                            "\"stated_sigma_r\": 0.01",
                                            "\"pairs\": 3",
                                            "\"scale\": null",
                                            "\"factor\": 1",
                                            "\"stated_sigma_t\": 0.02",
                                            "\"stated_sigma_r\": 0.04",
                                            "\"pairs\": 36",
                                            "\"scale\": 1.5",
                                            "\"factor\": 1.5"};
  ExpectMembersInOrder(json, members);
  // No class with detections: an empty list.
  EXPECT_NE(FormatReplaySummaryJson("log.jsonl", ReplayOptions(), {})
                .find("\"noise\": []"),
            std::string::npos);
}

TEST(ReplayOutputTest, AtomicWriteCreatesTheDirectoryWithEveryFile) {
  TempDir temp;
  const fs::path out = temp.path() / "out";
  ASSERT_TRUE(
      WriteDirectoryAtomically(out.string(), {{"a.txt", "A"}, {"b.txt", "B"}})
          .ok());
  EXPECT_EQ(ReadFile(out / "a.txt"), "A");
  EXPECT_EQ(ReadFile(out / "b.txt"), "B");
  EXPECT_EQ(temp.Entries(), std::vector<std::string>{"out"});
}

TEST(ReplayOutputTest, AtomicWriteReplacesAnExistingDirectoryWhole) {
  TempDir temp;
  const fs::path out = temp.path() / "out";
  ASSERT_TRUE(WriteDirectoryAtomically(out.string(),
                                       {{"a.txt", "old"}, {"stale.txt", "x"}})
                  .ok());
  ASSERT_TRUE(WriteDirectoryAtomically(out.string(), {{"a.txt", "new"}}).ok());
  EXPECT_EQ(ReadFile(out / "a.txt"), "new");
  EXPECT_FALSE(fs::exists(out / "stale.txt"));
  EXPECT_EQ(temp.Entries(), std::vector<std::string>{"out"});
}

TEST(ReplayOutputTest, AFailedWriteLeavesTheExistingOutputUntouched) {
  TempDir temp;
  const fs::path out = temp.path() / "out";
  ASSERT_TRUE(WriteDirectoryAtomically(out.string(), {{"a.txt", "old"}}).ok());
  // The second file cannot be written (its directory does not exist).
  const Status status = WriteDirectoryAtomically(
      out.string(), {{"a.txt", "new"}, {"no/such.txt", "x"}});
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("cannot write"), std::string::npos)
      << status.message();
  EXPECT_EQ(ReadFile(out / "a.txt"), "old");
  EXPECT_EQ(temp.Entries(), std::vector<std::string>{"out"});
}

TEST(ReplayOutputTest, AMissingParentIsAnErrorAndCreatesNothing) {
  TempDir temp;
  const fs::path out = temp.path() / "missing" / "out";
  const Status status =
      WriteDirectoryAtomically(out.string(), {{"a.txt", "A"}});
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.message(),
            out.string() + ": parent directory " +
                (temp.path() / "missing").string() + " does not exist");
  EXPECT_TRUE(temp.Entries().empty());
}

// Outputs that are not files symba may replace whole: nothing is written
// and the message names the path. (Renaming a new file over /dev/null, as
// root, would have replaced the device.)
TEST(ReplayOutputTest, OnlyRegularFilesAndNamedDirectoriesAreReplaced) {
  TempDir temp;
  const fs::path fifo = temp.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(WriteFileAtomically(fifo.string(), "x").message(),
            fifo.string() + ": exists and is not a regular file");
  EXPECT_EQ(WriteFileAtomically(temp.path().string(), "x").message(),
            temp.path().string() + ": exists and is not a regular file");
  EXPECT_EQ(WriteFileAtomically("", "x").message(), "output file: empty path");
  EXPECT_EQ(WriteDirectoryAtomically("", {}).message(),
            "output directory: empty path");
  const std::string dot = (temp.path() / ".").string();
  EXPECT_EQ(WriteDirectoryAtomically(dot, {}).message(),
            dot + ": name the output directory itself, not . or ..");
  EXPECT_EQ(temp.Entries(), std::vector<std::string>{"fifo"});
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST(ReplayOutputTest, AnOutputMustNotBeOrHoldAnInput) {
  TempDir temp;
  const fs::path dir = temp.path() / "run";
  fs::create_directory(dir);
  const std::string log = (dir / "log.jsonl").string();
  std::ofstream(log) << "{}\n";
  // The same file by another spelling; an input inside the directory.
  const std::string same = (dir / ".." / "run" / "log.jsonl").string();
  EXPECT_EQ(CheckOutputSparesInputs(same, {"", log}).message(),
            same + ": is the input " + log);
  EXPECT_EQ(CheckOutputSparesInputs(dir.string() + "/", {log}).message(),
            dir.string() + "/: holds the input " + log);
  EXPECT_TRUE(CheckOutputSparesInputs((dir / "out").string(), {log}).ok());
  EXPECT_TRUE(
      CheckOutputSparesInputs((temp.path() / "ru").string(), {log}).ok())
      << "a directory whose name is a prefix of the input's is not its parent";
}

// summary.json's "loop_closures": the waiting closure is counted as such
// and left out of the times and corrections, which are the closed ones'.
TEST(ReplaySummaryJson, LoopClosuresCountTheWaitingOnesApart) {
  ReplayResult result;
  LoopClosureReport closed;
  closed.moved_past = true;
  closed.correction_m = 0.5;
  closed.seconds = 0.25;
  LoopClosureReport waiting;
  waiting.waiting = true;
  waiting.message = "waits for the next solve";
  result.loop_closures = {closed, waiting};
  const std::string json =
      FormatReplaySummaryJson("log.jsonl", ReplayOptions(), result);
  const std::vector<std::string> members = {"\"loop_closures\": {",
                                            "\"count\": 2",
                                            "\"moved_past\": 1",
                                            "\"waiting\": 1",
                                            "\"from_objects\": 0",
                                            "\"objects_merged\": 0",
                                            "\"max_correction_m\": 0.5",
                                            "\"median_seconds\": 0.25",
                                            "\"max_seconds\": 0.25"};
  ExpectMembersInOrder(json, members);
}

// The counts: a revisit that moved the past without a loop closure is
// counted after the merged duplicates.
TEST(ReplaySummaryJson, ARevisitThatMovedThePastIsCounted) {
  ReplayResult result;
  result.statistics.objects_merged = 3;
  result.statistics.revisits_moved_past = 2;
  const std::string json =
      FormatReplaySummaryJson("log.jsonl", ReplayOptions(), result);
  ExpectMembersInOrder(json,
                       {"\"counts\": {",
                        "\"objects_merged\": 3",
                        "\"revisits_moved_past\": 2",
                        "\"rotation_outliers\": 0"});
}

// A loop found from the objects: counted in summary.json, its recognised
// pairs ("MAP:DUPLICATE") and how many were merged in loop_closures.csv.
TEST(ReplayLoopClosures, ALoopFromObjectsListsItsPairs) {
  LoopClosureReport host;
  host.keyframe = 9;
  host.other = 2;
  LoopClosureReport found;
  found.keyframe = 40;
  found.other = 7;
  found.moved_past = true;
  found.from_objects = true;
  found.objects = {{3, 17, true}, {5, 18, true}, {6, 19, false}};
  EXPECT_EQ(FormatLoopClosuresCsv({host, found}),
            "keyframe,other,moved_past,correction_m,correction_deg,"
            "keyframes_moved,initial_cost,final_cost,seconds,message,"
            "from_objects,objects,merged\n"
            "9,2,false,0,0,0,0,0,0,,false,,0\n"
            "40,7,true,0,0,0,0,0,0,,true,3:17 5:18 6:19,2\n");
  ReplayResult result;
  result.loop_closures = {host, found};
  const std::string json =
      FormatReplaySummaryJson("log.jsonl", ReplayOptions(), result);
  ExpectMembersInOrder(json,
                       {"\"loop_closures\": {",
                        "\"count\": 2",
                        "\"from_objects\": 1",
                        "\"objects_merged\": 2"});
}

}  // namespace
}  // namespace symba
