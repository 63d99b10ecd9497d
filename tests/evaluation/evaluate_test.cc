// Evaluate on hand-made ground-truth and result directories whose answers
// are known, and the exact messages for malformed inputs.
#include "symba/evaluation/evaluate.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "symba/geometry/angle.h"

namespace symba {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kDeg = kPi / 180.0;

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

// "qx qy qz qw" of a rotation by `angle` about `axis`.
std::string Quat(double angle, const Eigen::Vector3d& axis) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis.normalized()));
  std::ostringstream out;
  out.precision(17);
  out << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
  return out.str();
}

std::string QuatJson(double angle, const Eigen::Vector3d& axis) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis.normalized()));
  std::ostringstream out;
  out.precision(17);
  out << "[" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]";
  return out.str();
}

std::string VecJson(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(17);
  out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return out.str();
}

// Ground truth: four keyframes, a rectangular table (discrete, order 2,
// vertical axis) at (1, 2, 0.4) turned 30 degrees about z, and a round table
// (continuous) at (-1, 0, 0.4). Detections k/0 are the table's (k = 0..3),
// 1/1 and 2/1 the round table's.
constexpr char kGtTrajectory[] =
    "# timestamp tx ty tz qx qy qz qw\n"
    "0 0 0 1 0 0 0 1\n"
    "0.5 1 0 1 0 0 0 1\n"
    "1 2 0 1 0 0 0 1\n"
    "1.5 3 0 1 0 0 0 1\n";

std::string GtObjects() {
  return R"({"objects": [
  {"id": 0, "class": "table", "symmetry": "discrete", "order": 2,
   "axis_o": [0, 0, 1], "axis": [0, 0, 1],
   "pose": {"t": [1, 2, 0.4], "q": )" +
         QuatJson(30 * kDeg, Eigen::Vector3d::UnitZ()) + R"(}},
  {"id": 1, "class": "round_table", "symmetry": "continuous", "order": 0,
   "axis_o": [0, 0, 1], "axis": [0, 0, 1],
   "pose": {"t": [-1, 0, 0.4], "q": [0, 0, 0, 1]}}],
 "detections": {"0/0": 0, "1/0": 0, "2/0": 0, "3/0": 0, "1/1": 1, "2/1": 1}}
)";
}

// The result: keyframes 1 and 3 are 0.1 m off in x and keyframe 2 is
// turned 2 degrees; the table went to map objects 5 (three detections) and
// 7 (one); the round table to map object 9 (asymmetric).
std::string ResultTrajectory() {
  return "0 0 0 1 0 0 0 1\n"
         "0.5 1.1 0 1 0 0 0 1\n"
         "1 2 0 1 " +
         Quat(2 * kDeg, Eigen::Vector3d::UnitX()) +
         "\n"
         "1.5 3.1 0 1 0 0 0 1\n";
}

// Map object 5: 0.05 m off (3-4-5), axis tilted 10 degrees about x and
// stored pointing down (the error is sign-free), two poses: the true
// rotation turned by 180 + 4 degrees about z, and one 90 degrees off.
// Map object 9: asymmetric, its pose tilted 5 degrees about y.
std::string ResultObjects() {
  const Eigen::Vector3d tilted =
      -(Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()) *
        Eigen::Vector3d::UnitZ());
  return R"({"objects": [
  {"id": 5, "class": "table", "symmetry": "discrete", "t": [1.03, 2.04, 0.4],
   "axis": )" +
         VecJson(tilted) + R"(, "angles": [0, 1.5],
   "poses": [{"t": [1.03, 2.04, 0.4], "q": )" +
         QuatJson((30 + 184) * kDeg, Eigen::Vector3d::UnitZ()) + R"(},
             {"t": [1.03, 2.04, 0.4], "q": )" +
         QuatJson((30 + 90) * kDeg, Eigen::Vector3d::UnitZ()) + R"(}],
   "observations": 3,
   "position_covariance": [[0.0001, 0, 0], [0, 0.0004, 0], [0, 0, 0.01]]},
  {"id": 7, "class": "table", "symmetry": "discrete", "t": [3, 3, 0.4],
   "axis": [0, 0, 1], "angles": [0],
   "poses": [{"t": [3, 3, 0.4], "q": [0, 0, 0, 1]}], "observations": 1},
  {"id": 9, "class": "round_table", "symmetry": "asymmetric",
   "t": [-1, 0, 0.4],
   "poses": [{"t": [-1, 0, 0.4], "q": )" +
         QuatJson(5 * kDeg, Eigen::Vector3d::UnitY()) + R"(}],
   "observations": 2}]}
)";
}

constexpr char kResultAssociations[] =
    "keyframe,detection,object,symmetry\n"
    "0,0/0,5,discrete\n"
    "1,1/0,5,discrete\n"
    "1,1/1,9,continuous\n"
    "2,2/0,7,asymmetric\n"
    "2,2/1,9,continuous\n"
    "3,3/0,5,discrete\n";

class EvaluateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info =
        ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(::testing::TempDir()) /
            (std::string("symba_evaluate_") + info->name());
    fs::remove_all(root_);
    gt_ = root_ / "gt";
    result_ = root_ / "result";
    fs::create_directories(gt_);
    fs::create_directories(result_);
    WriteFile(gt_ / "gt_trajectory.tum", kGtTrajectory);
    WriteFile(gt_ / "gt_objects.json", GtObjects());
    WriteFile(result_ / "trajectory.tum", ResultTrajectory());
    WriteFile(result_ / "objects.json", ResultObjects());
    WriteFile(result_ / "associations.csv", kResultAssociations);
  }
  void TearDown() override { fs::remove_all(root_); }

  // The message of a failing Evaluate.
  std::string Error() {
    Evaluation evaluation;
    const Status status = Evaluate(gt_.string(), result_.string(), &evaluation);
    EXPECT_FALSE(status.ok());
    return status.message();
  }

  fs::path root_;
  fs::path gt_;
  fs::path result_;
};

TEST_F(EvaluateTest, KnownAnswers) {
  Evaluation e;
  const Status status = Evaluate(gt_.string(), result_.string(), &e);
  ASSERT_TRUE(status.ok()) << status.message();

  EXPECT_EQ(e.keyframes, 4);
  // Two of four keyframes 0.1 m off: sqrt(2 * 0.01 / 4).
  EXPECT_NEAR(e.position_rmse, std::sqrt(0.005), 1e-12);
  EXPECT_NEAR(e.max_position_error, 0.1, 1e-12);
  // One of four keyframes 2 degrees off: sqrt(4 / 4) = 1 degree.
  EXPECT_NEAR(e.rotation_rmse_deg, 1.0, 1e-9);
  EXPECT_EQ(e.map_objects, 3);

  ASSERT_EQ(e.objects.size(), 2u);
  const ObjectEvaluation& table = e.objects[0];
  EXPECT_EQ(table.gt_id, 0);
  EXPECT_EQ(table.detections, 4);
  EXPECT_EQ(table.map_objects, 2);
  EXPECT_EQ(table.main_object, 5);
  EXPECT_EQ(table.main_object_symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(table.detections_per_map_object.at(5), 3);
  EXPECT_EQ(table.detections_per_map_object.at(7), 1);
  EXPECT_NEAR(table.translation_error, 0.05, 1e-12);
  // e = (0.03, 0.04, 0): 0.03^2 / 0.0001 + 0.04^2 / 0.0004.
  EXPECT_NEAR(table.position_nees, 13.0, 1e-9);
  EXPECT_NEAR(table.axis_error_deg, 10.0, 1e-9);
  // 184 degrees about z is 4 degrees from the order-2 symmetric pose.
  EXPECT_NEAR(table.rotation_error_deg, 4.0, 1e-9);
  EXPECT_EQ(table.categorized_correctly, 3);
  EXPECT_DOUBLE_EQ(table.categorization_accuracy, 0.75);

  const ObjectEvaluation& round = e.objects[1];
  EXPECT_EQ(round.detections, 2);
  EXPECT_EQ(round.map_objects, 1);
  EXPECT_EQ(round.main_object, 9);
  EXPECT_NEAR(round.translation_error, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(round.position_nees));  // no covariance
  // An asymmetric map object's axis is its rotation applied to axis_o.
  EXPECT_NEAR(round.axis_error_deg, 5.0, 1e-9);
  EXPECT_NEAR(round.rotation_error_deg, 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(round.categorization_accuracy, 1.0);

  EXPECT_EQ(e.detections, 6);
  EXPECT_EQ(e.categorized_correctly, 5);
  EXPECT_DOUBLE_EQ(e.categorization_accuracy, 5.0 / 6.0);
  const int kA = static_cast<int>(SymmetryType::kAsymmetric);
  const int kD = static_cast<int>(SymmetryType::kDiscrete);
  const int kC = static_cast<int>(SymmetryType::kContinuous);
  EXPECT_EQ(e.confusion[kD][kD], 3);
  EXPECT_EQ(e.confusion[kD][kA], 1);
  EXPECT_EQ(e.confusion[kC][kC], 2);
  EXPECT_EQ(e.confusion[kA][kA], 0);
  EXPECT_EQ(e.MaxFragmentation(), 2);
}

TEST_F(EvaluateTest, AsymmetricObjectRotationErrorAndUndetectedObject) {
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [
  {"id": 3, "class": "chair", "symmetry": "asymmetric", "order": 0,
   "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}},
  {"id": 4, "class": "chair", "symmetry": "asymmetric", "order": 0,
   "pose": {"t": [5, 5, 0], "q": [0, 0, 0, 1]}}],
 "detections": {"0/0": 3}})");
  WriteFile(result_ / "objects.json",
            R"({"objects": [
  {"id": 0, "class": "chair", "symmetry": "asymmetric", "t": [0, 0, 0.2],
   "poses": [{"t": [0, 0, 0.2], "q": )" +
                QuatJson(7 * kDeg, Eigen::Vector3d::UnitX()) +
                R"(}], "observations": 1}]})");
  WriteFile(result_ / "associations.csv",
            "keyframe,detection,object,symmetry\n0,0/0,0,asymmetric\n");
  Evaluation e;
  const Status status = Evaluate(gt_.string(), result_.string(), &e);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(e.objects.size(), 2u);
  EXPECT_EQ(e.objects[0].map_objects, 1);
  EXPECT_NEAR(e.objects[0].translation_error, 0.2, 1e-12);
  EXPECT_TRUE(std::isnan(e.objects[0].axis_error_deg));
  EXPECT_NEAR(e.objects[0].rotation_error_deg, 7.0, 1e-9);
  // Never detected: no main object, nothing defined.
  EXPECT_EQ(e.objects[1].detections, 0);
  EXPECT_EQ(e.objects[1].map_objects, 0);
  EXPECT_EQ(e.objects[1].main_object, -1);
  EXPECT_TRUE(std::isnan(e.objects[1].translation_error));
  EXPECT_TRUE(std::isnan(e.objects[1].categorization_accuracy));
  EXPECT_DOUBLE_EQ(e.categorization_accuracy, 1.0);

  const std::string table = FormatEvaluationTable(e);
  EXPECT_THAT(table,
              HasSubstr("| 4 | chair | asymmetric | 0 | 0 | none | "
                        "n/a | n/a | n/a | n/a |"));
  const nlohmann::json json = nlohmann::json::parse(FormatEvaluationJson(e));
  EXPECT_TRUE(json["objects"][1]["translation_error"].is_null());
  EXPECT_TRUE(json["objects"][1]["main_object"].is_null());
}

TEST_F(EvaluateTest, TableAndJson) {
  Evaluation e;
  ASSERT_TRUE(Evaluate(gt_.string(), result_.string(), &e).ok());
  const std::string table = FormatEvaluationTable(e);
  EXPECT_THAT(table,
              HasSubstr("| 4 | 0.071 | 1.00 | 0.100 | 3 | 83.3 % (5/6) |"));
  EXPECT_THAT(table,
              HasSubstr("| 0 | table | discrete (2) | 4 | 2 | 5 (discrete) | "
                        "0.050 | 10.00 | 4.00 | 75.0 % (3/4) |"));
  EXPECT_THAT(table, HasSubstr("| discrete | 1 | 3 | 0 |"));

  const nlohmann::json json = nlohmann::json::parse(FormatEvaluationJson(e));
  EXPECT_EQ(json["keyframes"], 4);
  EXPECT_DOUBLE_EQ(json["position_rmse"].get<double>(), e.position_rmse);
  EXPECT_EQ(json["max_fragmentation"], 2);
  EXPECT_EQ(json["objects"][0]["map_objects"], 2);
  EXPECT_EQ(json["objects"][0]["detections_per_map_object"]["7"], 1);
  EXPECT_TRUE(json["objects"][1]["axis_error_deg"].is_number());
  EXPECT_EQ(json["confusion"]["discrete"]["asymmetric"], 1);
}

TEST_F(EvaluateTest, MissingFiles) {
  fs::remove(gt_ / "gt_objects.json");
  EXPECT_EQ(Error(), (gt_ / "gt_objects.json").string() + ": cannot open");
  fs::remove(gt_ / "gt_trajectory.tum");
  EXPECT_EQ(Error(), (gt_ / "gt_trajectory.tum").string() + ": cannot open");
}

TEST_F(EvaluateTest, MissingResultFile) {
  fs::remove(result_ / "associations.csv");
  EXPECT_EQ(Error(), (result_ / "associations.csv").string() + ": cannot open");
}

TEST_F(EvaluateTest, BadJsonNamesTheLine) {
  WriteFile(gt_ / "gt_objects.json", "{\"objects\": [\n  {\"id\": 0,,\n");
  EXPECT_EQ(Error(),
            (gt_ / "gt_objects.json").string() +
                ":2: invalid JSON at column 12: syntax error while parsing "
                "object key - "
                "unexpected ','; expected string literal");
}

TEST_F(EvaluateTest, TruncatedJson) {
  WriteFile(result_ / "objects.json", "{\"objects\": [\n");
  EXPECT_EQ(Error(),
            (result_ / "objects.json").string() +
                ":2: invalid JSON at column 1: syntax error while parsing "
                "value - "
                "unexpected end of input; expected '[', '{', or a literal");
}

TEST_F(EvaluateTest, JsonContentErrorsNameTheMember) {
  const std::string path = (gt_ / "gt_objects.json").string();
  WriteFile(gt_ / "gt_objects.json", "[]");
  EXPECT_EQ(Error(), path + ": expected an object, got an array");
  WriteFile(gt_ / "gt_objects.json", R"({"detections": {}})");
  EXPECT_EQ(Error(), path + ": objects: missing");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "table", "symmetry": "discrete", "order": 2,
    "axis_o": [0, 0, 1], "axis": [0, 0, 1],
    "pose": {"t": [0, 0], "q": [0, 0, 0, 1]}}], "detections": {}})");
  EXPECT_EQ(Error(),
            path +
                ": objects[0].pose.t: expected an array of 3 numbers, got 2 "
                "elements");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "table", "symmetry": "discrete", "order": 2,
    "axis_o": [0, 0, 1], "axis": [1, 0, 0],
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}}], "detections": {}})");
  EXPECT_EQ(Error(), path + ": objects[0].axis: is not pose.q * axis_o");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "table", "symmetry": "round", "order": 0,
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}}], "detections": {}})");
  EXPECT_EQ(Error(),
            path +
                ": objects[0].symmetry: \"round\" is not asymmetric, "
                "discrete or continuous");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "table", "symmetry": "discrete", "order": 1,
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}}], "detections": {}})");
  EXPECT_EQ(Error(),
            path +
                ": objects[0].order: a discrete object needs an order of "
                "at least 2");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "chair", "symmetry": "asymmetric", "order": 0,
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 2]}}], "detections": {}})");
  EXPECT_EQ(Error(),
            path +
                ": objects[0].pose.q: quaternion norm 2 is not within 1e-3 "
                "of 1");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "chair", "symmetry": "asymmetric", "order": 0,
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}}],
    "detections": {"0/0": 0, "1/0": 4}})");
  EXPECT_EQ(Error(),
            path + ": detections[\"1/0\"]: object 4 is not in objects");
  WriteFile(gt_ / "gt_objects.json", R"({"objects": [{"id": 0,
    "class": "chair", "symmetry": "asymmetric", "order": 0,
    "pose": {"t": [0, 0, 0], "q": [0, 0, 0, 1]}}],
    "detections": {"0/0": "zero"}})");
  EXPECT_EQ(Error(),
            path +
                ": detections[\"0/0\"]: expected an integer, got the string "
                "\"zero\"");
  WriteFile(result_ / "objects.json",
            R"({"objects": [{"id": 5, "class": "table",
    "symmetry": "discrete", "t": [0, 0, 0], "angles": [0],
    "poses": [{"t": [0, 0, 0], "q": [0, 0, 0, 1]}], "observations": 1}]})");
  WriteFile(gt_ / "gt_objects.json", GtObjects());
  EXPECT_EQ(Error(),
            (result_ / "objects.json").string() + ": objects[0].axis: missing");
}

TEST_F(EvaluateTest, TrajectoryErrorsNameTheLine) {
  const std::string gt_path = (gt_ / "gt_trajectory.tum").string();
  const std::string path = (result_ / "trajectory.tum").string();
  WriteFile(result_ / "trajectory.tum", "0 0 0 1 0 0 0 1\n0.5 1 0 1 0 0 1\n");
  EXPECT_EQ(Error(),
            path +
                ":2: expected 8 numbers (timestamp tx ty tz qx qy qz qw), "
                "found 7");
  WriteFile(result_ / "trajectory.tum", "0 0 0 1 0 0 0 1\n0.5 1 0 x 0 0 0 1\n");
  EXPECT_EQ(Error(), path + ":2: \"x\" is not a finite number");
  WriteFile(result_ / "trajectory.tum", "0 0 0 1 0 0 0 1\n0 1 0 1 0 0 0 1\n");
  EXPECT_EQ(Error(), path + ":2: timestamp 0 is not after the previous one");
  WriteFile(result_ / "trajectory.tum", "0 0 0 1 0 0 0 1\n0.7 1 0 1 0 0 0 1\n");
  EXPECT_EQ(Error(),
            path + ":2: no keyframe of " + gt_path + " has timestamp 0.7");
  WriteFile(result_ / "trajectory.tum", "0 0 0 1 0 0 0 1\n0.5 1 0 1 0 0 0 1\n");
  EXPECT_EQ(
      Error(),
      gt_path + ":4: the keyframe at timestamp 1 has no estimate in " + path);
  WriteFile(result_ / "trajectory.tum", "\n");
  EXPECT_EQ(Error(), path + ": no keyframes");
}

TEST_F(EvaluateTest, AssociationErrorsNameTheLine) {
  const std::string path = (result_ / "associations.csv").string();
  WriteFile(result_ / "associations.csv", "keyframe,detection,object\n");
  EXPECT_EQ(
      Error(),
      path + ":1: expected the header keyframe,detection,object,symmetry");
  WriteFile(result_ / "associations.csv",
            "keyframe,detection,object,symmetry\n0,0/0,5\n");
  EXPECT_EQ(Error(), path + ":2: expected 4 fields, found 3");
  WriteFile(result_ / "associations.csv",
            "keyframe,detection,object,symmetry\n0,0/0,five,discrete\n");
  EXPECT_EQ(Error(), path + ":2: object \"five\" is not an integer");
  WriteFile(result_ / "associations.csv",
            std::string(kResultAssociations) + "3,9/9,5,discrete\n");
  EXPECT_EQ(Error(),
            path + ":8: detection \"9/9\" is not in " +
                (gt_ / "gt_objects.json").string());
  WriteFile(result_ / "associations.csv",
            std::string(kResultAssociations) + "3,\"3/0\",5,discrete\n");
  EXPECT_EQ(Error(), path + ":8: duplicate detection \"3/0\"");
  WriteFile(result_ / "associations.csv",
            "keyframe,detection,object,symmetry\n0,0/0,6,discrete\n");
  EXPECT_EQ(Error(),
            path + ":2: map object 6 is not in " +
                (result_ / "objects.json").string());
  WriteFile(result_ / "associations.csv",
            "keyframe,detection,object,symmetry\n0,0/0,5,discrete\n");
  EXPECT_EQ(Error(),
            (gt_ / "gt_objects.json").string() +
                ": detection \"1/0\" has no row in " + path);
}

}  // namespace
}  // namespace symba
