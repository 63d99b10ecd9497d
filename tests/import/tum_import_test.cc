// symba import tum as a library: exact log text for a small input, and for
// each bad input the exact message and no output file.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "symba/import/class_prior_spec.h"
#include "symba/import/tum_import.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

namespace fs = std::filesystem;

class TumImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("tum_import_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // Four frames; the front end starts at (1, 0, 0) and turns by 180
    // degrees about z at frame 2, so every odometry number is exact.
    traj_ = Write("traj.txt",
                  "# front end\n"
                  "0.0 1 0 0 0 0 0 1\n"
                  "0.1 1 1 0 0 0 0 1\n"
                  "0.2 1 2 0 0 0 1 0\n"
                  "0.3 1 3 0 0 0 1 0\n");
    gt_ = Write("gt.txt",
                "0.0 5 6 7 0 0 0 1\n"
                "0.1 9 9 9 1 0 0 0\n");
    // Frame 0: not detected; frame 1: not a keyframe (stride 2); frame 2:
    // detected (timestamp within 1e-6 s); frame 3: not a keyframe.
    box_ = Write("box.txt",
                 "0.0 0 0 0 0 0 0 0\n"
                 "0.1 0.5 0 2 0 0 0 1\n"
                 "0.2000004 0.25 -0.5 1.5 0 1 0 0\n"
                 "0.3 0.5 0 2 0 0 0 1\n");
    can_ = Write("can.txt", "0.0 0 0 1 0 0 0 1\n");
    out_ = (dir_ / "out.jsonl").string();
    options_.trajectory = traj_;
    options_.objects = {{"box", box_}, {"can", can_}};
    options_.stride = 2;
  }

  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  std::string Read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // The import fails with exactly `message` and writes nothing.
  void ExpectFailure(const std::string& message) {
    const Status status = ImportTumToLog(options_, out_, nullptr);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.message(), message);
    int entries = 0;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      (void)entry;
      ++entries;
    }
    EXPECT_FALSE(fs::exists(out_));
    EXPECT_EQ(entries, count_inputs_) << "a stray file was left behind";
  }

  fs::path dir_;
  std::string traj_, gt_, box_, can_, out_;
  int count_inputs_ = 4;
  TumImportOptions options_;
};

TEST_F(TumImportTest, WritesTheExpectedLog) {
  TumImportCounts counts;
  const Status status = ImportTumToLog(options_, out_, &counts);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(counts.keyframes, 2);
  EXPECT_EQ(counts.detections, 2);
  EXPECT_EQ(Read(out_),
            "{\"format\":\"symba-log\",\"version\":1}\n"
            "{\"keyframe\":0,\"t\":0.0,\"T_wc\":{\"t\":[1.0,0.0,0.0],"
            "\"q\":[0.0,0.0,0.0,1.0]},\"detections\":[{\"class\":\"can\","
            "\"hypotheses\":[{\"t\":[0.0,0.0,1.0],\"q\":[0.0,0.0,0.0,1.0]}]}"
            "]}\n"
            "{\"keyframe\":2,\"t\":0.2,\"odometry\":{\"T\":{\"t\":[0.0,2.0,"
            "0.0],\"q\":[0.0,0.0,1.0,0.0]},\"sigma_t\":0.005,\"sigma_r\":0.01},"
            "\"detections\":[{\"class\":\"box\",\"hypotheses\":[{\"t\":[0.25,"
            "-0.5,1.5],\"q\":[0.0,1.0,0.0,0.0]}]}]}\n");
}

TEST_F(TumImportTest, FirstPoseSigmasAndPriorsAreWritten) {
  options_.first_pose = gt_;
  options_.stride = 3;
  options_.odometry_sigma_t = 0.25;
  options_.odometry_sigma_r = 0.5;
  options_.detection_sigma_t = 0.125;
  options_.detection_sigma_r = 0.0625;
  ClassPrior prior;
  prior.symmetry = SymmetryType::kDiscrete;
  prior.order = 2;
  prior.axis_o = Eigen::Vector3d(0, 0, 1);
  options_.classes["box"] = prior;
  const Status status = ImportTumToLog(options_, out_, nullptr);
  ASSERT_TRUE(status.ok()) << status.message();
  // Keyframes 0 and 3; T_wc(0) is gt's first pose; T_0,3 from the front end:
  // (180 deg about z, (0, 3, 0)).
  EXPECT_EQ(Read(out_),
            "{\"format\":\"symba-log\",\"version\":1,\"classes\":{\"box\":{"
            "\"symmetry\":\"discrete\",\"order\":2,\"axis\":[0.0,0.0,1.0]}}}"
            "\n"
            "{\"keyframe\":0,\"t\":0.0,\"T_wc\":{\"t\":[5.0,6.0,7.0],"
            "\"q\":[0.0,0.0,0.0,1.0]},\"detections\":[{\"class\":\"can\","
            "\"sigma_t\":0.125,\"sigma_r\":0.0625,\"hypotheses\":[{\"t\":[0.0,"
            "0.0,1.0],\"q\":[0.0,0.0,0.0,1.0]}]}]}\n"
            "{\"keyframe\":3,\"t\":0.3,\"odometry\":{\"T\":{\"t\":[0.0,3.0,"
            "0.0],\"q\":[0.0,0.0,1.0,0.0]},\"sigma_t\":0.25,\"sigma_r\":0.5},"
            "\"detections\":[{\"class\":\"box\",\"sigma_t\":0.125,"
            "\"sigma_r\":0.0625,\"hypotheses\":[{\"t\":[0.5,0.0,2.0],\"q\":["
            "0.0,0.0,0.0,1.0]}]}]}\n");
}

TEST_F(TumImportTest, ReplacesAnExistingLogOnlyOnSuccess) {
  Write("out.jsonl", "old");
  count_inputs_ = 5;
  options_.stride = 0;
  const Status status = ImportTumToLog(options_, out_, nullptr);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(Read(out_), "old");
  options_.stride = 2;
  ASSERT_TRUE(ImportTumToLog(options_, out_, nullptr).ok());
  EXPECT_EQ(Read(out_).substr(0, 35),
            "{\"format\":\"symba-log\",\"version\":1}\n");
}

TEST_F(TumImportTest, MissingTrajectory) {
  options_.trajectory = (dir_ / "nope.txt").string();
  ExpectFailure(options_.trajectory + ": cannot open");
}

TEST_F(TumImportTest, MalformedTrajectoryLine) {
  Write("traj.txt", "0.0 1 0 0 0 0 0 1\n0.1 1 1 0 0 0 0\n");
  ExpectFailure(traj_ +
                ":2: expected 8 numbers (timestamp tx ty tz qx qy qz qw), "
                "found 7");
}

TEST_F(TumImportTest, AllZeroRowInTrajectoryIsAnError) {
  Write("traj.txt", "0.0 1 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 0\n");
  ExpectFailure(traj_ + ":2: quaternion norm 0 is not 1");
}

TEST_F(TumImportTest, EmptyTrajectory) {
  Write("traj.txt", "# nothing\n");
  ExpectFailure(traj_ + ": no poses");
}

TEST_F(TumImportTest, MalformedObjectLine) {
  Write("box.txt", "0.0 0 0 0 0 0 0 0\n0.1 0.5 0 2 0 0 0 x\n");
  ExpectFailure(box_ + ":2: \"x\" is not a finite number");
}

TEST_F(TumImportTest, ObjectTimeGoingBack) {
  Write("can.txt", "0.2 0 0 1 0 0 0 1\n0.1 0 0 1 0 0 0 1\n");
  ExpectFailure(can_ + ":2: timestamp 0.1 is not after the previous one");
}

TEST_F(TumImportTest, ObjectRowAtNoFrame) {
  Write("box.txt", "0.0 0 0 0 0 0 0 0\n0.15 0.5 0 2 0 0 0 1\n");
  ExpectFailure(box_ + ":2: timestamp 0.15 is not the time of any frame of " +
                traj_ + " (within 1e-06 s)");
}

TEST_F(TumImportTest, ObjectRowJustOutsideTheTolerance) {
  Write("box.txt", "0.2000011 0.5 0 2 0 0 0 1\n");
  ExpectFailure(box_ +
                ":1: timestamp 0.2000011 is not the time of any frame of " +
                traj_ + " (within 1e-06 s)");
}

TEST_F(TumImportTest, MissingObjectFile) {
  options_.objects[1].path = (dir_ / "none.txt").string();
  ExpectFailure(options_.objects[1].path + ": cannot open");
}

TEST_F(TumImportTest, FirstPoseWithoutTheFirstFrame) {
  Write("gt.txt", "0.1 9 9 9 1 0 0 0\n");
  options_.first_pose = gt_;
  ExpectFailure(gt_ + ": no pose at the first frame's timestamp 0 (" + traj_ +
                ":2)");
}

TEST_F(TumImportTest, InvalidOptions) {
  options_.stride = 0;
  ExpectFailure("stride: must be at least 1, got 0");
  options_.stride = 1;
  options_.odometry_sigma_t = 0.0;
  ExpectFailure("odometry sigma_t: must be in [1e-9, 1e9], got 0");
  options_.odometry_sigma_t = 0.1;
  options_.odometry_sigma_r = -1.0;
  ExpectFailure("odometry sigma_r: must be in [1e-9, 1e9], got -1");
  options_.odometry_sigma_r = 0.1;
  options_.detection_sigma_r = 0.0;
  ExpectFailure("detection sigma_r: must be in [1e-9, 1e9], got 0");
  options_.detection_sigma_r.reset();
  options_.objects[0].class_name = "";
  ExpectFailure(box_ + ": the object's class name is empty");
}

TEST_F(TumImportTest, OutputDirectoryMissing) {
  out_ = (dir_ / "no_dir" / "out.jsonl").string();
  ExpectFailure(out_ + ": cannot open for writing (No such file or directory)");
}

// The log WritesTheExpectedLog expects, written from other forms of the
// same inputs.
std::string ExpectedSmallLog() {
  return "{\"format\":\"symba-log\",\"version\":1}\n"
         "{\"keyframe\":0,\"t\":0.0,\"T_wc\":{\"t\":[1.0,0.0,0.0],"
         "\"q\":[0.0,0.0,0.0,1.0]},\"detections\":[{\"class\":\"can\","
         "\"hypotheses\":[{\"t\":[0.0,0.0,1.0],\"q\":[0.0,0.0,0.0,1.0]}]}"
         "]}\n"
         "{\"keyframe\":2,\"t\":0.2,\"odometry\":{\"T\":{\"t\":[0.0,2.0,"
         "0.0],\"q\":[0.0,0.0,1.0,0.0]},\"sigma_t\":0.005,\"sigma_r\":0.01},"
         "\"detections\":[{\"class\":\"box\",\"hypotheses\":[{\"t\":[0.25,"
         "-0.5,1.5],\"q\":[0.0,1.0,0.0,0.0]}]}]}\n";
}

TEST_F(TumImportTest, CommaSeparatedFilesGiveTheSameLog) {
  Write("traj.txt",
        "0.0,1,0,0,0,0,0,1\n"
        "0.1, 1, 1, 0, 0, 0, 0, 1\n"
        "0.2 ,1 ,2 ,0 ,0 ,0 ,1 ,0\n"
        "0.3,\t1,3,0,0,0,1,0\n");
  Write("can.txt", "0.0,0,0,1,0,0,0,1\n");
  TumImportCounts counts;
  const Status status = ImportTumToLog(options_, out_, &counts);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(Read(out_), ExpectedSmallLog());
  EXPECT_TRUE(counts.notes.empty());
  EXPECT_TRUE(counts.warnings.empty());
}

TEST_F(TumImportTest, EmptyCommaFieldIsNamed) {
  Write("can.txt", "0.0,0,,1,0,0,0,1\n");
  ExpectFailure(can_ + ":1: \"\" is not a finite number");
}

TEST_F(TumImportTest, NanosecondsAndMicrosecondsAreConvertedWithANote) {
  // The same four frames 1.7e9 s after the epoch, in ns; the box in us.
  Write("traj.txt",
        "1700000000000000000 1 0 0 0 0 0 1\n"
        "1700000000100000000 1 1 0 0 0 0 1\n"
        "1700000000200000000 1 2 0 0 0 1 0\n"
        "1700000000300000000 1 3 0 0 0 1 0\n");
  Write("box.txt", "1700000000200000 0.25 -0.5 1.5 0 1 0 0\n");
  Write("can.txt", "1700000000.0 0 0 1 0 0 0 1\n");
  TumImportCounts counts;
  const Status status = ImportTumToLog(options_, out_, &counts);
  ASSERT_TRUE(status.ok()) << status.message();
  const std::string log = Read(out_);
  EXPECT_NE(log.find("{\"keyframe\":0,\"t\":1.7e+09,"), std::string::npos)
      << log;
  EXPECT_NE(log.find("{\"keyframe\":2,\"t\":1700000000.2,"), std::string::npos)
      << log;
  EXPECT_EQ(counts.detections, 2);
  ASSERT_EQ(counts.notes.size(), 2u);
  EXPECT_EQ(counts.notes[0],
            traj_ +
                ": timestamps read as nanoseconds (the first is "
                "1700000000000000000), converted to seconds");
  EXPECT_EQ(counts.notes[1],
            box_ +
                ": timestamps read as microseconds (the first is "
                "1700000000200000), converted to seconds");
}

TEST_F(TumImportTest, SecondsJustBelowTheMicrosecondRuleStaySeconds) {
  EXPECT_EQ(kMicrosecondsAbove, 1e14);
  EXPECT_EQ(kNanosecondsAbove, 1e17);
  Write("traj.txt", "100000000000000 1 0 0 0 0 0 1\n");
  Write("can.txt", "100000000000000 0 0 1 0 0 0 1\n");
  options_.objects = {{"can", can_}};
  TumImportCounts counts;
  ASSERT_TRUE(ImportTumToLog(options_, out_, &counts).ok());
  EXPECT_TRUE(counts.notes.empty());
  EXPECT_NE(Read(out_).find("\"t\":1e+14,"), std::string::npos) << Read(out_);
}

TEST_F(TumImportTest, HeaderWithoutHashIsNamed) {
  Write("traj.txt", "timestamp tx ty tz qx qy qz qw\n0.0 1 0 0 0 0 0 1\n");
  ExpectFailure(traj_ +
                ":1: \"timestamp tx ty tz qx qy qz qw\" looks like a header: "
                "TUM files have none; start the line with '#' to make it a "
                "comment, or delete it");
  Write("box.txt", "# comment\n\n  t,x,y,z,qx,qy,qz,qw\n");
  Write("traj.txt", "0.0 1 0 0 0 0 0 1\n");
  ExpectFailure(box_ +
                ":3: \"t,x,y,z,qx,qy,qz,qw\" looks like a header: TUM files "
                "have none; start the line with '#' to make it a comment, or "
                "delete it");
}

TEST_F(TumImportTest, NanOnTheFirstLineIsANumberNotAHeader) {
  Write("can.txt", "nan 0 0 1 0 0 0 1\n");
  ExpectFailure(can_ + ":1: \"nan\" is not a finite number");
}

TEST_F(TumImportTest, AWordAfterTheFirstLineIsNotAHeader) {
  Write("can.txt", "0.0 0 0 1 0 0 0 1\nnan 0 0 1 0 0 0 1\n");
  ExpectFailure(can_ + ":2: \"nan\" is not a finite number");
}

TEST_F(TumImportTest, ObjectFileWithoutDetectionIsAWarning) {
  Write("can.txt", "");
  Write("box.txt", "0.0 0 0 0 0 0 0 0\n0.1 0 0 0 0 0 0 0\n");
  TumImportCounts counts;
  const Status status = ImportTumToLog(options_, out_, &counts);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(counts.detections, 0);
  ASSERT_EQ(counts.warnings.size(), 2u);
  EXPECT_EQ(
      counts.warnings[0],
      box_ + ": no detection (2 all-zero rows): the object is never seen");
  EXPECT_EQ(counts.warnings[1],
            can_ + ": no detection (no data line): the object is never seen");
}

TEST_F(TumImportTest, TimeToleranceMatchesTheNearestFrame) {
  // 3 ms late: outside the default 1e-6 s, the nearest frame within 5 ms.
  Write("box.txt", "0.203 0.25 -0.5 1.5 0 1 0 0\n");
  Write("can.txt", "-0.004 0 0 1 0 0 0 1\n");
  ExpectFailure(box_ + ":1: timestamp 0.203 is not the time of any frame of " +
                traj_ + " (within 1e-06 s)");
  options_.time_tolerance = 0.005;
  const Status status = ImportTumToLog(options_, out_, nullptr);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(Read(out_), ExpectedSmallLog());
}

TEST_F(TumImportTest, TimeToleranceFirstPose) {
  Write("gt.txt", "0.004 5 6 7 0 0 0 1\n");
  options_.first_pose = gt_;
  ExpectFailure(gt_ + ": no pose at the first frame's timestamp 0 (" + traj_ +
                ":2)");
  options_.time_tolerance = 0.005;
  ASSERT_TRUE(ImportTumToLog(options_, out_, nullptr).ok());
  EXPECT_NE(Read(out_).find("\"T_wc\":{\"t\":[5.0,6.0,7.0]"),
            std::string::npos);
}

TEST_F(TumImportTest, TwoRowsAtOneFrameAreAnError) {
  Write("box.txt",
        "0.19 0.25 -0.5 1.5 0 1 0 0\n"
        "0.21 0.25 -0.5 1.5 0 1 0 0\n");
  options_.time_tolerance = 0.02;
  ExpectFailure(box_ + ":2: timestamp 0.21 is at the same frame (" + traj_ +
                ":4) as line 1 (within 0.02 s)");
}

TEST_F(TumImportTest, NegativeTimeToleranceIsRefused) {
  options_.time_tolerance = -1.0;
  ExpectFailure("time tolerance: must be finite and not negative, got -1");
}

TEST(ClassPriorSpec, Parses) {
  std::string name;
  ClassPrior prior;
  ASSERT_TRUE(ParseClassPriorSpec("mug=asymmetric", &name, &prior).ok());
  EXPECT_EQ(name, "mug");
  EXPECT_EQ(prior.symmetry, SymmetryType::kAsymmetric);
  ASSERT_TRUE(ParseClassPriorSpec("box=discrete:2:0,0,1", &name, &prior).ok());
  EXPECT_EQ(name, "box");
  EXPECT_EQ(prior.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(prior.order, 2);
  EXPECT_EQ(prior.axis_o, Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(ParseClassPriorSpec("sq=discrete:4", &name, &prior).ok());
  EXPECT_EQ(prior.order, 4);
  EXPECT_EQ(prior.axis_o, Eigen::Vector3d::Zero());
  ASSERT_TRUE(
      ParseClassPriorSpec("can=continuous:0,2.5,0", &name, &prior).ok());
  EXPECT_EQ(prior.symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(prior.order, 0);
  EXPECT_EQ(prior.axis_o, Eigen::Vector3d(0, 2.5, 0));
}

TEST(ClassPriorSpec, RejectsWithExactMessages) {
  const auto message = [](const std::string& spec) {
    std::string name;
    ClassPrior prior;
    return ParseClassPriorSpec(spec, &name, &prior).message();
  };
  EXPECT_EQ(message("box"),
            "class prior \"box\": expected NAME=asymmetric, "
            "NAME=discrete:ORDER[:ax,ay,az] or NAME=continuous[:ax,ay,az]");
  EXPECT_EQ(message("=asymmetric"),
            "class prior \"=asymmetric\": expected NAME=asymmetric, "
            "NAME=discrete:ORDER[:ax,ay,az] or NAME=continuous[:ax,ay,az]");
  EXPECT_EQ(message("box=round"),
            "class prior \"box=round\": unknown symmetry \"round\" (expected "
            "asymmetric, discrete or continuous)");
  EXPECT_EQ(message("box=discrete"),
            "class prior \"box=discrete\": a discrete class needs its order: "
            "NAME=discrete:ORDER");
  EXPECT_EQ(message("box=discrete:1"),
            "class prior \"box=discrete:1\": the order must be an integer "
            "from 2 to 1000000, got \"1\"");
  EXPECT_EQ(message("box=discrete:2.5"),
            "class prior \"box=discrete:2.5\": the order must be an integer "
            "from 2 to 1000000, got \"2.5\"");
  EXPECT_EQ(message("mug=asymmetric:0,0,1"),
            "class prior \"mug=asymmetric:0,0,1\": an asymmetric class has "
            "no order or axis");
  EXPECT_EQ(message("can=continuous:0,0,1:3"),
            "class prior \"can=continuous:0,0,1:3\": too many ':' fields");
  EXPECT_EQ(message("can=continuous:0,1"),
            "class prior \"can=continuous:0,1\": the axis must be three "
            "numbers ax,ay,az, got \"0,1\"");
  EXPECT_EQ(message("can=continuous:0,0,0"),
            "class prior \"can=continuous:0,0,0\": the axis must not be the "
            "zero vector");
}

}  // namespace
}  // namespace symba
