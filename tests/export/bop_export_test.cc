// BOP export: the results CSV's text, the refined rows of a replay
// (ids, the symmetric pose nearest the detector's, T_cw * T_wo in mm), the
// export of a log to BOP files read back by symba import bop, and every
// error with its message and no output.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/export/bop_export.h"
#include "symba/export/bop_results_csv.h"
#include "symba/export/refined_bop_results.h"
#include "symba/import/bop_import.h"
#include "symba/io/file_output.h"
#include "symba/io/log_file.h"

namespace symba {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

Eigen::Quaterniond RotZ(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("bop_export_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(BopResultsCsv, HeaderAndRowsInMillimetresRowMajor) {
  BopResult row;
  row.scene_id = 7;
  row.im_id = 12;
  row.obj_id = 3;
  row.score = 0.875;
  // 180 degrees about z: R = diag(-1, -1, 1) exactly.
  row.T_co =
      Rigid3d(Eigen::Quaterniond(0, 0, 0, 1), Eigen::Vector3d(0.25, -0.5, 1.5));
  BopResult second = row;
  second.im_id = 13;
  second.T_co =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 2.0));
  second.time = 0.125;
  EXPECT_EQ(FormatBopResultsCsv({row, second}),
            "scene_id,im_id,obj_id,score,R,t,time\n"
            "7,12,3,0.875,-1 0 0 0 -1 0 0 0 1,250 -500 1500,-1\n"
            "7,13,3,0.875,1 0 0 0 1 0 0 0 1,0 0 2000,0.125\n");
  EXPECT_EQ(FormatBopResultsCsv({}), "scene_id,im_id,obj_id,score,R,t,time\n");
}

TEST(BopResultsCsv, RowMajorMeansRowByRow) {
  BopResult row;
  row.T_co.q = RotZ(kPi / 2);  // R = [0 -1 0; 1 0 0; 0 0 1]
  const std::string text = FormatBopResultsCsv({row});
  std::istringstream line(text.substr(text.find('\n') + 1));
  std::vector<std::string> fields;
  for (std::string field; std::getline(line, field, ',');) {
    fields.push_back(field);
  }
  ASSERT_EQ(fields.size(), 7u);
  std::istringstream numbers(fields[4]);
  double R[9];
  for (double& value : R) numbers >> value;
  // R(0, 1) = -1 is the second number, R(1, 0) = 1 the fourth.
  EXPECT_NEAR(R[1], -1.0, 1e-15);
  EXPECT_NEAR(R[3], 1.0, 1e-15);
  EXPECT_NEAR(R[8], 1.0, 1e-15);
  EXPECT_NEAR(std::abs(R[0]) + std::abs(R[4]), 0.0, 1e-15);
}

TEST(BopResultsCsv, WritesAtomicallyAndLeavesNothingOnError) {
  const fs::path dir = FreshDir("atomic");
  const std::string path = (dir / "results.csv").string();
  ASSERT_TRUE(WriteBopResultsCsv(path, {BopResult()}).ok());
  EXPECT_EQ(ReadFile(path),
            "scene_id,im_id,obj_id,score,R,t,time\n"
            "0,0,0,1,1 0 0 0 1 0 0 0 1,0 0 0,-1\n");
  const std::string missing = (dir / "no" / "results.csv").string();
  const Status status = WriteBopResultsCsv(missing, {});
  EXPECT_EQ(status.message(),
            missing + ": cannot write (No such file or directory)");
  EXPECT_EQ(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

MapObjectEstimate Object(int id,
                         const std::string& class_name,
                         SymmetryType symmetry,
                         const Eigen::Vector3d& t_wo) {
  MapObjectEstimate object;
  object.id = id;
  object.class_name = class_name;
  object.symmetry = symmetry;
  object.t_wo = t_wo;
  return object;
}

TEST(ClosestSymmetricPose, DiscretePicksTheAngleNearestTheDetection) {
  MapObjectEstimate table =
      Object(0, "table", SymmetryType::kDiscrete, Eigen::Vector3d(1, 2, 3));
  table.axis_w = Eigen::Vector3d::UnitZ();
  table.axis_o = Eigen::Vector3d::UnitZ();
  table.angles = {0.0, kPi};
  table.poses = {Rigid3d(RotZ(0.3), table.t_wo),
                 Rigid3d(RotZ(0.3 + kPi), table.t_wo)};
  const Rigid3d T_cw(RotZ(-0.3), Eigen::Vector3d(0, 0, 1));
  // The detector saw the table at 170 degrees in the camera: the pose at
  // angle pi (camera rotation -0.3 + 0.3 + pi = 180 degrees) is 10 away.
  const Rigid3d reference(RotZ(kPi * 170 / 180), Eigen::Vector3d::Zero());
  const Rigid3d T_wo = ClosestSymmetricPose(table, T_cw, reference);
  EXPECT_EQ(T_wo.q.coeffs(), table.poses[1].q.coeffs());
  EXPECT_EQ(T_wo.t, table.t_wo);
  const Rigid3d near_zero(RotZ(0.1), Eigen::Vector3d::Zero());
  EXPECT_EQ(ClosestSymmetricPose(table, T_cw, near_zero).q.coeffs(),
            table.poses[0].q.coeffs());
}

// With the prior's order a flip folded onto the object's one angle gets
// the turned pose back: R_wo_0 Rot(a_o, pi) for a detection near pi.
TEST(ClosestSymmetricPose, AKnownOrderTurnsTheOneAngleByTheSymmetry) {
  MapObjectEstimate table =
      Object(0, "table", SymmetryType::kDiscrete, Eigen::Vector3d(1, 2, 3));
  table.axis_w = Eigen::Vector3d::UnitZ();
  table.axis_o = Eigen::Vector3d::UnitZ();
  table.angles = {0.0};
  table.poses = {Rigid3d(RotZ(0.3), table.t_wo)};
  const Rigid3d T_cw(RotZ(-0.3), Eigen::Vector3d(0, 0, 1));
  const Rigid3d reference(RotZ(kPi * 170 / 180), Eigen::Vector3d::Zero());
  // Without the order: the one pose, 170 degrees from the detection.
  EXPECT_EQ(ClosestSymmetricPose(table, T_cw, reference).q.coeffs(),
            table.poses[0].q.coeffs());
  // Order 2: turned by pi, 10 degrees from it.
  const Rigid3d turned = ClosestSymmetricPose(table, T_cw, reference, 2);
  EXPECT_LT(turned.q.angularDistance(RotZ(0.3 + kPi)), 1e-12);
  EXPECT_EQ(turned.t, table.t_wo);
  // Order 4 and a detection at 95 degrees: turned by pi / 2.
  const Rigid3d at_95(RotZ(kPi * 95 / 180), Eigen::Vector3d::Zero());
  EXPECT_LT(ClosestSymmetricPose(table, T_cw, at_95, 4)
                .q.angularDistance(RotZ(0.3 + kPi / 2)),
            1e-12);
}

TEST(ClosestSymmetricPose, ContinuousTurnsAboutTheAxisToTheDetection) {
  // A round table with its axis along world x (its pose turns object z
  // onto world x), seen from a camera turned 0.4 rad about z.
  MapObjectEstimate round =
      Object(0, "round", SymmetryType::kContinuous, Eigen::Vector3d(0.5, 0, 2));
  const Eigen::Quaterniond R_wo0(
      Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
  round.axis_w = Eigen::Vector3d::UnitX();
  round.axis_o = Eigen::Vector3d::UnitZ();
  round.poses = {Rigid3d(R_wo0, round.t_wo)};
  const Rigid3d T_cw(RotZ(0.4), Eigen::Vector3d(0.1, 0, 0));
  // The detector's pose: the table turned by 1.1 rad about its axis, plus
  // a small tilt off it (which no turn about the axis can explain).
  const Eigen::Quaterniond turned =
      Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitX())) *
      R_wo0;
  const Eigen::Quaterniond tilt(
      Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()));
  const Rigid3d reference(T_cw.q * tilt * turned, Eigen::Vector3d::Zero());
  const Rigid3d T_wo = ClosestSymmetricPose(round, T_cw, reference);
  EXPECT_NEAR(T_wo.q.angularDistance(turned), 0.0, 1e-4);
  EXPECT_EQ(T_wo.t, round.t_wo);
  // Still a pose of the same table: its axis stays world x.
  EXPECT_NEAR((T_wo.q * round.axis_o - round.axis_w).norm(), 0.0, 1e-12);
}

// A replay of one keyframe, camera 1 m behind the world origin: a table
// (asymmetric, 2 m in front) with detection "3/0"; "3/1" was an outlier.
struct SmallReplay {
  ReplayResult replay;
  std::vector<KeyframeInput> keyframes;

  SmallReplay() {
    replay.header.bop = BopSource{7, {{"table", 4}}};
    KeyframeEstimate k;
    k.id = 3;
    k.T_wc = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -1));
    replay.keyframes = {k};
    MapObjectEstimate table = Object(
        5, "table", SymmetryType::kAsymmetric, Eigen::Vector3d(0.1, 0, 1));
    table.poses = {Rigid3d(RotZ(kPi / 2), table.t_wo)};
    replay.objects = {table};
    replay.assignments = {{3, "3/0", 5, SymmetryType::kAsymmetric},
                          {3, "3/1", -1, SymmetryType::kAsymmetric}};
    KeyframeInput input;
    input.id = 3;
    input.T_wc = Rigid3d();
    for (const char* id : {"3/0", "3/1"}) {
      DetectionInput d;
      d.id = id;
      d.class_name = "table";
      d.score = 0.625;
      d.hypotheses = {{Rigid3d(), 1.0}};
      input.detections.push_back(d);
    }
    keyframes = {input};
  }
};

TEST(RefinedBopResults, OneRowPerAssignedDetectionWithTheHeadersIds) {
  const SmallReplay small;
  std::vector<BopResult> rows;
  ASSERT_TRUE(RefinedBopResults(small.replay, small.keyframes, {}, &rows).ok());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].scene_id, 7);
  EXPECT_EQ(rows[0].im_id, 3);
  EXPECT_EQ(rows[0].obj_id, 4);
  EXPECT_EQ(rows[0].score, 0.625);
  EXPECT_EQ(rows[0].time, -1.0);
  // T_co = T_cw T_wo: the camera at z = -1 sees the table at z = 1 2 m away.
  EXPECT_EQ(rows[0].T_co.t, Eigen::Vector3d(0.1, 0, 2));
  EXPECT_EQ(rows[0].T_co.q.coeffs(), RotZ(kPi / 2).coeffs());
  EXPECT_EQ(FormatBopResultsCsv(rows).substr(37, 16), "7,3,4,0.625,2.22");
}

TEST(RefinedBopResults, TheSceneOptionAndObjNamesStandInForTheHeader) {
  SmallReplay small;
  small.replay.header.bop.reset();
  std::vector<BopResult> rows;
  EXPECT_EQ(
      RefinedBopResults(small.replay, small.keyframes, {}, &rows).message(),
      "no BOP scene id: the log header has no \"bop\" key (symba import "
      "bop writes one); give the scene id (--bop-scene)");
  RefinedBopResultsOptions options;
  options.scene_id = 9;
  EXPECT_EQ(RefinedBopResults(small.replay, small.keyframes, options, &rows)
                .message(),
            "class \"table\": no BOP obj_id: the log header has no \"bop\" key "
            "and the name is not obj_<id>");
  for (KeyframeInput& k : small.keyframes) {
    for (DetectionInput& d : k.detections) d.class_name = "obj_000012";
  }
  ASSERT_TRUE(
      RefinedBopResults(small.replay, small.keyframes, options, &rows).ok());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].scene_id, 9);
  EXPECT_EQ(rows[0].obj_id, 12);
}

TEST(RefinedBopResults, EachBadInputIsNamed) {
  SmallReplay small;
  small.replay.header.bop->obj_ids = {{"mug", 1}};
  std::vector<BopResult> rows;
  EXPECT_EQ(
      RefinedBopResults(small.replay, small.keyframes, {}, &rows).message(),
      "class \"table\": no BOP obj_id: the log header's bop.obj_ids "
      "does not list it and the name is not obj_<id>");
  RefinedBopResultsOptions options;
  options.scene_id = -2;
  EXPECT_EQ(RefinedBopResults(small.replay, small.keyframes, options, &rows)
                .message(),
            "scene id: must be a non-negative integer, got -2");
  small = SmallReplay();
  small.keyframes[0].id = 4;
  EXPECT_EQ(
      RefinedBopResults(small.replay, small.keyframes, {}, &rows).message(),
      "keyframe 4 is not in the replay");
  small = SmallReplay();
  small.keyframes[0].id = -3;
  small.replay.keyframes[0].id = -3;
  small.replay.assignments[0].keyframe = -3;
  EXPECT_EQ(
      RefinedBopResults(small.replay, small.keyframes, {}, &rows).message(),
      "keyframe -3: not a BOP im_id (an integer from 0 to 2147483647)");
}

// A log of two keyframes: the second has odometry only (its front-end pose
// is the first's composed with it) and a table detection whose best
// hypothesis is the second; the header has a camera and a discrete prior.
std::string WriteSmallLog(const fs::path& dir) {
  LogHeader header;
  header.camera = PinholeIntrinsics{500.0, 510.0, 320.0, 240.0};
  header.classes["table"] =
      ClassPrior{SymmetryType::kDiscrete, 2, Eigen::Vector3d(0, 0, 2)};
  KeyframeInput first;
  first.id = 2;
  first.timestamp = 0.5;
  first.T_wc = Rigid3d(RotZ(kPi), Eigen::Vector3d(1, 0, 0));
  DetectionInput mug;
  mug.class_name = "mug";
  mug.hypotheses = {{Rigid3d(RotZ(0.2), Eigen::Vector3d(0.1, 0.2, 1.5)), 0.5}};
  first.detections = {mug};
  KeyframeInput second;
  second.id = 5;
  second.timestamp = 1.25;
  second.odometry =
      Odometry{Rigid3d(RotZ(kPi / 2), Eigen::Vector3d(0, 0.5, 0)), 0.01, 0.01};
  DetectionInput table;
  table.class_name = "table";
  table.sigma_t = 0.03;
  table.hypotheses = {
      {Rigid3d(RotZ(0.1), Eigen::Vector3d(0, 0, 2)), 0.7},
      {Rigid3d(RotZ(0.1 + kPi), Eigen::Vector3d(0.01, 0, 2)), 0.9},
      {Rigid3d(RotZ(0.15), Eigen::Vector3d(0, 0.02, 2)), 0.75}};
  second.detections = {table};
  const std::string path = (dir / "small.jsonl").string();
  EXPECT_TRUE(WriteLogAtomically(path, header, {first, second}).ok());
  return path;
}

TEST(ExportLogToBop, WritesTheFilesTheImporterReadsBack) {
  const fs::path dir = FreshDir("files");
  const std::string log = WriteSmallLog(dir);
  const std::string out = (dir / "bop").string();
  BopExportOptions options;
  options.scene_id = 4;
  options.diameter = 0.5;
  BopExportReport report;
  const Status status = ExportLogToBopDirectory(log, options, out, &report);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(report.images, 2);
  EXPECT_EQ(report.rows, 4);
  EXPECT_EQ(report.obj_ids,
            (std::map<std::string, int>{{"mug", 1}, {"table", 2}}));
  ASSERT_EQ(report.notes.size(), 1u);
  EXPECT_EQ(report.notes[0],
            "class \"mug\" (obj_id 1): symmetry or axis unknown, written "
            "without symmetries (BOP reads that as asymmetric)");

  const std::string csv = ReadFile(fs::path(out) / "results.csv");
  std::vector<std::string> lines;
  std::istringstream csv_lines(csv);
  for (std::string line; std::getline(csv_lines, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], "scene_id,im_id,obj_id,score,R,t,time");
  EXPECT_EQ(lines[1].substr(0, 12), "4,2,1,0.5,0.");
  EXPECT_EQ(lines[2].substr(0, 11), "4,5,2,0.9,-");  // the best first
  EXPECT_NE(lines[2].find(",10 0 2000,-1"), std::string::npos) << lines[2];
  EXPECT_NE(lines[3].find(",0 0 2000,-1"), std::string::npos) << lines[3];
  EXPECT_EQ(lines[3].substr(0, 10), "4,5,2,0.7,");
  EXPECT_EQ(lines[4].substr(0, 11), "4,5,2,0.75,");
  EXPECT_EQ(ReadFile(fs::path(out) / "image_times.txt"), "2 0.5\n5 1.25\n");
  EXPECT_EQ(ReadFile(fs::path(out) / "class_names.txt"), "1=mug,2=table\n");
  const std::string models = ReadFile(fs::path(out) / "models_info.json");
  EXPECT_NE(models.find("\"1\": {\"diameter\": 500.0}"), std::string::npos)
      << models;
  EXPECT_NE(models.find("\"2\": {\"diameter\": 500.0, \"symmetries_discrete\": "
                        "[[-1.0, "),
            std::string::npos)
      << models;

  // Read back with both pose sources: the same keyframes and detections.
  BopImportOptions import;
  import.results = (fs::path(out) / "results.csv").string();
  import.scene_camera = (fs::path(out) / "scene_camera.json").string();
  import.models_info = (fs::path(out) / "models_info.json").string();
  import.class_names = {{1, "mug"}, { 2, "table" }};
  for (bool trajectory : {false, true}) {
    SCOPED_TRACE(trajectory ? "frontend.tum" : "scene_camera.json");
    if (trajectory) {
      import.trajectory = (fs::path(out) / "frontend.tum").string();
      import.image_times = (fs::path(out) / "image_times.txt").string();
    }
    LogHeader header;
    std::vector<KeyframeInput> keyframes;
    const Status read = ImportBop(import, &header, &keyframes, nullptr);
    ASSERT_TRUE(read.ok()) << read.message();
    EXPECT_EQ(header.camera->fx, 500.0);
    EXPECT_EQ(header.camera->fy, 510.0);
    ASSERT_TRUE(header.bop.has_value());
    EXPECT_EQ(header.bop->scene_id, 4);
    const ClassPrior& prior = header.classes.at("table");
    EXPECT_EQ(prior.symmetry, SymmetryType::kDiscrete);
    EXPECT_EQ(prior.order, 2);
    EXPECT_NEAR((prior.axis_o - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_EQ(header.classes.at("mug").symmetry, SymmetryType::kAsymmetric);
    ASSERT_EQ(keyframes.size(), 2u);
    EXPECT_EQ(keyframes[1].id, 5);
    EXPECT_EQ(keyframes[1].timestamp, trajectory ? 1.25 : 5.0);
    // T_wc(5) = T_wc(2) T_{2,5}: (1, 0, 0) + Rot(z, pi) (0, 0.5, 0).
    EXPECT_NEAR((keyframes[1].T_wc->t - Eigen::Vector3d(1, -0.5, 0)).norm(),
                0.0,
                1e-12);
    EXPECT_NEAR(
        keyframes[1].T_wc->q.angularDistance(RotZ(-kPi / 2)), 0.0, 1e-12);
    ASSERT_EQ(keyframes[1].detections.size(), 1u);
    const DetectionInput& table = keyframes[1].detections[0];
    EXPECT_EQ(table.id, "5/0");
    EXPECT_EQ(table.score, 0.9);
    EXPECT_FALSE(table.sigma_t.has_value()) << "BOP carries no sigma";
    ASSERT_EQ(table.hypotheses.size(), 3u);
    EXPECT_EQ(table.hypotheses[0].weight, 0.9);
    EXPECT_NEAR(table.hypotheses[0].T_co.q.angularDistance(RotZ(0.1 + kPi)),
                0.0,
                1e-12);
    EXPECT_NEAR(
        (table.hypotheses[2].T_co.t - Eigen::Vector3d(0, 0.02, 2)).norm(),
        0.0,
        1e-12);
  }
}

// A log may give two keyframes the same time; a TUM trajectory may not (the
// importer refuses it), so frontend.tum is left out with a note and the
// other files, scene_camera.json's poses among them, still import.
TEST(ExportLogToBop, RepeatedTimesLeaveOutTheTumTrajectoryWithANote) {
  const fs::path dir = FreshDir("repeated_times");
  LogHeader header;
  header.camera = PinholeIntrinsics{500.0, 500.0, 320.0, 240.0};
  std::vector<KeyframeInput> keyframes(3);
  for (int k = 0; k < 3; ++k) {
    keyframes[k].id = 10 + k;
    keyframes[k].timestamp = k == 0 ? 0.5 : 0.75;
    keyframes[k].T_wc = Rigid3d(RotZ(0.1 * k), Eigen::Vector3d(k, 0, 0));
  }
  const std::string log = (dir / "repeated.jsonl").string();
  ASSERT_TRUE(WriteLogAtomically(log, header, keyframes).ok());
  const std::string out = (dir / "bop").string();
  BopExportReport report;
  const Status status = ExportLogToBopDirectory(log, {}, out, &report);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(report.notes.size(), 1u);
  EXPECT_EQ(report.notes[0],
            "frontend.tum not written: keyframe 12 has the time 0.75 of the "
            "keyframe before it, and a TUM trajectory needs increasing times "
            "(scene_camera.json carries the same poses)");
  EXPECT_FALSE(fs::exists(fs::path(out) / "frontend.tum"));
  EXPECT_EQ(ReadFile(fs::path(out) / "image_times.txt"),
            "10 0.5\n11 0.75\n12 0.75\n");

  BopImportOptions import;
  import.results = (fs::path(out) / "results.csv").string();
  import.scene_camera = (fs::path(out) / "scene_camera.json").string();
  import.image_times = (fs::path(out) / "image_times.txt").string();
  LogHeader read_header;
  std::vector<KeyframeInput> read;
  const Status read_status = ImportBop(import, &read_header, &read, nullptr);
  ASSERT_TRUE(read_status.ok()) << read_status.message();
  ASSERT_EQ(read.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(read[k].timestamp, keyframes[k].timestamp);
    EXPECT_NEAR((read[k].T_wc->t - keyframes[k].T_wc->t).norm(), 0.0, 1e-12);
  }
}

// --class-names separates its pairs with commas, so a class name with one
// cannot be written there: class_names.txt is left out with a note (the
// import then names the classes obj_<id>). An output directory that holds
// the log is refused: replacing it would delete the log.
TEST(ExportLogToBop, ACommaInAClassNameAndAnOutputHoldingTheLog) {
  const fs::path dir = FreshDir("comma");
  LogHeader header;
  header.camera = PinholeIntrinsics{500.0, 500.0, 320.0, 240.0};
  KeyframeInput keyframe;
  keyframe.T_wc = Rigid3d();
  DetectionInput detection;
  detection.class_name = "a,b";
  detection.hypotheses = {{Rigid3d(), 1.0}};
  keyframe.detections = {detection};
  const std::string log = (dir / "comma.jsonl").string();
  ASSERT_TRUE(WriteLogAtomically(log, header, {keyframe}).ok());
  BopExportReport report;
  const std::string out = (dir / "bop").string();
  ASSERT_TRUE(ExportLogToBopDirectory(log, {}, out, &report).ok());
  EXPECT_FALSE(fs::exists(fs::path(out) / "class_names.txt"));
  ASSERT_EQ(report.notes.size(), 2u);
  EXPECT_EQ(report.notes[1],
            "class_names.txt not written: the class \"a,b\" has a comma, "
            "which --class-names separates pairs with (the import names the "
            "classes obj_<id>)");

  EXPECT_EQ(ExportLogToBopDirectory(log, {}, dir.string(), nullptr).message(),
            dir.string() + ": holds the input " + log);
  EXPECT_TRUE(fs::exists(log));
}

TEST(ExportLogToBop, EachBadInputIsNamedAndNothingIsWritten) {
  const fs::path dir = FreshDir("errors");
  const std::string out = (dir / "bop").string();
  auto failure = [&out](const std::string& log, const BopExportOptions& o) {
    const Status status = ExportLogToBopDirectory(log, o, out, nullptr);
    EXPECT_FALSE(status.ok());
    EXPECT_FALSE(fs::exists(out)) << "a failed export wrote " << out;
    return status.message();
  };
  const std::string log = WriteSmallLog(dir);
  BopExportOptions options;
  options.diameter = 0.0;
  EXPECT_EQ(failure(log, options),
            "options: diameter: must be positive, got 0");
  options.diameter = 1e306;  // 1e309 mm is no double
  EXPECT_EQ(failure(log, options),
            "options: diameter: must be positive, got 1e+306");
  options = BopExportOptions();
  options.scene_id = -1;
  EXPECT_EQ(failure(log, options),
            "options: scene id: must be a non-negative integer, got -1");

  const std::string no_camera = (dir / "no_camera.jsonl").string();
  std::ofstream(no_camera) << "{\"format\": \"symba-log\", \"version\": 1}\n";
  EXPECT_EQ(failure(no_camera, {}),
            no_camera +
                ": header: no camera; scene_camera.json needs cam_K (the "
                "intrinsics)");

  const std::string negative = (dir / "negative.jsonl").string();
  std::ofstream(negative)
      << "{\"format\": \"symba-log\", \"version\": 1, \"camera\": {\"fx\": 1, "
         "\"fy\": 1, \"cx\": 0, \"cy\": 0}}\n\n"
         "{\"keyframe\": -1, \"t\": 0, \"T_wc\": {\"t\": [0, 0, 0], \"q\": "
         "[0, 0, 0, 1]}}\n";
  EXPECT_EQ(failure(negative, {}),
            negative +
                ":3: keyframe -1: not a BOP im_id (an integer from 0 to "
                "2147483647)");

  const std::string truncated = (dir / "truncated.jsonl").string();
  std::ofstream(truncated) << ReadFile(log).substr(0, ReadFile(log).size() - 5);
  const std::string message = failure(truncated, {});
  EXPECT_EQ(message.rfind(truncated + ":3: invalid JSON at column ", 0), 0u)
      << message;
  EXPECT_EQ(failure((dir / "absent.jsonl").string(), {}),
            (dir / "absent.jsonl").string() + ": cannot open");
}

TEST(ClassSymmetriesFromGroundTruth, ReadsEachClassAndRefusesConflicts) {
  const fs::path dir = FreshDir("gt");
  const std::string gt = (dir / "gt_objects.json").string();
  const std::string object_a =
      "{\"id\": 0, \"class\": \"table\", \"symmetry\": \"discrete\", "
      "\"order\": 2, \"axis_o\": [0.0, 0.0, 1.0], \"axis\": [0.0, 0.0, 1.0], "
      "\"pose\": {\"t\": [0.0, 0.0, 0.0], \"q\": [0.0, 0.0, 0.0, 1.0]}}";
  const std::string object_b =
      "{\"id\": 1, \"class\": \"table\", \"symmetry\": \"discrete\", "
      "\"order\": 4, \"axis_o\": [0.0, 0.0, 1.0], \"axis\": [0.0, 0.0, 1.0], "
      "\"pose\": {\"t\": [1.0, 0.0, 0.0], \"q\": [0.0, 0.0, 0.0, 1.0]}}";
  std::ofstream(gt) << "{\"objects\": [" << object_a
                    << "], \"detections\": {}}\n";
  std::map<std::string, ClassPrior> symmetries;
  Status status = ClassSymmetriesFromGroundTruth(gt, &symmetries);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(symmetries.count("table"), 1u);
  EXPECT_EQ(symmetries["table"].order, 2);
  EXPECT_EQ(symmetries["table"].axis_o, Eigen::Vector3d::UnitZ());

  std::ofstream(gt) << "{\"objects\": [" << object_a << ", " << object_b
                    << "], \"detections\": {}}\n";
  symmetries.clear();
  EXPECT_EQ(ClassSymmetriesFromGroundTruth(gt, &symmetries).message(),
            gt + ": class \"table\": object 1's symmetry differs from an "
                 "earlier object of its class");
}

}  // namespace
}  // namespace symba
