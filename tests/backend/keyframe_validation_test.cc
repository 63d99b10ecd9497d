// ValidateKeyframe's ranges (src/backend/keyframe_validation.h): a sigma
// within [kMinNoiseSigma, kMaxNoiseSigma], a translation and a pixel
// coordinate within +-kMaxCoordinate. Values outside used to pass as
// "positive and finite" and abort a replay or make every solve fail.
#include "backend/keyframe_validation.h"

#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "symba/backend/backend_options.h"

namespace symba::internal {
namespace {

using ::testing::HasSubstr;

KeyframeInput WithPointAndDetection(double u, double sigma_t, double t_x) {
  KeyframeInput keyframe;
  keyframe.id = 3;
  keyframe.T_wc = Rigid3d();
  keyframe.T_wc->t.x() = t_x;
  DetectionInput detection;
  detection.class_name = "chair";
  detection.hypotheses.push_back(
      {Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 2)), 1.0});
  detection.sigma_t = sigma_t;
  keyframe.detections.push_back(detection);
  PointObservation point;
  point.id = 11;
  point.uv = Eigen::Vector2d(u, 240.0);
  keyframe.points.push_back(point);
  return keyframe;
}

std::string Message(const KeyframeInput& keyframe) {
  return ValidateKeyframe(keyframe, std::nullopt, true).message();
}

TEST(KeyframeValidation, TheRangesEndsAreAccepted) {
  for (const KeyframeInput& keyframe :
       {WithPointAndDetection(kMaxCoordinate, kMinNoiseSigma, -kMaxCoordinate),
        WithPointAndDetection(-kMaxCoordinate, kMaxNoiseSigma, kMaxCoordinate),
        WithPointAndDetection(320.0, 0.05, 1.0)}) {
    EXPECT_TRUE(ValidateKeyframe(keyframe, std::nullopt, true).ok())
        << Message(keyframe);
  }
}

TEST(KeyframeValidation, ValuesBeyondTheRangesAreRefusedWithTheirPlace) {
  EXPECT_EQ(Message(WithPointAndDetection(1e160, 0.05, 1.0)),
            "keyframe 3: point 11: uv beyond 1e9 px (1e+160)");
  EXPECT_EQ(Message(WithPointAndDetection(-2e9, 0.05, 1.0)),
            "keyframe 3: point 11: uv beyond 1e9 px (2e+09)");
  EXPECT_THAT(Message(WithPointAndDetection(320.0, 1e-100, 1.0)),
              HasSubstr("sigma_t must be in [1e-9, 1e9], got 1e-100"));
  EXPECT_THAT(Message(WithPointAndDetection(320.0, 2e9, 1.0)),
              HasSubstr("sigma_t must be in [1e-9, 1e9], got 2e+09"));
  EXPECT_EQ(Message(WithPointAndDetection(320.0, 0.05, -1e300)),
            "keyframe 3: T_wc: translation beyond 1e9 m (1e+300)");
  KeyframeInput heavy = WithPointAndDetection(320.0, 0.05, 1.0);
  heavy.detections[0].hypotheses[0].weight = kMaxHypothesisWeight;
  EXPECT_TRUE(ValidateKeyframe(heavy, std::nullopt, true).ok());
  heavy.detections[0].hypotheses[0].weight = 1e300;
  EXPECT_THAT(Message(heavy),
              HasSubstr("hypothesis 0: weight must be positive and at most "
                        "1e100"));
}

}  // namespace
}  // namespace symba::internal
