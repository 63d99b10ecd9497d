// The map file (symba/io/map_file.h, docs/map-format.md): what is written
// reads back as the same map and writes again as the same bytes; every
// malformed file is refused with its name, the member's path and the
// reason, leaving the caller's map unchanged.
#include "symba/io/map_file.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace symba {
namespace {

MapObjectEstimate Chair() {
  MapObjectEstimate o;
  o.id = 0;
  o.class_name = "chair";
  o.symmetry = SymmetryType::kAsymmetric;
  o.t_wo = Eigen::Vector3d(0.1, -2.0 / 3.0, 1e-9);
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  o.poses = {Rigid3d(q, o.t_wo)};
  o.observations = 41;
  MapObjectCovariance c;
  c.id = 0;
  c.position << 1e-4, 2e-6, 0, 2e-6, 2e-4, 0, 0, 0, 3.333333e-4;
  c.rotation = Eigen::Matrix3d::Identity() * 0.0012345678;
  o.covariance = c;
  return o;
}

MapObjectEstimate Table() {
  MapObjectEstimate o;
  o.id = 4;
  o.class_name = "table";
  o.symmetry = SymmetryType::kDiscrete;
  o.t_wo = Eigen::Vector3d(1, 2, 0.4);
  o.axis_w = Eigen::Vector3d::UnitZ();
  o.axis_o = Eigen::Vector3d::UnitZ();
  o.angles = {0.25, 0.25 + M_PI};
  for (double a : o.angles) {
    o.poses.push_back(Rigid3d(
        Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())),
        o.t_wo));
  }
  o.angle_evidence = {5.25, 1.75};
  o.observations = 7;
  MapObjectEstimate::Upgrade upgrade;
  upgrade.keyframe = 12;
  upgrade.evidence = 3;
  upgrade.order = 2;
  upgrade.angle = 3.1;
  o.upgrade = upgrade;
  return o;
}

SavedMap Map() {
  SavedMap map;
  map.objects = {Chair(), Table()};
  map.noise = {{"chair", 0.05},
               {"table", 0.031, 0.12, 0.012, 0.034, 6.25, 1.0}};
  return map;
}

TEST(MapFile, RoundTripKeepsEveryValueAndTheBytes) {
  const std::string text = FormatMapFile(Map());
  SavedMap read;
  const Status status = ParseMapFile(text, "map.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(read.objects.size(), 2u);
  const MapObjectEstimate& chair = read.objects[0];
  EXPECT_EQ(chair.id, 0);
  EXPECT_EQ(chair.class_name, "chair");
  EXPECT_EQ(chair.t_wo, Chair().t_wo);  // exact: shortest round-trip text
  EXPECT_EQ(chair.observations, 41);
  ASSERT_TRUE(chair.covariance && chair.covariance->rotation);
  EXPECT_EQ((*chair.covariance->rotation)(1, 1), 0.00123457);  // 6 digits
  const MapObjectEstimate& table = read.objects[1];
  EXPECT_EQ(table.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(table.angles, Table().angles);
  EXPECT_EQ(table.angle_evidence, Table().angle_evidence);
  EXPECT_EQ(table.angle_probabilities, std::vector<double>({0.75, 0.25}));
  ASSERT_EQ(table.poses.size(), 2u);
  EXPECT_NEAR((table.axis_o - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  ASSERT_TRUE(table.upgrade.has_value());
  EXPECT_EQ(table.upgrade->keyframe, 12);
  EXPECT_EQ(table.upgrade->order, 2);
  ASSERT_EQ(read.noise.size(), 2u);
  EXPECT_EQ(read.noise[0].sigma_t, 0.05);
  EXPECT_FALSE(read.noise[0].sigma_r.has_value());
  EXPECT_EQ(read.noise[1].sigma_r, 0.12);
  EXPECT_FALSE(read.noise[0].white_sigma_t || read.noise[0].white_sigma_r ||
               read.noise[0].claim_factor_t || read.noise[0].claim_factor_r);
  EXPECT_EQ(read.noise[1].white_sigma_t, 0.012);
  EXPECT_EQ(read.noise[1].white_sigma_r, 0.034);
  EXPECT_EQ(read.noise[1].claim_factor_t, 6.25);
  EXPECT_EQ(read.noise[1].claim_factor_r, 1.0);
  // Writing what was read gives the same bytes, and so on.
  const std::string again = FormatMapFile(read);
  EXPECT_EQ(again, text);
  SavedMap third;
  ASSERT_TRUE(ParseMapFile(again, "map.json", &third).ok());
  EXPECT_EQ(FormatMapFile(third), text);
}

// Normalising a unit quaternion or axis again may change its last bit; the
// writer and the reader keep one that is unit already, so maps of random
// rotations keep their bytes too, and keyframe ids beyond 32 bits survive.
TEST(MapFile, RandomRotationsAndLargeIdsKeepTheirBytes) {
  std::srand(3);
  auto uniform = [] { return 2.0 * std::rand() / RAND_MAX - 1.0; };
  SavedMap map;
  for (int i = 0; i < 200; ++i) {
    MapObjectEstimate o = Table();
    o.id = i;
    o.axis_w = Eigen::Vector3d(uniform(), uniform(), uniform()).normalized();
    for (Rigid3d& pose : o.poses) {
      pose.q = Eigen::Quaterniond(uniform(), uniform(), uniform(), uniform())
                   .normalized();
    }
    o.upgrade->keyframe = (int64_t{1} << 40) + i;
    map.objects.push_back(o);
  }
  const std::string text = FormatMapFile(map);
  SavedMap read;
  const Status status = ParseMapFile(text, "map.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.objects[7].upgrade->keyframe, (int64_t{1} << 40) + 7);
  EXPECT_EQ(FormatMapFile(read), text);
}

// The evidence is optional: a map without it (written before it existed,
// or by another tool) reads as zero evidence, uniform probabilities, and
// the probabilities written are always those of the evidence (a reader
// never takes them).
TEST(MapFile, AngleEvidenceIsOptionalAndTheProbabilitiesAreDerived) {
  std::string text = FormatMapFile(Map());
  const size_t begin = text.find("\"angle_evidence\"");
  const size_t end = text.find("\"poses\"", begin);
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  text.erase(begin, end - begin);
  SavedMap read;
  Status status = ParseMapFile(text, "old.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.objects[1].angle_evidence, std::vector<double>({0.0, 0.0}));
  EXPECT_EQ(read.objects[1].angle_probabilities,
            std::vector<double>({0.5, 0.5}));
  EXPECT_TRUE(read.objects[0].angle_evidence.empty());  // asymmetric

  text = FormatMapFile(Map());
  const std::string written = "\"angle_probabilities\": [\n        0.75,";
  const size_t at = text.find(written);
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, written.size(), "\"angle_probabilities\": [\n        0.1,");
  status = ParseMapFile(text, "edited.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.objects[1].angle_probabilities,
            std::vector<double>({0.75, 0.25}));
}

TEST(MapFile, EmptyMapIsValid) {
  SavedMap read;
  read.noise = {{"x", 1.0, 1.0}};
  const Status status = ParseMapFile(
      R"({"format": "symba-map", "version": 1, "objects": [], "noise": []})",
      "empty.json",
      &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(read.objects.empty());
  EXPECT_TRUE(read.noise.empty());
}

// Replaces the first `from` in the written map by `to`.
std::string Edited(const std::string& from, const std::string& to) {
  std::string text = FormatMapFile(Map());
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

struct BadMap {
  std::string name;
  std::string text;
  std::string message;  // what the error must contain
};

TEST(MapFile, MalformedFilesAreRefusedWithWhereAndWhy) {
  const std::vector<BadMap> cases = {
      {"syntax", "{\"format\": ", "bad.json:1: invalid JSON"},
      {"not an object", "[1, 2]", "bad.json: expected an object"},
      {"format",
       Edited("\"symba-map\"", "\"symba-log\""),
       "bad.json: format: expected \"symba-map\""},
      {"no version",
       Edited("\"version\": 1,", ""),
       "bad.json: version: missing"},
      {"future version",
       Edited("\"version\": 1", "\"version\": 2"),
       "version 2 is not supported"},
      {"no objects",
       Edited("\"objects\"", "\"things\""),
       "bad.json: objects: missing"},
      {"duplicate id",
       Edited("\"id\": 4", "\"id\": 0"),
       "objects[1].id: duplicate id 0"},
      {"negative id",
       Edited("\"id\": 4", "\"id\": -4"),
       "objects[1].id: expected an id in [0, 100000)"},
      {"huge id",
       Edited("\"id\": 4", "\"id\": 100000"),
       "objects[1].id: expected an id in [0, 100000)"},
      {"negative observations",
       Edited("\"observations\": 41", "\"observations\": -1"),
       "objects[0].observations: expected a count >= 0"},
      {"empty class",
       Edited("\"class\": \"chair\"", "\"class\": \"\""),
       "objects[0].class: expected a class name"},
      {"symmetry", Edited("\"discrete\"", "\"round\""), "objects[1].symmetry"},
      {"axis missing",
       Edited("\"axis\"", "\"axes\""),
       "objects[1].axis: missing"},
      {"not a unit quaternion",
       Edited("\"q\": [", "\"q\": [7, "),
       "objects[0].poses[0].q"},
      {"poses per angle",
       Edited("\"angles\": [\n        0.25,", "\"angles\": ["),
       "objects[1].poses: expected 1 poses, one per angle"},
      {"angle evidence per angle",
       Edited("\"angle_evidence\": [\n        5.25,", "\"angle_evidence\": ["),
       "objects[1].angle_evidence: expected 2 entries, one per angle"},
      {"negative angle evidence",
       Edited("5.25", "-5.25"),
       "objects[1].angle_evidence[0]: expected evidence >= 0"},
      {"angle evidence of an asymmetric object",
       Edited("\"observations\": 41",
              "\"observations\": 41, \"angle_evidence\": [1]"),
       "objects[0].angle_evidence: only a discrete object has it"},
      {"asymmetric rotation covariance",
       Edited("\"rotation_covariance\"", "\"axis_covariance\""),
       "objects[0].axis_covariance: only a symmetric object has one"},
      {"upgrade of an asymmetric object",
       Edited("\"observations\": 41", "\"observations\": 41, \"upgrade\": {}"),
       "objects[0].upgrade: only a symmetric object has one"},
      {"upgrade member",
       Edited("\"evidence\": 3", "\"evidence\": \"3\""),
       "objects[1].upgrade.evidence"},
      {"no noise",
       Edited("\"noise\"", "\"noises\""),
       "bad.json: noise: missing"},
      {"noise class order",
       Edited("\"class\": \"table\",\n      \"sigma_t\"",
              "\"class\": \"a\",\n      \"sigma_t\""),
       "noise[1].class: classes must be sorted by name, each once"},
      {"noise sigma",
       Edited("\"sigma_t\": 0.05", "\"sigma_t\": 0"),
       "noise[0].sigma_t: must be positive"},
      {"noise white sigma",
       Edited("\"white_sigma_r\": 0.034", "\"white_sigma_r\": -0.034"),
       "noise[1].white_sigma_r: must be positive"},
      {"claim factor below 1",
       Edited("\"claim_factor_t\": 6.25", "\"claim_factor_t\": 0.5"),
       "noise[1].claim_factor_t: must be at least 1"},
      {"claim factor not a number",
       Edited("\"claim_factor_r\": 1.0", "\"claim_factor_r\": \"1\""),
       "noise[1].claim_factor_r"},
  };
  for (const BadMap& c : cases) {
    SavedMap map = Map();
    const Status status = ParseMapFile(c.text, "bad.json", &map);
    ASSERT_FALSE(status.ok()) << c.name;
    EXPECT_NE(status.message().find(c.message), std::string::npos)
        << c.name << ": " << status.message();
    EXPECT_EQ(FormatMapFile(map), FormatMapFile(Map())) << c.name;
  }
}

TEST(MapFile, MissingFileNamesIt) {
  SavedMap map;
  const Status status = ReadMapFile("/nonexistent/map.json", &map);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("/nonexistent/map.json"), std::string::npos);
}

}  // namespace
}  // namespace symba
