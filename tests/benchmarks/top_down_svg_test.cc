// Tests of the benchmarks' top-down picture (benchmarks/top_down_svg.h) as
// far as the loop closures go: LoopClosureLines looks the two keyframes up
// by id and leaves out a closure still waiting, one that failed (it has a
// message) and one whose keyframes are not both known; TopDownSvg draws each
// closure once, with its ring on the closing keyframe, and counts them in
// the legend.
#include "top_down_svg.h"

#include <cstddef>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace symba::bench {
namespace {

KeyframeEstimate Keyframe(KeyframeId id, double x, double y) {
  KeyframeEstimate k;
  k.id = id;
  k.timestamp = static_cast<double>(id);
  k.T_wc.t = Eigen::Vector3d(x, y, 1.5);
  return k;
}

LoopClosureReport Loop(KeyframeId keyframe,
                       KeyframeId other,
                       bool waiting = false,
                       const std::string& message = "") {
  LoopClosureReport report;
  report.keyframe = keyframe;
  report.other = other;
  report.waiting = waiting;
  report.message = message;
  return report;
}

int Occurrences(const std::string& text, const std::string& what) {
  int count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos;
       at = text.find(what, at + what.size())) {
    ++count;
  }
  return count;
}

// The value of attribute `name` in the first element of `svg` from `from`.
std::string Attribute(const std::string& svg,
                      std::size_t from,
                      const std::string& name) {
  const std::size_t at = svg.find(" " + name + "=\"", from);
  if (at == std::string::npos) return "";
  const std::size_t begin = at + name.size() + 3;
  return svg.substr(begin, svg.find('"', begin) - begin);
}

TEST(LoopClosureLines, LooksUpBothKeyframesAndLeavesOutWhatCannotBeDrawn) {
  const std::vector<KeyframeEstimate> keyframes = {
      Keyframe(3, 1.0, 2.0), Keyframe(7, -4.0, 0.5), Keyframe(9, 6.0, 6.0)};
  const std::vector<LoopClosureLine> lines =
      LoopClosureLines(keyframes,
                       {Loop(7, 3),
                        Loop(9, 5),
                        Loop(5, 9),
                        Loop(9, 7, true, "waits for the next solve"),
                        Loop(3, 9, false, "the keyframe graph's solve failed"),
                        Loop(3, 9)});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].closing, Eigen::Vector3d(-4.0, 0.5, 1.5));
  EXPECT_EQ(lines[0].other, Eigen::Vector3d(1.0, 2.0, 1.5));
  EXPECT_EQ(lines[1].closing, Eigen::Vector3d(1.0, 2.0, 1.5));
  EXPECT_EQ(lines[1].other, Eigen::Vector3d(6.0, 6.0, 1.5));
}

TEST(TopDownSvg, DrawsEachLoopClosureWithItsRingOnTheClosingKeyframe) {
  GroundTruth gt;
  ReplayOutputs result;
  for (int k = 0; k < 4; ++k) {
    TrajectoryPose pose;
    pose.timestamp = k;
    pose.T_wc.t = Eigen::Vector3d(k, 0.5 * k, 1.5);
    gt.keyframes.push_back(pose);
    result.keyframes.push_back(pose);
  }
  const std::vector<LoopClosureLine> loops = {
      {Eigen::Vector3d(3.0, 1.5, 1.5), Eigen::Vector3d(0.0, 0.0, 1.5)},
      {Eigen::Vector3d(2.0, 1.0, 1.5), Eigen::Vector3d(1.0, 0.5, 1.5)}};

  const std::string with = TopDownSvg(gt, result, "t", "#1f77b4", {}, loops);
  EXPECT_EQ(Occurrences(with, "class=\"loop-closure\""), 2);
  EXPECT_EQ(Occurrences(with, "loop closure (2)"), 1);
  const std::size_t first = with.find("class=\"loop-closure\"");
  ASSERT_NE(first, std::string::npos);
  // The line starts where the ring is: at the closing keyframe, right of
  // and above the other one (x right, y up).
  EXPECT_EQ(Attribute(with, first, "x1"), Attribute(with, first, "cx"));
  EXPECT_EQ(Attribute(with, first, "y1"), Attribute(with, first, "cy"));
  EXPECT_GT(std::stod(Attribute(with, first, "x1")),
            std::stod(Attribute(with, first, "x2")));
  EXPECT_LT(std::stod(Attribute(with, first, "y1")),
            std::stod(Attribute(with, first, "y2")));

  const std::string without = TopDownSvg(gt, result, "t", "#1f77b4");
  EXPECT_EQ(Occurrences(without, "loop-closure"), 0);
  EXPECT_EQ(Occurrences(without, "loop closure ("), 0);
}

}  // namespace
}  // namespace symba::bench
