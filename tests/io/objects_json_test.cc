// objects.json's covariance members (symba/io/objects_json.h): written with
// 6 significant digits and read back; every malformed member refused with
// the file and the member's path.
#include "symba/io/objects_json.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace symba {
namespace {

namespace fs = std::filesystem;

std::string WriteTemp(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(testing::TempDir()) / name;
  std::ofstream(path) << text;
  return path.string();
}

MapObjectEstimate Discrete() {
  MapObjectEstimate o;
  o.id = 3;
  o.class_name = "table";
  o.symmetry = SymmetryType::kDiscrete;
  o.t_wo = Eigen::Vector3d(1, 2, 3);
  o.axis_w = Eigen::Vector3d::UnitZ();
  o.angles = {0.0, 1.5};
  o.poses = {Rigid3d(), Rigid3d()};
  o.observations = 7;
  MapObjectCovariance c;
  c.id = 3;
  c.source = MapObjectCovariance::Source::kPrior;
  c.position << 1.23456789e-4, 1e-6, 0, 1e-6, 2e-4, 0, 0, 0, 3e-4;
  c.axis = Eigen::Matrix3d::Zero();
  (*c.axis)(0, 0) = 0.01;
  (*c.axis)(1, 1) = 0.02;
  c.angle_variances = {0.0025, std::nullopt};
  o.covariance = c;
  return o;
}

TEST(ObjectsJson, CovariancesRoundTripWithSixDigits) {
  const std::string path =
      WriteTemp("objects_covariance.json", FormatObjectsJson({Discrete()}));
  std::vector<MapObjectEstimate> read;
  const Status status = ReadObjectsJson(path, &read);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(read.size(), 1u);
  ASSERT_TRUE(read[0].covariance.has_value());
  const MapObjectCovariance& c = *read[0].covariance;
  EXPECT_EQ(c.id, 3);
  EXPECT_EQ(c.source, MapObjectCovariance::Source::kPrior);
  EXPECT_EQ(c.position(0, 0), 1.23457e-4);
  EXPECT_EQ(c.position(1, 0), 1e-6);
  EXPECT_EQ(c.position(2, 2), 3e-4);
  ASSERT_TRUE(c.axis.has_value());
  EXPECT_EQ((*c.axis)(1, 1), 0.02);
  EXPECT_FALSE(c.rotation.has_value());
  ASSERT_EQ(c.angle_variances.size(), 2u);
  EXPECT_EQ(c.angle_variances[0], 0.0025);
  EXPECT_FALSE(c.angle_variances[1].has_value());
  // Writing what was read gives the same text.
  EXPECT_EQ(FormatObjectsJson(read), FormatObjectsJson({Discrete()}));
}

// With the noise a replay used (after the objects, as in summary.json):
// the objects read back as without it, and the noise is in the text.
TEST(ObjectsJson, TheNoiseFollowsTheObjectsAndTheReaderIgnoresIt) {
  ClassNoiseEstimate box;
  box.class_name = "box";
  box.sigma_t = 0.25;
  MotionNoiseReport motion;
  motion.odometry_steps = 3;
  motion.odometry_sigma_t = 0.005;
  const std::string text = FormatObjectsJson({Discrete()}, {box}, motion);
  for (const char* member : {"\"noise\": [",
                             "\"class\": \"box\"",
                             "\"sigma_t\": 0.25",
                             "\"motion\": {",
                             "\"steps\": 3"}) {
    EXPECT_NE(text.find(member), std::string::npos) << member << "\n" << text;
  }
  EXPECT_LT(text.find("\"objects\""), text.find("\"noise\""));
  std::vector<MapObjectEstimate> read;
  const Status status =
      ReadObjectsJson(WriteTemp("objects_noise.json", text), &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(FormatObjectsJson(read), FormatObjectsJson({Discrete()}));
}

// Every source is written by its name and read back as itself.
TEST(ObjectsJson, EveryCovarianceSourceRoundTrips) {
  const std::pair<MapObjectCovariance::Source, const char*> sources[] = {
      {MapObjectCovariance::Source::kSolve, "\"covariance_source\": \"solve\""},
      {MapObjectCovariance::Source::kPrior, "\"covariance_source\": \"prior\""},
      {MapObjectCovariance::Source::kKeyframeGraph,
       "\"covariance_source\": \"keyframe_graph\""}};
  for (const auto& [source, text] : sources) {
    MapObjectEstimate object = Discrete();
    object.covariance->source = source;
    const std::string written = FormatObjectsJson({object});
    EXPECT_NE(written.find(text), std::string::npos) << written;
    const std::string path = WriteTemp("objects_source.json", written);
    std::vector<MapObjectEstimate> read;
    const Status status = ReadObjectsJson(path, &read);
    ASSERT_TRUE(status.ok()) << status.message();
    ASSERT_EQ(read.size(), 1u);
    ASSERT_TRUE(read[0].covariance.has_value());
    EXPECT_EQ(read[0].covariance->source, source) << text;
  }
}

// A discrete object's angle variances: one per angle, each >= 0 or null.
TEST(ObjectsJson, AngleVariancesMatchTheAngles) {
  const std::string head =
      R"({"objects": [{"id": 0, "class": "table", "symmetry": "discrete", )"
      R"("t": [0, 0, 0], "axis": [0, 0, 1], "angles": [0, 1], )"
      R"("poses": [{"t": [0, 0, 0], "q": [0, 0, 0, 1]}, )"
      R"({"t": [0, 0, 0], "q": [0, 0, 0, 1]}], "observations": 1, )"
      R"("position_covariance": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], )";
  const std::string cases[][2] = {
      {R"("angle_variances": [0.1])",
       "objects[0].angle_variances: expected 2 entries, one per angle"},
      {R"("angle_variances": [0.1, -2])",
       "objects[0].angle_variances[1]: expected a variance (>= 0)"},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string path =
        WriteTemp("objects_angles_" + std::to_string(k++) + ".json",
                  head + c[0] + "}]}\n");
    std::vector<MapObjectEstimate> read;
    const Status status = ReadObjectsJson(path, &read);
    ASSERT_FALSE(status.ok()) << c[0];
    EXPECT_NE(status.message().find(path + ": " + c[1]), std::string::npos)
        << status.message();
  }
  const std::string path =
      WriteTemp("objects_angles_ok.json",
                head + R"("angle_variances": [0.1, null]}]})" + "\n");
  std::vector<MapObjectEstimate> read;
  const Status status = ReadObjectsJson(path, &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read[0].covariance->angle_variances[0], 0.1);
  EXPECT_FALSE(read[0].covariance->angle_variances[1].has_value());
}

TEST(ObjectsJson, AnObjectWithoutCovarianceHasNone) {
  MapObjectEstimate o = Discrete();
  o.covariance.reset();
  const std::string path =
      WriteTemp("objects_plain.json", FormatObjectsJson({o}));
  std::vector<MapObjectEstimate> read;
  ASSERT_TRUE(ReadObjectsJson(path, &read).ok());
  EXPECT_FALSE(read[0].covariance.has_value());
}

// Each malformed covariance member, spliced into a valid object.
TEST(ObjectsJson, MalformedCovariancesAreRefusedWithTheirPath) {
  const std::string head =
      R"({"objects": [{"id": 0, "class": "box", "symmetry": "asymmetric", )"
      R"("t": [0, 0, 0], "poses": [{"t": [0, 0, 0], "q": [0, 0, 0, 1]}], )"
      R"("observations": 1, )";
  const std::string identity = R"([[1, 0, 0], [0, 1, 0], [0, 0, 1]])";
  const struct {
    std::string members;
    std::string message;
  } cases[] = {
      {R"("position_covariance": [[1, 0, 0], [0, 1, 0]])",
       "objects[0].position_covariance: expected 3 rows of 3 numbers"},
      {R"("position_covariance": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])",
       "objects[0].position_covariance: expected a symmetric matrix"},
      {R"("position_covariance": [[-1, 0, 0], [0, 1, 0], [0, 0, 1]])",
       "objects[0].position_covariance: expected a non-negative diagonal"},
      {R"("position_covariance": [[1, 0, 0], [0, "x", 0], [0, 0, 1]])",
       "objects[0].position_covariance[1]"},
      {R"("rotation_covariance": )" + identity,
       "objects[0]: a covariance without \"position_covariance\""},
      {R"("position_covariance": )" + identity +
           R"(, "covariance_source": "guess")",
       "objects[0].covariance_source: expected \"solve\", \"prior\" or "
       "\"keyframe_graph\""},
      {R"("position_covariance": )" + identity + R"(, "axis_covariance": )" +
           identity,
       "objects[0].axis_covariance: only a symmetric object has one"},
      {R"("position_covariance": )" + identity +
           R"(, "angle_variances": [0.1])",
       "objects[0].angle_variances: only a discrete object has them"},
      {R"("position_covariance": [[1e-8, 1e-9, 0], [0, 1e-8, 0], [0, 0, 1e-8]])",
       "objects[0].position_covariance: expected a symmetric matrix"},
  };
  int k = 0;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.members);
    const std::string path =
        WriteTemp("objects_bad_" + std::to_string(k++) + ".json",
                  head + c.members + "}]}\n");
    std::vector<MapObjectEstimate> read;
    const Status status = ReadObjectsJson(path, &read);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find(path + ": " + c.message), std::string::npos)
        << status.message();
  }
}

}  // namespace
}  // namespace symba
