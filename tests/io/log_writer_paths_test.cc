// The log writer names a refused value by its path (src/io/log_writer.cc
// builds the path only for the message): the nested paths of detections,
// hypotheses, points and loop closures, beyond those log_reader_test
// checks.
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "symba/io/log_format.h"

namespace symba {
namespace {

class LogWriterPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    LogHeader header;
    header.camera = PinholeIntrinsics{600.0, 600.0, 320.0, 240.0};
    ASSERT_TRUE(LogWriter::OpenStream(&text_, "out", header, &writer_).ok());
    keyframe_.id = 2;
    keyframe_.T_wc = Rigid3d();
    for (int d = 0; d < 2; ++d) {
      DetectionInput detection;
      detection.class_name = "mug";
      for (int h = 0; h < 3; ++h)
        detection.hypotheses.push_back({Rigid3d(), 1.0});
      keyframe_.detections.push_back(detection);
    }
    keyframe_.points.resize(2);
  }

  std::string Refusal() { return writer_->Write(keyframe_).message(); }

  std::ostringstream text_;
  std::unique_ptr<LogWriter> writer_;
  KeyframeInput keyframe_;
};

TEST_F(LogWriterPaths, NamesNestedValues) {
  keyframe_.detections[1].hypotheses[2].T_co.q.coeffs() *= 2.0;
  EXPECT_EQ(Refusal(),
            "out: keyframe 2: detections[1].hypotheses[2].q: quaternion norm 2 "
            "is not within 1e-3 of 1");
  keyframe_.detections[1].hypotheses[2].T_co = Rigid3d();
  keyframe_.detections[1].hypotheses[1].T_co.t.x() =
      std::numeric_limits<double>::infinity();
  EXPECT_EQ(
      Refusal(),
      "out: keyframe 2: detections[1].hypotheses[1].t: non-finite number");
  keyframe_.detections[1].hypotheses[1].T_co = Rigid3d();
  keyframe_.detections[1].sigma_r = -0.5;
  EXPECT_EQ(Refusal(),
            "out: keyframe 2: detections[1].sigma_r: must be positive, got "
            "-0.5");
  keyframe_.detections[1].sigma_r.reset();
  keyframe_.points[1].depth = 0.0;
  EXPECT_EQ(Refusal(),
            "out: keyframe 2: points[1].depth: must be positive, got 0");
  keyframe_.points[1].depth.reset();
  keyframe_.points[0].uv.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Refusal(), "out: keyframe 2: points[0].uv: non-finite number");
  keyframe_.points[0].uv.y() = 1.0;
  EXPECT_TRUE(writer_->Write(keyframe_).ok());
}

TEST_F(LogWriterPaths, NamesLoopClosures) {
  ASSERT_TRUE(writer_->Write(keyframe_).ok());  // keyframe 2
  keyframe_.id = 3;
  keyframe_.odometry = Odometry{};
  keyframe_.loop_closures.resize(2);
  keyframe_.loop_closures[0].keyframe = 2;
  keyframe_.loop_closures[1].keyframe = 1;
  EXPECT_EQ(Refusal(),
            "out: keyframe 3: loop_closures[1].keyframe: 1 is not the id of an "
            "earlier keyframe of this log");
  keyframe_.loop_closures[1].keyframe = 3;
  EXPECT_EQ(Refusal(),
            "out: keyframe 3: loop_closures[1].keyframe: 3 is not the id of an "
            "earlier keyframe of this log");
  keyframe_.loop_closures[1].keyframe = 2;
  keyframe_.loop_closures[1].T.q.coeffs() *= 2.0;
  EXPECT_EQ(Refusal(),
            "out: keyframe 3: loop_closures[1].T.q: quaternion norm 2 is not "
            "within 1e-3 of 1");
  keyframe_.loop_closures[1].T = Rigid3d();
  keyframe_.loop_closures[0].sigma_t = 0.0;
  EXPECT_EQ(Refusal(),
            "out: keyframe 3: loop_closures[0].sigma_t: must be positive, got "
            "0");
  keyframe_.loop_closures[0].sigma_t = 0.1;
  EXPECT_TRUE(writer_->Write(keyframe_).ok());
  EXPECT_NE(text_.str().find("\"loop_closures\":[{\"keyframe\":2,"),
            std::string::npos);
}

}  // namespace
}  // namespace symba
