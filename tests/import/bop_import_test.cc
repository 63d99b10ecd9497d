// symba import bop as a library: units, frames and grouping on a small
// input with exact expected values; the BOP symmetry mapping; a front end's
// trajectory matched by image time; and for each bad input its message and
// no output file.
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "import/bop_files.h"
#include "symba/import/bop_import.h"

namespace symba {
namespace {

namespace fs = std::filesystem;
using import_internal::BopContinuousSymmetry;
using import_internal::MapBopSymmetries;

constexpr double kPi = 3.14159265358979323846;

// Image 0: camera at the world origin; image 3: camera 1 m along world x,
// turned by 180 degrees about z (R_w2c = diag(-1, -1, 1), t_w2c = R_w2c *
// -c = (1000, 0, 0) mm).
constexpr const char* kSceneCamera = R"({
  "0": {"cam_K": [600, 0, 320, 0, 610, 240, 0, 0, 1],
        "cam_R_w2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_w2c": [0, 0, 0]},
  "3": {"cam_K": [600, 0, 320, 0, 610, 240, 0, 0, 1],
        "cam_R_w2c": [-1, 0, 0, 0, -1, 0, 0, 0, 1],
        "cam_t_w2c": [1000, 0, 0]}
})";

// Image 0, object 1: two rows 10 mm apart (one detection), one 500 mm
// away (another); image 3, object 2: one row, R = 90 degrees about z.
constexpr const char* kResults =
    "scene_id,im_id,obj_id,score,R,t,time\n"
    "7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0.1\n"
    "7,0,1,0.5,1 0 0 0 1 0 0 0 1,500 0 1000,0.1\n"
    "7,0,1,0.3,1 0 0 0 1 0 0 0 1,10 0 1000,0.1\n"
    "\n"
    "7,3,2,0.8,0 -1 0 1 0 0 0 0 1,0 100 2000,-1\n";

class BopImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("bop_import_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    options_.results = Write("results.csv", kResults);
    options_.scene_camera = Write("scene_camera.json", kSceneCamera);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::string Log() const { return (dir_ / "out.jsonl").string(); }

  // The message of a failed import; the log must not have been written.
  std::string Failure() {
    const Status status = ImportBopToLog(options_, Log(), nullptr);
    EXPECT_FALSE(status.ok());
    EXPECT_FALSE(fs::exists(Log())) << "a failed import wrote the log";
    return status.message();
  }

  fs::path dir_;
  BopImportOptions options_;
};

TEST_F(BopImportTest, GroupsRowsIntoDetectionsInMetresAndCameraToWorld) {
  options_.class_names = {{1, "mug"}};
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  BopImportReport report;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, &report).ok());
  EXPECT_EQ(report.rows, 4);
  EXPECT_EQ(report.keyframes, 2);
  EXPECT_EQ(report.detections, 3);
  ASSERT_TRUE(header.camera.has_value());
  EXPECT_EQ(header.camera->fx, 600.0);
  EXPECT_EQ(header.camera->fy, 610.0);
  EXPECT_EQ(header.camera->cx, 320.0);
  EXPECT_EQ(header.camera->cy, 240.0);
  EXPECT_TRUE(header.classes.empty()) << "no models_info, no priors";

  ASSERT_EQ(keyframes.size(), 2u);
  EXPECT_EQ(keyframes[0].id, 0);
  EXPECT_EQ(keyframes[1].id, 3);
  EXPECT_EQ(keyframes[0].timestamp, 0.0);
  EXPECT_EQ(keyframes[1].timestamp, 3.0);
  ASSERT_TRUE(keyframes[1].T_wc.has_value());
  EXPECT_FALSE(keyframes[1].odometry.has_value());
  // T_wc = T_cw^-1: the camera centre is (1, 0, 0) m.
  EXPECT_NEAR(
      (keyframes[1].T_wc->t - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(keyframes[1].T_wc->q.angularDistance(Eigen::Quaterniond(
                  Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()))),
              0.0,
              1e-12);

  const std::vector<DetectionInput>& d0 = keyframes[0].detections;
  ASSERT_EQ(d0.size(), 2u);
  EXPECT_EQ(d0[0].id, "0/0");
  EXPECT_EQ(d0[1].id, "0/1");
  EXPECT_EQ(d0[0].class_name, "mug");
  ASSERT_EQ(d0[0].hypotheses.size(), 2u);  // rows 1 and 3, 10 mm apart
  EXPECT_EQ(d0[0].hypotheses[0].weight, 0.9);
  EXPECT_EQ(d0[0].hypotheses[1].weight, 0.3);
  EXPECT_EQ(d0[0].score, 0.9);
  EXPECT_NEAR((d0[0].hypotheses[1].T_co.t - Eigen::Vector3d(0.01, 0, 1)).norm(),
              0.0,
              1e-15);
  ASSERT_EQ(d0[1].hypotheses.size(), 1u);
  EXPECT_EQ(d0[1].score, 0.5);
  EXPECT_FALSE(d0[0].sigma_t.has_value());

  const DetectionInput& d3 = keyframes[1].detections.at(0);
  EXPECT_EQ(d3.id, "3/0");
  EXPECT_EQ(d3.class_name, "obj_2");
  EXPECT_NEAR((d3.hypotheses[0].T_co.t - Eigen::Vector3d(0, 0.1, 2)).norm(),
              0.0,
              1e-15);
  EXPECT_NEAR(d3.hypotheses[0].T_co.q.angularDistance(Eigen::Quaterniond(
                  Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()))),
              0.0,
              1e-12);
}

TEST_F(BopImportTest, TheGateDecidesWhatIsOneDetection) {
  options_.gate = 0.005;  // 5 mm: the rows 10 mm apart are two detections
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  ASSERT_EQ(keyframes[0].detections.size(), 3u);
  EXPECT_EQ(keyframes[0].detections[2].id, "0/2");
  EXPECT_EQ(keyframes[0].detections[2].score, 0.3);
}

TEST_F(BopImportTest, ModelsInfoGivesClassPriorsAndTheGate) {
  // Object 1: a cylinder about z through the origin, 18 mm wide (gate 9
  // mm: the rows 10 mm apart part). Object 2: a 4-fold box.
  options_.models_info = Write("models_info.json", R"({
    "1": {"diameter": 18, "symmetries_continuous":
          [{"axis": [0, 0, 1], "offset": [0, 0, 0]}]},
    "2": {"diameter": 300, "symmetries_discrete": [
          [0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
          [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
          [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]]}
  })");
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  BopImportReport report;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, &report).ok());
  EXPECT_EQ(keyframes[0].detections.size(), 3u);
  ASSERT_EQ(header.classes.size(), 2u);
  const ClassPrior& cylinder = header.classes.at("obj_1");
  EXPECT_EQ(cylinder.symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(cylinder.axis_o, Eigen::Vector3d(0, 0, 1));
  const ClassPrior& box = header.classes.at("obj_2");
  EXPECT_EQ(box.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(box.order, 4);
  EXPECT_NEAR((box.axis_o - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-9);
  EXPECT_TRUE(report.symmetry_notes.empty());
}

Rigid3d Rotation(double angle, const Eigen::Vector3d& axis) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)),
                 Eigen::Vector3d::Zero());
}

TEST(MapBopSymmetries, ExactCases) {
  std::string note;
  EXPECT_EQ(MapBopSymmetries({}, {}, &note).symmetry,
            SymmetryType::kAsymmetric);
  EXPECT_EQ(note, "");
  // C3 about -x, listed with the identity: the axis is written +x.
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const ClassPrior c3 = MapBopSymmetries(
      {Rigid3d(), Rotation(2 * kPi / 3, -x), Rotation(4 * kPi / 3, -x)},
      {},
      &note);
  EXPECT_EQ(c3.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(c3.order, 3);
  EXPECT_NEAR((c3.axis_o - x).norm(), 0.0, 1e-9);
  EXPECT_EQ(note, "");
  BopContinuousSymmetry about_y;
  about_y.axis = -Eigen::Vector3d::UnitY();
  const ClassPrior round = MapBopSymmetries({}, {about_y}, &note);
  EXPECT_EQ(round.symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(round.axis_o, Eigen::Vector3d::UnitY());
  EXPECT_EQ(note, "");
}

TEST(MapBopSymmetries, InexactCasesAreMappedAndSaid) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  std::string note;
  // A box: D2 (180 degrees about x, y and z) -> discrete 2 about x.
  const ClassPrior box = MapBopSymmetries(
      {Rotation(kPi, x), Rotation(kPi, y), Rotation(kPi, z)}, {}, &note);
  EXPECT_EQ(box.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(box.order, 2);
  EXPECT_NEAR((box.axis_o - x).norm(), 0.0, 1e-9);
  EXPECT_EQ(note,
            "3 discrete symmetries that are not the cyclic group of one "
            "axis: mapped to discrete 2 about [1, 0, 0]; the others are not "
            "modelled");
  // D4: C4 about z and four flips -> discrete 4 about z.
  const ClassPrior d4 = MapBopSymmetries({Rotation(kPi / 2, z),
                                          Rotation(kPi, z),
                                          Rotation(3 * kPi / 2, z),
                                          Rotation(kPi, x),
                                          Rotation(kPi, y)},
                                         {},
                                         &note);
  EXPECT_EQ(d4.order, 4);
  EXPECT_NEAR((d4.axis_o - z).norm(), 0.0, 1e-9);
  // A can: continuous about z plus a flip about x.
  BopContinuousSymmetry about_z;
  const ClassPrior can = MapBopSymmetries({Rotation(kPi, x)}, {about_z}, &note);
  EXPECT_EQ(can.symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(note,
            "continuous about [0, 0, 1] plus 1 discrete symmetries: mapped "
            "to continuous about [0, 0, 1]; the others are not modelled");
  // An axis 20 mm off the origin.
  about_z.offset = Eigen::Vector3d(0.02, 0, 0);
  MapBopSymmetries({}, {about_z}, &note);
  EXPECT_EQ(note,
            "its axis passes 20 mm from the model's origin, symba's "
            "through it");
  // A 2-fold whose transform also shifts the origin by 30 mm.
  Rigid3d shifted = Rotation(kPi, z);
  shifted.t = Eigen::Vector3d(0.03, 0, 0);
  const ClassPrior c2 = MapBopSymmetries({shifted}, {}, &note);
  EXPECT_EQ(c2.order, 2);
  EXPECT_EQ(note,
            "its symmetries move the model's origin by up to 30 mm (the axis "
            "misses the origin, symba's passes through it)");
  // 90 degrees about z alone is no group: its largest cyclic subgroup is
  // the identity -> asymmetric.
  const ClassPrior none = MapBopSymmetries({Rotation(kPi / 2, z)}, {}, &note);
  EXPECT_EQ(none.symmetry, SymmetryType::kAsymmetric);
  EXPECT_EQ(note,
            "1 discrete symmetries that are not the cyclic group of one "
            "axis: mapped to asymmetric");
  // An offset no int can hold is still said, in millimetres.
  shifted.t = Eigen::Vector3d(3e9, 0, 0);
  MapBopSymmetries({shifted}, {}, &note);
  EXPECT_EQ(note,
            "its symmetries move the model's origin by up to 3e+12 mm (the "
            "axis misses the origin, symba's passes through it)");
  // C_60 about z and a flip about x: the 60-fold subgroup is found among
  // the 60 transforms (the identity listed too).
  std::vector<Rigid3d> c60 = {Rotation(kPi, x)};
  for (int k = 0; k < 60; ++k) c60.push_back(Rotation(2 * kPi * k / 60, z));
  const ClassPrior sixty = MapBopSymmetries(c60, {}, &note);
  EXPECT_EQ(sixty.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(sixty.order, 60);
  EXPECT_NEAR((sixty.axis_o - z).norm(), 0.0, 1e-9);
}

// An axis whose norm overflows (or underflows) a double still has its
// direction.
TEST_F(BopImportTest, AHugeContinuousAxisKeepsItsDirection) {
  options_.models_info =
      Write("models_info.json",
            R"({"1": {"symmetries_continuous": [{"axis": [0, 0, 1e200]}]},
          "2": {"symmetries_continuous": [{"axis": [0, -1e-200, 0]}]}})");
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  EXPECT_EQ(header.classes.at("obj_1").axis_o, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(header.classes.at("obj_2").axis_o, Eigen::Vector3d(0, 1, 0));
}

TEST_F(BopImportTest, PosesFromATrajectoryMatchedByImageTime) {
  options_.trajectory = Write("frontend.tum",
                              "10.00 0 0 0 0 0 0 1\n"
                              "10.49 2 0 0 0 0 0 1\n"
                              "10.51 3 0 0 0 0 0 1\n");
  // TUM rgb.txt: im_id = the data line's index.
  options_.image_times = Write("rgb.txt",
                               "# timestamp filename\n"
                               "10.005 rgb/10.005.png\n"
                               "10.100 rgb/10.100.png\n"
                               "10.200 rgb/10.200.png\n"
                               "10.505 rgb/10.505.png\n");
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  BopImportReport report;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, &report).ok());
  ASSERT_EQ(keyframes.size(), 2u);
  EXPECT_EQ(keyframes[0].timestamp, 10.005);
  EXPECT_EQ(keyframes[1].timestamp, 10.505);
  EXPECT_EQ(keyframes[0].T_wc->t, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(keyframes[1].T_wc->t, Eigen::Vector3d(3, 0, 0));  // nearest

  // "im_id timestamp" lines; image 3 has no pose within 0.02 s.
  options_.image_times = Write("times.txt", "0 10.0\n3 10.3\n");
  EXPECT_EQ(Failure(),
            options_.image_times + ":2: image 3 has no pose in " +
                options_.trajectory + " within 0.02 s");
  options_.skip_images_without_pose = true;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, &report).ok());
  EXPECT_EQ(keyframes.size(), 1u);
  EXPECT_EQ(report.skipped_images, 1);
  EXPECT_EQ(report.skipped_rows, 1);
}

// A UTF-8 byte order mark (spreadsheet programs write one) at the start of
// the CSV, the trajectory or the image times is not part of the first line.
TEST_F(BopImportTest, ByteOrderMarksAreSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  LogHeader header;
  std::vector<KeyframeInput> expected;
  ASSERT_TRUE(ImportBop(options_, &header, &expected, nullptr).ok());
  options_.results = Write("bom.csv", bom + kResults);
  options_.trajectory =
      Write("bom.tum", bom + "0.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n");
  options_.image_times = Write("bom_times.txt", bom + "0 0.0\n3 1.0\n");
  std::vector<KeyframeInput> keyframes;
  const Status status = ImportBop(options_, &header, &keyframes, nullptr);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(keyframes.size(), expected.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    EXPECT_EQ(keyframes[k].detections.size(), expected[k].detections.size());
  }
  EXPECT_EQ(keyframes[1].timestamp, 1.0);
  EXPECT_EQ(keyframes[1].T_wc->t, Eigen::Vector3d(1, 0, 0));
}

// A directory is named as one; a pipe (a FIFO here, `<(...)` in a shell)
// is read to its end like a file.
TEST_F(BopImportTest, DirectoriesAreRefusedAndPipesRead) {
  const std::string results = options_.results;
  options_.results = dir_.string();
  EXPECT_EQ(Failure(), dir_.string() + ": is a directory");
  options_.results = results;
  options_.scene_camera = dir_.string();
  EXPECT_EQ(Failure(), dir_.string() + ": is a directory");
  options_.scene_camera = (dir_ / "scene_camera.json").string();

  LogHeader header;
  std::vector<KeyframeInput> expected;
  ASSERT_TRUE(ImportBop(options_, &header, &expected, nullptr).ok());
  const std::string fifo = (dir_ / "results.fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&fifo] { std::ofstream(fifo) << kResults; });
  options_.results = fifo;
  std::vector<KeyframeInput> keyframes;
  const Status status = ImportBop(options_, &header, &keyframes, nullptr);
  writer.join();
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(keyframes.size(), expected.size());
  EXPECT_EQ(keyframes[0].detections.size(), expected[0].detections.size());
}

// A first line that starts like the header must be the header; a file
// with old Mac line ends ('\r' alone) is one such line.
TEST_F(BopImportTest, AHeaderLineNamesTheSevenColumns) {
  options_.results = Write("bad_header.csv", "scene_idXYZ garbage\n");
  EXPECT_EQ(Failure(),
            options_.results +
                ":1: a header line must be "
                "scene_id,im_id,obj_id,score,R,t,time");
  std::string mac = kResults;
  std::replace(mac.begin(), mac.end(), '\n', '\r');
  options_.results = Write("mac.csv", mac);
  EXPECT_EQ(Failure(),
            options_.results +
                ":1: a header line must be "
                "scene_id,im_id,obj_id,score,R,t,time (this line holds a "
                "carriage return: lines must end with \\n or \\r\\n)");
}

// The first data line decides the form of the image times; every later
// line must have it, so a misread time is an error where it stands.
TEST_F(BopImportTest, ImageTimesKeepTheFormOfTheirFirstLine) {
  options_.image_times = Write("times.txt", "0 0,000\n3 0,033\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ":1: expected \"im_id timestamp\" or \"timestamp "
                "filename\" (TUM rgb.txt)");
  options_.image_times = Write("times.txt", "# times\n0 0.0\n3 0.167s\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ":3: expected \"im_id timestamp\" as on line 2 (a "
                "non-negative integer and a number)");
  options_.image_times = Write("times.txt", "0 0.0\n3 NaN\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ":2: expected \"im_id timestamp\" as on line 1 (a "
                "non-negative integer and a number)");
  options_.image_times =
      Write("rgb.txt", "10.0 rgb/10.0.png\n10.1 rgb/10.1.png\n7 8\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ":3: expected \"timestamp filename\" (TUM rgb.txt) as on "
                "line 1");
}

// Options that are not numbers the importer can use; rows of other scenes
// are counted; an output that is an input is refused.
TEST_F(BopImportTest, BadOptionsAndOutputsAreNamed) {
  options_.gate = std::nan("");
  EXPECT_EQ(Failure(), "options: gate: must be positive and finite, got nan");
  options_.gate.reset();
  options_.detection_sigma_r = -1.0;
  EXPECT_EQ(Failure(),
            "options: detection sigma_r: must be in [1e-9, 1e9], got -1");
  options_.detection_sigma_r.reset();

  options_.results = Write("two_scenes.csv",
                           "7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n"
                           "8,3,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n"
                           "8,3,2,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n");
  options_.scene = 7;
  BopImportReport report;
  ASSERT_TRUE(ImportBopToLog(options_, Log(), &report).ok());
  EXPECT_EQ(report.rows, 1);
  EXPECT_EQ(report.other_scene_rows, 2);

  const Status status = ImportBopToLog(options_, options_.results, nullptr);
  EXPECT_EQ(status.message(),
            options_.results + ": is the input " + options_.results);
  std::ifstream kept(options_.results);
  std::string first;
  std::getline(kept, first);
  EXPECT_EQ(first, "7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0");
}

// The w2c poses with the images' times from --image-times (no trajectory).
TEST_F(BopImportTest, ImageTimesTimeTheSceneCameraPoses) {
  options_.image_times = Write("times.txt", "3 20.25\n0 20.0\n");
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  ASSERT_EQ(keyframes.size(), 2u);
  EXPECT_EQ(keyframes[0].id, 0);
  EXPECT_EQ(keyframes[0].timestamp, 20.0);
  EXPECT_EQ(keyframes[1].id, 3);
  EXPECT_EQ(keyframes[1].timestamp, 20.25);
  EXPECT_TRUE(keyframes[1].T_wc->t.isApprox(Eigen::Vector3d(1, 0, 0)));

  // Equal times are a log's right (timestamps only must not decrease).
  options_.image_times = Write("times.txt", "0 20.5\n3 20.5\n");
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  EXPECT_EQ(keyframes[1].timestamp, 20.5);

  options_.image_times = Write("times.txt", "0 21.0\n3 20.5\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ": image 3 is earlier than image 0: the times must not "
                "decrease with the image id");
  options_.image_times = Write("times.txt", "0 20.0\n");
  EXPECT_EQ(Failure(),
            options_.image_times + ": no time for image 3 of " +
                options_.scene_camera);
}

TEST_F(BopImportTest, EachBadInputNamesItsFileAndLineAndWritesNothing) {
  const std::string results = options_.results;
  const std::string scene = options_.scene_camera;
  struct Case {
    std::string csv;
    std::string message;  // after "results.csv:"
  };
  const Case csv_cases[] = {
      {"7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000\n",
       "1: expected 7 comma-separated fields "
       "(scene_id,im_id,obj_id,score,R,t,time), got 6"},
      {"7,x,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n",
       "1: im_id: expected a non-negative integer, got \"x\""},
      // A long value is cut at 40 bytes, a control byte escaped.
      {"7,0,1," + std::string(50, '9') + "\t\x01" +
           ",1 0 0 0 1 0 0 0 1,0 0 1000,0\n",
       "1: score: expected a number, got \"" + std::string(40, '9') + "...\""},
      {"7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,\x01\n",
       "1: time: expected a number, got \"\\u0001\""},
      {"7,0,1,nan,1 0 0 0 1 0 0 0 1,0 0 1000,0\n",
       "1: score: expected a number, got \"nan\""},
      {"7,0,1,0.9,1 0 0 0 1 0 0 0,0 0 1000,0\n",
       "1: R: expected 9 space-separated numbers (row-major)"},
      {"7,0,1,0.9,1 0 0 0 1 0 0 0 -1,0 0 1000,0\n",
       "1: R: not a rotation (|R^T R - I| = 0, det = -1)"},
      {"7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 1000,0\n",
       "1: t: expected 3 space-separated numbers (mm)"},
      {"7,5,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n",
       "1: image 5 is not in " + scene},
      {"7,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n"
       "8,0,1,0.9,1 0 0 0 1 0 0 0 1,0 0 1000,0\n",
       "2: scene 8 after scene 7: a log holds one scene; choose it with "
       "--scene"},
  };
  for (const Case& c : csv_cases) {
    options_.results = Write("bad.csv", c.csv);
    EXPECT_EQ(Failure(), options_.results + ":" + c.message);
  }
  options_.results = results;

  const std::pair<std::string, std::string> json_cases[] = {
      {R"({"0": {"cam_R_w2c": [1, 0, 0, 0, 1, 0, 0, 0, 1]}})",
       ": [\"0\"].cam_K: missing (9 numbers, row-major)"},
      {R"({"x": {"cam_K": [1, 0, 0, 0, 1, 0, 0, 0, 1]}})",
       ": [\"x\"]: expected a non-negative integer id as the key"},
      {R"({"0": {"cam_K": [1, 0, 0, 0, 1, 0, 0, 0, 1],
                 "cam_R_w2c": [1, 0, 0, 0, 1, 0, 0, 0, 1]}})",
       ": [\"0\"]: cam_R_w2c and cam_t_w2c go together"},
      {R"({"0": {"cam_K": [1, 0, 0, 0, 1, 0, 0, 0, 1]}})",
       ": [\"0\"]: no cam_R_w2c/cam_t_w2c; give the front end's poses with "
       "--trajectory and --image-times, or skip such images"},
  };
  for (const auto& [json, message] : json_cases) {
    options_.scene_camera = Write("bad_scene_camera.json", json);
    EXPECT_EQ(Failure(), options_.scene_camera + message);
  }
  options_.scene_camera = scene;

  options_.models_info = Write(
      "bad_models_info.json",
      R"({"1": {"symmetries_discrete": [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]]}})");
  EXPECT_EQ(Failure(),
            options_.models_info +
                ": [\"1\"].symmetries_discrete[0]: expected an array of 16 "
                "numbers, got 11 elements");
  options_.models_info.clear();

  options_.trajectory = Write("t.tum", "10 0 0 0 0 0 0 1\n");
  EXPECT_EQ(Failure(), "options: a trajectory needs the image times");
  options_.image_times = Write("times.txt", "0 10\n0 11\n");
  EXPECT_EQ(Failure(), options_.image_times + ":2: image 0 already at line 1");
  options_.image_times = Write("times.txt", "0\n");
  EXPECT_EQ(Failure(),
            options_.image_times +
                ":1: expected \"im_id timestamp\" or \"timestamp filename\" "
                "(TUM rgb.txt)");
}

TEST(BopClassNames, ParsesPairsAndRefusesOthers) {
  std::map<int, std::string> names;
  ASSERT_TRUE(ParseBopClassNames("1=ape,12=can", &names).ok());
  EXPECT_EQ(names.size(), 2u);
  EXPECT_EQ(names.at(12), "can");
  std::map<int, std::string> again;
  EXPECT_EQ(ParseBopClassNames("1=ape,1=cat", &again).message(),
            "class names \"1=ape,1=cat\": obj_id 1 named twice");
  std::map<int, std::string> bad;
  EXPECT_EQ(ParseBopClassNames("ape", &bad).message(),
            "class names \"ape\": expected obj_id=name pairs, got \"ape\"");
}

// The header's "bop" key records where the log came from: the scene and
// the obj_id of every class (rows and models_info), for replay --bop-out.
TEST_F(BopImportTest, HeaderRecordsTheSceneAndEachClassObjId) {
  options_.class_names = {{1, "mug"}};
  options_.models_info =
      Write("models_info.json", R"({"5": {"diameter": 100}, "1": {}})");
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  ASSERT_TRUE(header.bop.has_value());
  EXPECT_EQ(header.bop->scene_id, 7);
  EXPECT_EQ(
      header.bop->obj_ids,
      (std::map<std::string, int>{{"mug", 1}, {"obj_2", 2}, {"obj_5", 5}}));

  options_.scene = 8;  // a scene without rows: its id all the same
  ASSERT_TRUE(ImportBop(options_, &header, &keyframes, nullptr).ok());
  EXPECT_EQ(header.bop->scene_id, 8);
}

TEST_F(BopImportTest, TwoObjIdsOfOneClassNameAreRefused) {
  options_.class_names = {{1, "box"}, {2, "box"}};
  EXPECT_EQ(Failure(),
            "class names: obj_ids 1 and 2 are both named \"box\"; a class "
            "maps to one BOP obj_id");
}

}  // namespace
}  // namespace symba
