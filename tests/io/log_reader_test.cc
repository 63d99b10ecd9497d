// Tests of the log format v1 reader and writer (docs/log-format.md): a round
// trip of every feature, the documented example, the malformed corpus in
// tests/data/malformed/ with each exact message, and a long log.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "symba/io/log_format.h"

namespace symba {
namespace {

const std::string kDataDir = SYMBA_TEST_DATA_DIR;

std::string TempPath(const std::string& name) {
  return testing::TempDir() + "symba_io_test_" + name;
}

// Reads a whole log; returns the first error (or OK).
Status ReadAll(std::unique_ptr<LogReader> reader,
               std::vector<KeyframeInput>* keyframes) {
  while (true) {
    KeyframeInput keyframe;
    bool end = false;
    Status status = reader->Next(&keyframe, &end);
    if (!status.ok() || end) return status;
    keyframes->push_back(keyframe);
  }
}

Status ReadFile(const std::string& path,
                LogHeader* header,
                std::vector<KeyframeInput>* keyframes) {
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::Open(path, &reader);
  if (!status.ok()) return status;
  *header = reader->header();
  return ReadAll(std::move(reader), keyframes);
}

Status ReadText(const std::string& text,
                LogHeader* header,
                std::vector<KeyframeInput>* keyframes) {
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::OpenStream(
      std::make_unique<std::istringstream>(text), "text.jsonl", &reader);
  if (!status.ok()) return status;
  *header = reader->header();
  return ReadAll(std::move(reader), keyframes);
}

// Bitwise equality of doubles: also tells -0.0 from 0.0.
void ExpectSame(double expected, double actual, const std::string& what) {
  EXPECT_EQ(expected, actual) << what;
  EXPECT_EQ(std::signbit(expected), std::signbit(actual)) << what;
}

void ExpectSamePose(const Rigid3d& expected,
                    const Rigid3d& actual,
                    const std::string& what) {
  for (int k = 0; k < 3; ++k) {
    ExpectSame(expected.t[k], actual.t[k], what + ".t");
  }
  for (int k = 0; k < 4; ++k) {
    ExpectSame(expected.q.coeffs()[k], actual.q.coeffs()[k], what + ".q");
  }
}

void ExpectSameKeyframe(const KeyframeInput& expected,
                        const KeyframeInput& actual) {
  const std::string where = "keyframe " + std::to_string(expected.id);
  EXPECT_EQ(expected.id, actual.id);
  ExpectSame(expected.timestamp, actual.timestamp, where + " t");
  ASSERT_EQ(expected.T_wc.has_value(), actual.T_wc.has_value()) << where;
  if (expected.T_wc) ExpectSamePose(*expected.T_wc, *actual.T_wc, where);
  ASSERT_EQ(expected.odometry.has_value(), actual.odometry.has_value());
  if (expected.odometry) {
    ExpectSamePose(expected.odometry->T_prev_cur,
                   actual.odometry->T_prev_cur,
                   where + " odometry");
    ExpectSame(expected.odometry->sigma_t, actual.odometry->sigma_t, where);
    ExpectSame(expected.odometry->sigma_r, actual.odometry->sigma_r, where);
  }
  ASSERT_EQ(expected.detections.size(), actual.detections.size()) << where;
  for (std::size_t d = 0; d < expected.detections.size(); ++d) {
    const DetectionInput& e = expected.detections[d];
    const DetectionInput& a = actual.detections[d];
    const std::string at = where + " detection " + std::to_string(d);
    EXPECT_EQ(e.id, a.id) << at;
    EXPECT_EQ(e.class_name, a.class_name) << at;
    ExpectSame(e.score, a.score, at + " score");
    ASSERT_EQ(e.sigma_t.has_value(), a.sigma_t.has_value()) << at;
    if (e.sigma_t) ExpectSame(*e.sigma_t, *a.sigma_t, at + " sigma_t");
    ASSERT_EQ(e.sigma_r.has_value(), a.sigma_r.has_value()) << at;
    if (e.sigma_r) ExpectSame(*e.sigma_r, *a.sigma_r, at + " sigma_r");
    ASSERT_EQ(e.hypotheses.size(), a.hypotheses.size()) << at;
    for (std::size_t h = 0; h < e.hypotheses.size(); ++h) {
      ExpectSamePose(e.hypotheses[h].T_co, a.hypotheses[h].T_co, at);
      ExpectSame(e.hypotheses[h].weight, a.hypotheses[h].weight, at + " w");
    }
  }
  ASSERT_EQ(expected.points.size(), actual.points.size()) << where;
  for (std::size_t p = 0; p < expected.points.size(); ++p) {
    const PointObservation& e = expected.points[p];
    const PointObservation& a = actual.points[p];
    EXPECT_EQ(e.id, a.id) << where;
    ExpectSame(e.uv.x(), a.uv.x(), where + " u");
    ExpectSame(e.uv.y(), a.uv.y(), where + " v");
    ASSERT_EQ(e.depth.has_value(), a.depth.has_value()) << where;
    if (e.depth) ExpectSame(*e.depth, *a.depth, where + " depth");
  }
  ASSERT_EQ(expected.loop_closures.size(), actual.loop_closures.size())
      << where;
  for (std::size_t c = 0; c < expected.loop_closures.size(); ++c) {
    const LoopClosureInput& e = expected.loop_closures[c];
    const LoopClosureInput& a = actual.loop_closures[c];
    EXPECT_EQ(e.keyframe, a.keyframe) << where;
    ExpectSamePose(e.T, a.T, where + " loop closure");
    ExpectSame(e.sigma_t, a.sigma_t, where + " loop sigma_t");
    ExpectSame(e.sigma_r, a.sigma_r, where + " loop sigma_r");
  }
}

Rigid3d RandomPose(std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  q.normalize();
  const Eigen::Vector3d t(normal(*rng), normal(*rng), normal(*rng));
  return Rigid3d(q, 3.0 * t);
}

LogHeader FullHeader() {
  LogHeader header;
  header.camera = PinholeIntrinsics{525.0, 524.5, 319.5, 239.25};
  ClassPrior table;
  table.symmetry = SymmetryType::kDiscrete;
  table.order = 4;
  table.axis_o = Eigen::Vector3d(0.0, 0.0, 1.0);
  header.classes["table"] = table;
  ClassPrior box;  // discrete, axis unknown
  box.symmetry = SymmetryType::kDiscrete;
  box.order = 2;
  header.classes["box"] = box;
  ClassPrior bowl;
  bowl.symmetry = SymmetryType::kContinuous;
  bowl.axis_o = Eigen::Vector3d(0.1, -0.2, 0.97);  // need not be unit
  header.classes["bowl"] = bowl;
  ClassPrior can;  // continuous, axis unknown
  can.symmetry = SymmetryType::kContinuous;
  header.classes["can \"tall\" \xc3\xa9"] = can;
  header.classes["mug"] = ClassPrior();  // asymmetric
  return header;
}

// Keyframes with every feature; ids of detections are what the reader
// returns (defaults filled in).
std::vector<KeyframeInput> FullKeyframes() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<KeyframeInput> keyframes;

  KeyframeInput first;
  first.id = -3;
  first.timestamp = 1700000000.123456789;
  first.T_wc = RandomPose(&rng);
  first.T_wc->t.x() = -0.0;
  for (int d = 0; d < 3; ++d) {
    DetectionInput detection;
    detection.id = d == 1 ? "" : "det-" + std::to_string(d);
    detection.class_name = d == 2 ? "can \"tall\" \xc3\xa9" : "table";
    for (int h = 0; h < 5; ++h) {
      PoseHypothesis hypothesis;
      hypothesis.T_co = RandomPose(&rng);
      hypothesis.weight = h == 0 ? 1.0 : uniform(rng) + 1e-3;
      detection.hypotheses.push_back(hypothesis);
    }
    if (d == 0) {
      detection.score = 0.1 + 0.2;  // not short in decimal
      detection.sigma_t = 0.05;
      detection.sigma_r = 1e-300;
    }
    if (d == 2) detection.sigma_r = 0.08;
    first.detections.push_back(detection);
  }
  first.detections[1].id = "-3/1";  // the default id
  for (int p = 0; p < 4; ++p) {
    PointObservation point;
    point.id = p == 3 ? std::numeric_limits<int64_t>::max() : 4000 + p;
    point.uv = Eigen::Vector2d(640.0 * uniform(rng), 480.0 * uniform(rng));
    if (p % 2 == 0) point.depth = 0.5 + 4.0 * uniform(rng);
    first.points.push_back(point);
  }
  keyframes.push_back(first);

  KeyframeInput odometry_only;
  odometry_only.id = 0;
  odometry_only.timestamp = first.timestamp;  // equal times are allowed
  odometry_only.odometry = Odometry{RandomPose(&rng), 0.01, 0.005};
  keyframes.push_back(odometry_only);

  KeyframeInput both;
  both.id = 17;
  both.timestamp = 1700000001.5;
  both.T_wc = RandomPose(&rng);
  both.odometry = Odometry{RandomPose(&rng), 1.0 / 3.0, 2e-9};
  DetectionInput one;
  one.id = "x";
  one.class_name = "mug";
  one.hypotheses.push_back({RandomPose(&rng), 0.25});
  one.score = 0.0;
  both.detections.push_back(one);
  // A loop closure to the first keyframe of the list.
  both.loop_closures.push_back(
      LoopClosureInput{keyframes.front().id, RandomPose(&rng), 0.03, 1e-4});
  keyframes.push_back(both);

  KeyframeInput pose_only;
  pose_only.id = std::numeric_limits<int64_t>::max();
  pose_only.timestamp = 1e300;
  pose_only.T_wc = Rigid3d();
  keyframes.push_back(pose_only);
  return keyframes;
}

TEST(LogRoundTrip, EveryFeatureReadsBackExactly) {
  const std::string path = TempPath("round_trip.jsonl");
  const LogHeader header = FullHeader();
  const std::vector<KeyframeInput> keyframes = FullKeyframes();
  {
    std::unique_ptr<LogWriter> writer;
    ASSERT_TRUE(LogWriter::Open(path, header, &writer).ok());
    for (const KeyframeInput& keyframe : keyframes) {
      const Status status = writer->Write(keyframe);
      ASSERT_TRUE(status.ok()) << status.message();
    }
    ASSERT_TRUE(writer->Close().ok());
  }
  LogHeader read_header;
  std::vector<KeyframeInput> read;
  const Status status = ReadFile(path, &read_header, &read);
  ASSERT_TRUE(status.ok()) << status.message();

  EXPECT_EQ(read_header.version, 1);
  ASSERT_TRUE(read_header.camera.has_value());
  EXPECT_EQ(read_header.camera->fx, header.camera->fx);
  EXPECT_EQ(read_header.camera->fy, header.camera->fy);
  EXPECT_EQ(read_header.camera->cx, header.camera->cx);
  EXPECT_EQ(read_header.camera->cy, header.camera->cy);
  ASSERT_EQ(read_header.classes.size(), header.classes.size());
  for (const auto& [name, prior] : header.classes) {
    ASSERT_EQ(read_header.classes.count(name), 1u) << name;
    const ClassPrior& read_prior = read_header.classes.at(name);
    EXPECT_EQ(read_prior.symmetry, prior.symmetry) << name;
    EXPECT_EQ(read_prior.order, prior.order) << name;
    EXPECT_EQ(read_prior.axis_o, prior.axis_o) << name;
  }
  ASSERT_EQ(read.size(), keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    ExpectSameKeyframe(keyframes[k], read[k]);
  }
}

TEST(LogRoundTrip, WriterPrintsShortestExactNumbers) {
  std::ostringstream text;
  {
    std::unique_ptr<LogWriter> writer;
    ASSERT_TRUE(LogWriter::OpenStream(&text, "mem", LogHeader(), &writer).ok());
    KeyframeInput keyframe;
    keyframe.timestamp = 0.1;
    keyframe.T_wc = Rigid3d();
    keyframe.T_wc->t = Eigen::Vector3d(-0.0, 1.0, 0.1 + 0.2);
    ASSERT_TRUE(writer->Write(keyframe).ok());
    ASSERT_TRUE(writer->Close().ok());
  }
  EXPECT_EQ(text.str(),
            "{\"format\":\"symba-log\",\"version\":1}\n"
            "{\"keyframe\":0,\"t\":0.1,\"T_wc\":{\"t\":[-0.0,1.0,"
            "0.30000000000000004],\"q\":[0.0,0.0,0.0,1.0]}}\n");
}

TEST(LogReader, ReadsTheDocumentedExample) {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status =
      ReadFile(kDataDir + "/example.jsonl", &header, &keyframes);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(header.camera.has_value());
  EXPECT_EQ(header.camera->fx, 525.0);
  EXPECT_EQ(header.camera->cy, 239.5);
  ASSERT_EQ(header.classes.size(), 3u);
  EXPECT_EQ(header.classes.at("table").symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(header.classes.at("table").order, 2);
  EXPECT_EQ(header.classes.at("bowl").symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(header.classes.at("bowl").axis_o, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(header.classes.at("mug").symmetry, SymmetryType::kAsymmetric);
  EXPECT_TRUE(header.classes.at("mug").axis_o.isZero());

  ASSERT_EQ(keyframes.size(), 3u);
  const KeyframeInput& k0 = keyframes[0];
  EXPECT_EQ(k0.id, 0);
  ASSERT_TRUE(k0.T_wc.has_value());
  EXPECT_EQ(k0.T_wc->t, Eigen::Vector3d(0.0, 0.0, 1.2));
  EXPECT_FALSE(k0.odometry.has_value());
  ASSERT_EQ(k0.detections.size(), 1u);
  EXPECT_EQ(k0.detections[0].id, "0/0");
  EXPECT_EQ(k0.detections[0].class_name, "table");
  EXPECT_EQ(k0.detections[0].score, 0.92);
  EXPECT_FALSE(k0.detections[0].sigma_t.has_value());
  ASSERT_EQ(k0.detections[0].hypotheses.size(), 2u);
  EXPECT_EQ(k0.detections[0].hypotheses[1].weight, 0.4);
  EXPECT_EQ(k0.detections[0].hypotheses[1].T_co.q.coeffs(),
            Eigen::Vector4d(0, 0, 1, 0));
  ASSERT_EQ(k0.points.size(), 2u);
  EXPECT_EQ(k0.points[0].depth, 2.31);
  EXPECT_FALSE(k0.points[1].depth.has_value());

  const KeyframeInput& k1 = keyframes[1];
  EXPECT_EQ(k1.id, 1);
  EXPECT_FALSE(k1.T_wc.has_value());
  ASSERT_TRUE(k1.odometry.has_value());
  EXPECT_EQ(k1.odometry->sigma_r, 0.005);
  // [0, 0, 0.01, 0.99995] has norm 1 + 1.25e-9: normalised.
  EXPECT_NEAR(k1.odometry->T_prev_cur.q.norm(), 1.0, 1e-15);
  EXPECT_NEAR(k1.odometry->T_prev_cur.q.z(), 0.01, 1e-8);
  ASSERT_EQ(k1.detections.size(), 1u);
  EXPECT_EQ(k1.detections[0].id, "bowl-a");
  EXPECT_EQ(k1.detections[0].sigma_t, 0.05);
  EXPECT_EQ(k1.detections[0].sigma_r, 0.08);
  EXPECT_EQ(k1.detections[0].hypotheses[0].T_co.q.coeffs(),
            Eigen::Vector4d(0, 0, 0, 1));
  EXPECT_TRUE(k1.points.empty());

  const KeyframeInput& k2 = keyframes[2];
  EXPECT_EQ(k2.id, 5);
  ASSERT_TRUE(k2.T_wc.has_value());
  ASSERT_TRUE(k2.odometry.has_value());
  // R = Rz(90 deg) read back as a quaternion.
  const Eigen::Quaterniond expected(
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  EXPECT_LT(k2.T_wc->q.angularDistance(expected), 1e-15);
  EXPECT_NEAR(k2.T_wc->q.norm(), 1.0, 1e-15);
  ASSERT_EQ(k2.points.size(), 1u);
  EXPECT_EQ(k2.points[0].uv, Eigen::Vector2d(320.0, 210.0));
}

std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// docs/log-format.md shows tests/data/example.jsonl in its ```jsonl block.
TEST(LogReader, DocumentedExampleIsTheTestFile) {
  const std::string doc = FileText(kDataDir + "/../../docs/log-format.md");
  const std::string open = "```jsonl\n";
  const std::size_t begin = doc.find(open);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```\n", begin + open.size());
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(doc.substr(begin + open.size(), end - begin - open.size()),
            FileText(kDataDir + "/example.jsonl"));
}

TEST(LogReader, ProjectsNearlyOrthonormalRotationMatrices) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())
          .toRotationMatrix();
  Eigen::Matrix3d noisy = R;
  noisy(0, 1) += 2e-4;
  noisy(2, 0) -= 3e-4;
  std::ostringstream line;
  line.precision(17);
  line << "{\"format\": \"symba-log\", \"version\": 1}\n"
       << "{\"keyframe\": 0, \"t\": 0, \"T_wc\": {\"t\": [1, 2, 3], \"R\": [";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) line << (r + c > 0 ? ", " : "") << noisy(r, c);
  }
  line << "]}}\n";
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ReadText(line.str(), &header, &keyframes);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(keyframes.size(), 1u);
  const Eigen::Quaterniond q = keyframes[0].T_wc->q;
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_LT(q.angularDistance(Eigen::Quaterniond(R)), 5e-4);
}

TEST(LogReader, NormalisesNearlyUnitQuaternions) {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ReadText(
      "{\"format\": \"symba-log\", \"version\": 1}\n"
      "{\"keyframe\": 0, \"t\": 0, \"T_wc\": {\"t\": [0, 0, 0], "
      "\"q\": [0, 0, 0, 1.0009]}}\n",
      &header,
      &keyframes);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(keyframes[0].T_wc->q.coeffs(), Eigen::Vector4d(0, 0, 0, 1));
}

TEST(LogReader, HeaderOnlyIsAnEmptyLog) {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ReadText(
      "{\"format\": \"symba-log\", \"version\": 1}", &header, &keyframes);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(keyframes.empty());
  EXPECT_FALSE(header.camera.has_value());
  EXPECT_TRUE(header.classes.empty());
}

TEST(LogReader, SkipsBlankLinesAndAcceptsCrLfAndEscapes) {
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  std::unique_ptr<LogReader> reader;
  ASSERT_TRUE(
      LogReader::OpenStream(
          std::make_unique<std::istringstream>(
              "{\"format\": \"symba-log\", \"version\": 1.0}\r\n"
              "\r\n  \t\n"
              "{\"keyframe\": 2e0, \"t\": 0, \"T_wc\": {\"t\": [0, 0, 0], "
              "\"q\": [0, 0, 0, 1]}, \"detections\": [{\"id\": \"\", "
              "\"class\": \"caf\\u00e9 \\\"x\\\"\", \"hypotheses\": "
              "[{\"t\": [0, 0, 1], \"q\": [0, 0, 0, 1]}]}], \"t\": 3}\r\n"
              "\n"),
          "crlf.jsonl",
          &reader)
          .ok());
  KeyframeInput keyframe;
  bool end = true;
  ASSERT_TRUE(reader->Next(&keyframe, &end).ok());
  ASSERT_FALSE(end);
  EXPECT_EQ(reader->line(), 4);
  EXPECT_EQ(keyframe.id, 2);
  EXPECT_EQ(keyframe.timestamp, 3.0);  // a repeated key: the last counts
  ASSERT_EQ(keyframe.detections.size(), 1u);
  EXPECT_EQ(keyframe.detections[0].id, "2/0");  // empty id: the default
  EXPECT_EQ(keyframe.detections[0].class_name, "caf\xc3\xa9 \"x\"");
  ASSERT_TRUE(reader->Next(&keyframe, &end).ok());
  EXPECT_TRUE(end);
  ASSERT_TRUE(reader->Next(&keyframe, &end).ok());
  EXPECT_TRUE(end);
}

TEST(LogReader, MissingFileCannotBeOpened) {
  std::unique_ptr<LogReader> reader;
  const std::string path = kDataDir + "/no_such_file.jsonl";
  const Status status = LogReader::Open(path, &reader);
  EXPECT_EQ(status.message(), path + ": cannot open");
  EXPECT_EQ(reader, nullptr);
  // A directory opens as a stream on Linux; it is named as what it is.
  EXPECT_EQ(LogReader::Open(kDataDir, &reader).message(),
            kDataDir + ": is a directory");
}

TEST(LogReader, ErrorsAreSticky) {
  std::unique_ptr<LogReader> reader;
  ASSERT_TRUE(LogReader::OpenStream(
                  std::make_unique<std::istringstream>(
                      "{\"format\": \"symba-log\", \"version\": 1}\n"
                      "{\"keyframe\": 0}\n"
                      "{\"keyframe\": 1, \"t\": 0, \"T_wc\": {\"t\": [0, 0, "
                      "0], \"q\": [0, 0, 0, 1]}}\n"),
                  "sticky",
                  &reader)
                  .ok());
  KeyframeInput keyframe;
  bool end = false;
  const Status first = reader->Next(&keyframe, &end);
  EXPECT_EQ(first.message(), "sticky:2: t: missing (the timestamp in seconds)");
  const Status second = reader->Next(&keyframe, &end);
  EXPECT_EQ(second.message(), first.message());
  EXPECT_FALSE(end);
}

// One file per check; the expected message names the file as it was opened.
struct MalformedCase {
  const char* file;
  const char* message;  // after "<path>:"
};

class MalformedLog : public testing::TestWithParam<MalformedCase> {};

TEST_P(MalformedLog, IsRejectedWithItsMessage) {
  const std::string path =
      kDataDir + "/malformed/" + GetParam().file + ".jsonl";
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  const Status status = ReadFile(path, &header, &keyframes);
  ASSERT_FALSE(status.ok()) << path << " was accepted";
  EXPECT_EQ(status.message(), path + ":" + GetParam().message);
}

// clang-format off
const MalformedCase kMalformedCases[] = {
    {"detection_class_number",
     "2: detections[0].class: expected a string, got 7"},
    {"detection_empty_hypotheses",
     "2: detections[1].hypotheses: empty; a detection needs at least one hypothesis"},
    {"detection_id_number",
     "2: detections[0].id: expected a string, got 3"},
    {"detection_missing_class",
     "2: detections[0].class: missing (the object class, a string)"},
    {"detection_missing_hypotheses",
     "2: detections[0].hypotheses: missing (at least one pose T_co)"},
    {"detection_sigma_zero",
     "2: detections[0].sigma_r: must be positive, got 0"},
    {"detection_weight_negative",
     "2: detections[0].hypotheses[0].w: must be positive, got -0.5"},
    {"detections_not_array",
     "2: detections: expected an array, got an object"},
    {"empty",
     "1: empty file; line 1 must be the header {\"format\": \"symba-log\", \"version\": 1, ...}"},
    {"first_keyframe_without_T_wc",
     "2: T_wc: missing (the first keyframe needs the camera pose T_wc)"},
    {"header_blank_line_1",
     "1: line 1 is blank; it must be the header {\"format\": \"symba-log\", \"version\": 1, ...}"},
    {"header_camera_fx_zero",
     "1: camera.fx: must be positive, got 0"},
    {"header_camera_missing_fy",
     "1: camera.fy: missing"},
    {"header_class_axis_asymmetric",
     "1: classes.mug.axis: an asymmetric class has no symmetry axis"},
    {"header_class_axis_length",
     "1: classes.table.axis: expected an array of 3 numbers, got 2 elements"},
    {"header_class_axis_zero",
     "1: classes.bowl.axis: must not be the zero vector"},
    {"header_class_axis_norm_overflows",
     "1: classes.bowl.axis: must have a norm in [1e-100, 1e100]"},
    {"header_class_bad_symmetry",
     "1: classes.bowl.symmetry: unknown symmetry \"round\" (expected \"asymmetric\", \"discrete\" or \"continuous\")"},
    {"header_class_discrete_without_order",
     "1: classes.table.order: missing (a discrete class needs its symmetry order, an integer >= 2)"},
    {"header_bop_not_object",
     "1: bop: expected an object, got an array"},
    {"header_bop_missing_scene_id",
     "1: bop.scene_id: missing (the BOP scene id, an integer >= 0)"},
    {"header_bop_scene_id_negative",
     "1: bop.scene_id: must be a non-negative integer, got -1"},
    {"header_bop_missing_obj_ids",
     "1: bop.obj_ids: missing (the BOP obj_id of each class, {\"<class>\": id, ...})"},
    {"header_bop_obj_id_string",
     "1: bop.obj_ids.table: expected an integer, got the string \"1\""},
    {"header_bop_obj_id_fraction",
     "1: bop.obj_ids.table: expected an integer, got 1.5"},
    {"header_class_order_1",
     "1: classes.table.order: must be an integer from 2 to 1000000, got 1"},
    {"header_class_order_not_discrete",
     "1: classes.bowl.order: only a discrete class has an order"},
    {"header_invalid_json",
     "1: invalid JSON at column 37: syntax error while parsing object - unexpected end of input; expected '}'"},
    {"header_missing_format",
     "1: format: missing (line 1 must be the header {\"format\": \"symba-log\", \"version\": 1, ...})"},
    {"header_missing_version",
     "1: version: missing"},
    {"header_not_object",
     "1: the header must be a JSON object {\"format\": \"symba-log\", \"version\": 1, ...}, got an array"},
    {"header_version_fraction",
     "1: version: expected an integer, got 1.5"},
    {"header_version_future",
     "1: version 2 is not supported (this reader reads version 1)"},
    {"header_version_string",
     "1: version: expected an integer, got the string \"1\""},
    {"header_wrong_format",
     "1: format: expected \"symba-log\", got the string \"symba-lg\""},
    {"keyframe_id_fraction",
     "2: keyframe: expected an integer, got 1.5"},
    {"keyframe_id_not_increasing",
     "3: keyframe: id 3 is not greater than the previous keyframe's id 3 (line 2)"},
    {"keyframe_id_out_of_range",
     "2: keyframe: integer 9223372036854775808 is out of range"},
    {"keyframe_invalid_utf8",
     "2: invalid JSON at column 102: syntax error while parsing value - invalid string: ill-formed UTF-8 byte; last read: '\"caf\\xE9\"'"},
    {"keyframe_missing_id",
     "2: keyframe: missing (the keyframe id, an integer)"},
    {"keyframe_missing_t",
     "2: t: missing (the timestamp in seconds)"},
    {"keyframe_not_object",
     "2: a keyframe must be a JSON object, got an array"},
    {"keyframe_number_overflow",
     "2: invalid JSON at column 22: number 1e400 overflows a double"},
    {"keyframe_t_string",
     "2: t: expected a number, got the string \"0.0\""},
    {"keyframe_time_decreasing",
     "4: t: 0.5 is before the previous keyframe's time 1 (line 2)"},
    {"keyframe_trailing_garbage",
     "2: invalid JSON at column 72: syntax error while parsing value - invalid literal; last read: '1]}} x'; expected end of input"},
    {"keyframe_truncated",
     "2: invalid JSON at column 41: syntax error while parsing value - unexpected end of input; expected '[', '{', or a literal"},
    {"keyframe_without_T_wc_or_odometry",
     "3: neither T_wc nor odometry (every keyframe after the first needs at least one of them)"},
    {"loop_closure_later_keyframe",
     "3: loop_closures[0].keyframe: 2 is not the id of an earlier keyframe of this log"},
    {"loop_closure_missing_keyframe",
     "3: loop_closures[0].keyframe: missing (the id of an earlier keyframe)"},
    {"loop_closure_missing_sigma_t",
     "3: loop_closures[0].sigma_t: missing (in metres)"},
    {"loop_closure_not_object",
     "3: loop_closures[0]: expected an object, got an array"},
    {"loop_closure_missing_T",
     "3: loop_closures[0].T: missing (this keyframe's pose in that one's frame)"},
    {"loop_closure_not_array",
     "3: loop_closures: expected an array, got an object"},
    {"loop_closure_sigma_zero",
     "3: loop_closures[1].sigma_r: must be positive, got 0"},
    {"loop_closure_unknown_keyframe",
     "3: loop_closures[0].keyframe: 7 is not the id of an earlier keyframe of this log"},
    {"odometry_missing_T",
     "3: odometry.T: missing (the pose T_{prev,cur})"},
    {"odometry_missing_sigma",
     "3: odometry.sigma_r: missing (in radians)"},
    {"odometry_sigma_zero",
     "3: odometry.sigma_t: must be positive, got 0"},
    {"point_depth_zero",
     "2: points[0].depth: must be positive, got 0"},
    {"point_id_fraction",
     "2: points[0].id: expected an integer, got 3.5"},
    {"point_missing_id",
     "2: points[0].id: missing (the map point id, an integer)"},
    {"point_missing_uv",
     "2: points[1].uv: missing (pixel coordinates [u, v])"},
    {"points_without_camera",
     "2: points: the header (line 1) has no camera; point observations need its intrinsics"},
    {"pose_R_length",
     "2: T_wc.R: expected an array of 9 numbers, got 8 elements"},
    {"pose_missing_t",
     "2: T_wc.t: missing (the translation [x, y, z])"},
    {"pose_not_object",
     "2: T_wc: expected an object, got an array"},
    {"pose_q_string_element",
     "2: T_wc.q[3]: expected a number, got the string \"1\""},
    {"pose_t_length",
     "2: T_wc.t: expected an array of 3 numbers, got 2 elements"},
    {"pose_with_q_and_R",
     "2: T_wc: has both q and R; give one rotation"},
    {"pose_without_rotation",
     "2: T_wc: has neither q [qx, qy, qz, qw] nor R (row-major 3 x 3); one of them is required"},
    {"quaternion_not_unit",
     "2: detections[0].hypotheses[2].q: quaternion norm 1.2 is not within 1e-3 of 1"},
    {"rotation_not_orthonormal",
     "2: T_wc.R: not a rotation: R^T R differs from the identity by 0.1 (more than 1e-3)"},
    {"rotation_reflection",
     "2: T_wc.R: not a rotation: det(R) = -1 is not positive"},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Corpus,
                         MalformedLog,
                         testing::ValuesIn(kMalformedCases),
                         [](const testing::TestParamInfo<MalformedCase>& info) {
                           return std::string(info.param.file);
                         });

TEST(MalformedCorpus, EveryFileHasACase) {
  // The corpus and the table must not drift apart: count the files.
  int files = 0;
  for (const MalformedCase& c : kMalformedCases) {
    std::ifstream in(kDataDir + "/malformed/" + c.file + ".jsonl");
    files += in.is_open() ? 1 : 0;
  }
  EXPECT_EQ(files, static_cast<int>(std::size(kMalformedCases)));
  EXPECT_GE(std::size(kMalformedCases), 25u);
}

TEST(LogWriter, RefusesWhatTheReaderWouldReject) {
  std::ostringstream text;
  std::unique_ptr<LogWriter> writer;
  ASSERT_TRUE(LogWriter::OpenStream(&text, "out", LogHeader(), &writer).ok());
  KeyframeInput keyframe;
  keyframe.id = 4;
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: T_wc: missing (the first keyframe needs T_wc)");
  keyframe.T_wc = Rigid3d();
  keyframe.T_wc->q.coeffs() *= 1.5;
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: T_wc.q: quaternion norm 1.5 is not within 1e-3 "
            "of 1");
  keyframe.T_wc = Rigid3d();
  keyframe.points.emplace_back();
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: points: the header has no camera");
  keyframe.points.clear();
  keyframe.detections.emplace_back();
  keyframe.detections[0].class_name = "mug";
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: detections[0].hypotheses: empty; a detection "
            "needs at least one hypothesis");
  keyframe.detections[0].hypotheses.push_back({Rigid3d(), 0.0});
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: detections[0].hypotheses[0].w: must be "
            "positive, got 0");
  keyframe.detections[0].hypotheses[0].weight = 1.0;
  keyframe.detections[0].class_name = "\xff";
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: detections[0].class: not UTF-8");
  keyframe.detections[0].class_name = "mug";
  ASSERT_TRUE(writer->Write(keyframe).ok());
  keyframe.T_wc.reset();
  keyframe.timestamp = std::nan("");
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 4: keyframe: id is not greater than the previous "
            "id 4");
  keyframe.id = 5;
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 5: t: non-finite number");
  keyframe.timestamp = 0.0;
  EXPECT_EQ(writer->Write(keyframe).message(),
            "out: keyframe 5: T_wc: neither T_wc nor odometry");
  ASSERT_TRUE(writer->Close().ok());
  // Only the header and the one good keyframe were written.
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  ASSERT_TRUE(ReadText(text.str(), &header, &keyframes).ok());
  EXPECT_EQ(keyframes.size(), 1u);
}

TEST(LogWriter, RefusesAnInvalidHeader) {
  std::ostringstream text;
  std::unique_ptr<LogWriter> writer;
  LogHeader header;
  header.classes["table"].symmetry = SymmetryType::kDiscrete;
  EXPECT_EQ(LogWriter::OpenStream(&text, "out", header, &writer).message(),
            "out: header: classes.table.order: must be an integer from 2 to "
            "1000000, got 0");
  EXPECT_EQ(writer, nullptr);
  header.classes["table"].order = 2;
  header.classes["table"].axis_o = Eigen::Vector3d(1e300, 1e300, 0.0);
  EXPECT_EQ(LogWriter::OpenStream(&text, "out", header, &writer).message(),
            "out: header: classes.table.axis: must have a norm in [1e-100, "
            "1e100]");
  header.classes.clear();
  header.camera = PinholeIntrinsics{-1.0, 1.0, 0.0, 0.0};
  EXPECT_EQ(LogWriter::OpenStream(&text, "out", header, &writer).message(),
            "out: header: camera.fx: must be positive, got -1");
}

// The optional "bop" key (written by symba import bop): its exact text,
// read back equal; absent, it stays absent.
TEST(LogHeaderBop, WritesItsTextAndReadsBackEqual) {
  LogHeader header;
  header.bop = BopSource{7, {{"table", 1}, {"mug", 2}}};
  std::ostringstream text;
  std::unique_ptr<LogWriter> writer;
  ASSERT_TRUE(LogWriter::OpenStream(&text, "out", header, &writer).ok());
  ASSERT_TRUE(writer->Close().ok());
  EXPECT_EQ(text.str(),
            "{\"format\":\"symba-log\",\"version\":1,\"bop\":{\"scene_id\":7,"
            "\"obj_ids\":{\"mug\":2,\"table\":1}}}\n");
  std::unique_ptr<LogReader> reader;
  const Status status = LogReader::OpenStream(
      std::make_unique<std::istringstream>(text.str()), "in", &reader);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(reader->header().bop.has_value());
  EXPECT_EQ(reader->header().bop->scene_id, 7);
  EXPECT_EQ(reader->header().bop->obj_ids,
            (std::map<std::string, int>{{"mug", 2}, {"table", 1}}));

  ASSERT_TRUE(LogReader::OpenStream(
                  std::make_unique<std::istringstream>(
                      "{\"format\": \"symba-log\", \"version\": 1}\n"),
                  "in",
                  &reader)
                  .ok());
  EXPECT_FALSE(reader->header().bop.has_value());
}

TEST(LogHeaderBop, ReaderTakesAnEmptyMapAndTheLastRepeatedKey) {
  std::unique_ptr<LogReader> reader;
  const Status status = LogReader::OpenStream(
      std::make_unique<std::istringstream>(
          "{\"format\": \"symba-log\", \"version\": 1, \"bop\": "
          "{\"scene_id\": 3.0, \"obj_ids\": {\"a\": 1, \"a\": 4}}}\n"),
      "in",
      &reader);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(reader->header().bop->scene_id, 3);
  EXPECT_EQ(reader->header().bop->obj_ids,
            (std::map<std::string, int>{{"a", 4}}));
}

TEST(LogHeaderBop, WriterRefusesNegativeIdsAndBadNames) {
  std::ostringstream text;
  std::unique_ptr<LogWriter> writer;
  LogHeader header;
  header.bop = BopSource{-1, {}};
  EXPECT_EQ(
      LogWriter::OpenStream(&text, "out", header, &writer).message(),
      "out: header: bop.scene_id: must be a non-negative integer, got -1");
  header.bop = BopSource{0, {{"table", -2}}};
  EXPECT_EQ(LogWriter::OpenStream(&text, "out", header, &writer).message(),
            "out: header: bop.obj_ids.table: must be a non-negative integer, "
            "got -2");
  header.bop = BopSource{0, {{"\xff", 1}}};
  EXPECT_EQ(LogWriter::OpenStream(&text, "out", header, &writer).message(),
            "out: header: bop.obj_ids.\xff: class name is not UTF-8");
  EXPECT_EQ(writer, nullptr);
}

// 20000 keyframes through the streaming reader; the reader keeps one line.
TEST(LogReader, StreamsALongLog) {
  const std::string path = TempPath("long.jsonl");
  LogHeader header;
  header.camera = PinholeIntrinsics{500.0, 500.0, 320.0, 240.0};
  constexpr int kKeyframes = 20000;
  {
    std::unique_ptr<LogWriter> writer;
    ASSERT_TRUE(LogWriter::Open(path, header, &writer).ok());
    std::mt19937 rng(3);
    KeyframeInput keyframe;
    keyframe.T_wc = Rigid3d();
    DetectionInput detection;
    detection.class_name = "mug";
    detection.hypotheses.resize(3);
    keyframe.detections.push_back(detection);
    keyframe.points.resize(5);
    for (int k = 0; k < kKeyframes; ++k) {
      keyframe.id = 10 * k;
      keyframe.timestamp = 0.1 * k;
      keyframe.T_wc = RandomPose(&rng);
      keyframe.detections[0].hypotheses[k % 3].T_co = RandomPose(&rng);
      keyframe.points[k % 5].id = k;
      ASSERT_TRUE(writer->Write(keyframe).ok());
    }
    ASSERT_TRUE(writer->Close().ok());
  }
  std::unique_ptr<LogReader> reader;
  ASSERT_TRUE(LogReader::Open(path, &reader).ok());
  KeyframeInput keyframe;
  bool end = false;
  int count = 0;
  while (true) {
    const Status status = reader->Next(&keyframe, &end);
    ASSERT_TRUE(status.ok()) << status.message();
    if (end) break;
    ASSERT_EQ(keyframe.id, 10 * count);
    ASSERT_EQ(reader->line(), count + 2);
    ++count;
  }
  EXPECT_EQ(count, kKeyframes);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace symba
