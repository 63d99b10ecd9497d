#include "top_down_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/angle.h"

namespace symba::bench {
namespace {

// Canvas: the plot is a square on the left, the legend a panel on the right.
constexpr double kPlotLeft = 20.0;
constexpr double kPlotTop = 40.0;
constexpr double kPlotSize = 600.0;
constexpr double kLegendLeft = kPlotLeft + kPlotSize + 20.0;
constexpr double kWidth = kLegendLeft + 230.0;
constexpr double kHeight = kPlotTop + kPlotSize + 20.0;
// Drawing sizes in pixels.
constexpr double kMarker = 7.0;
constexpr double kTick = 16.0;
constexpr double kAxisHalf = 26.0;
constexpr double kRing = 13.0;
constexpr double kLoopRing = 5.0;
// An axis is drawn when its horizontal component exceeds sin(5 deg).
const double kMinHorizontal = std::sin(5.0 * kPi / 180.0);
constexpr char kGtColor[] = "#2ca02c";
constexpr char kGtTrajectoryColor[] = "#222222";
constexpr char kFrontEndColor[] = "#999999";
constexpr char kLoopColor[] = "#ff7f0e";

std::string Num(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f", value);
  return buffer;
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') {
      out += "&amp;";
    } else if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else {
      out += c;
    }
  }
  return out;
}

// A loop closure's drawing in picture pixels: the line from the closing
// keyframe (x1, y1) to the other one and a ring at the closing one.
std::string LoopClosureSvg(
    double x1, double y1, double x2, double y2, const std::string& css_class) {
  return "<g class=\"" + css_class + "\" stroke=\"" + kLoopColor +
         "\" fill=\"none\" stroke-width=\"1.5\"><line x1=\"" + Num(x1) +
         "\" y1=\"" + Num(y1) + "\" x2=\"" + Num(x2) + "\" y2=\"" + Num(y2) +
         "\"/><circle cx=\"" + Num(x1) + "\" cy=\"" + Num(y1) + "\" r=\"" +
         Num(kLoopRing) + "\"/></g>\n";
}

// World x-y to picture pixels.
class Frame {
 public:
  Frame(double x_min, double y_max, double scale)
      : x_min_(x_min), y_max_(y_max), scale_(scale) {}
  double X(double x) const { return kPlotLeft + (x - x_min_) * scale_; }
  double Y(double y) const { return kPlotTop + (y_max_ - y) * scale_; }
  double scale() const { return scale_; }

 private:
  double x_min_;
  double y_max_;
  double scale_;
};

// The unit vector of the object frame perpendicular to a_o closest to
// object x (object y if a_o is object x).
Eigen::Vector3d PerpendicularInObject(const Eigen::Vector3d& a_o) {
  Eigen::Vector3d e = Eigen::Vector3d::UnitX() - a_o.x() * a_o;
  if (e.norm() < 1e-3) e = Eigen::Vector3d::UnitY() - a_o.y() * a_o;
  return e.normalized();
}

class Svg {
 public:
  explicit Svg(const Frame& frame) : frame_(frame) {}

  void Raw(const std::string& text) { out_ += text; }

  void Polyline(const std::vector<Eigen::Vector2d>& points,
                const std::string& color,
                double width,
                const std::string& extra = "") {
    out_ += "<polyline fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" +
            Num(width) + "\"" + extra + " points=\"";
    for (const Eigen::Vector2d& p : points) {
      out_ += Num(frame_.X(p.x())) + "," + Num(frame_.Y(p.y())) + " ";
    }
    out_ += "\"/>\n";
  }

  // A line from world point `c` along pixel direction `d` (x right, y up)
  // from pixel offset `from` to `to`.
  void Ray(const Eigen::Vector3d& c,
           const Eigen::Vector2d& d,
           double from,
           double to,
           const std::string& color,
           const std::string& extra = "") {
    const double x = frame_.X(c.x());
    const double y = frame_.Y(c.y());
    out_ += "<line x1=\"" + Num(x + from * d.x()) + "\" y1=\"" +
            Num(y - from * d.y()) + "\" x2=\"" + Num(x + to * d.x()) +
            "\" y2=\"" + Num(y - to * d.y()) + "\" stroke=\"" + color +
            "\" stroke-width=\"2\"" + extra + "/>\n";
  }

  // A tick along the horizontal part of world direction `u`.
  void Tick(const Eigen::Vector3d& c,
            const Eigen::Vector3d& u,
            const std::string& color) {
    const Eigen::Vector2d d(u.x(), u.y());
    if (d.norm() < 0.2) return;  // nearly vertical: nothing to see from above
    Ray(c, d.normalized(), kMarker, kMarker + kTick, color);
  }

  // The symmetry axis `a_w`, when it is not vertical.
  void Axis(const Eigen::Vector3d& c,
            const Eigen::Vector3d& a_w,
            const std::string& color) {
    const Eigen::Vector2d d(a_w.x(), a_w.y());
    const double horizontal = d.norm();
    if (horizontal <= kMinHorizontal) return;
    Ray(c,
        d / horizontal,
        -kAxisHalf * horizontal,
        kAxisHalf * horizontal,
        color,
        " stroke-dasharray=\"5 3\"");
  }

  // A loop closure: a line between its keyframes and a ring at the one
  // that closed it.
  void LoopClosure(const LoopClosureLine& loop) {
    out_ += LoopClosureSvg(frame_.X(loop.closing.x()),
                           frame_.Y(loop.closing.y()),
                           frame_.X(loop.other.x()),
                           frame_.Y(loop.other.y()),
                           "loop-closure");
  }

  void Ring(const Eigen::Vector3d& c, const std::string& color) {
    out_ += "<circle cx=\"" + Num(frame_.X(c.x())) + "\" cy=\"" +
            Num(frame_.Y(c.y())) + "\" r=\"" + Num(kRing) +
            "\" fill=\"none\" stroke=\"" + color +
            "\" stroke-width=\"1.5\" stroke-dasharray=\"3 3\"/>\n";
  }

  void GtMarker(double x, double y) {
    out_ += "<circle cx=\"" + Num(x) + "\" cy=\"" + Num(y) + "\" r=\"" +
            Num(kMarker) + "\" fill=\"none\" stroke=\"" + kGtColor +
            "\" stroke-width=\"2.5\"/>\n";
  }

  void MapMarker(double x, double y, const std::string& color) {
    const double r = kMarker - 1.0;
    out_ += "<polygon fill=\"" + color + "\" fill-opacity=\"0.85\" points=\"" +
            Num(x) + "," + Num(y - r) + " " + Num(x + r) + "," + Num(y) + " " +
            Num(x) + "," + Num(y + r) + " " + Num(x - r) + "," + Num(y) +
            "\"/>\n";
  }

  void Text(double x,
            double y,
            const std::string& text,
            double size,
            const std::string& extra = "") {
    out_ += "<text x=\"" + Num(x) + "\" y=\"" + Num(y) + "\" font-size=\"" +
            Num(size) + "\"" + extra + ">" + Escape(text) + "</text>\n";
  }

  const std::string& str() const { return out_; }

 private:
  const Frame& frame_;
  std::string out_;
};

// A round length (1, 2 or 5 times a power of ten) of at most `max` metres.
double ScaleBarLength(double max) {
  const double power = std::pow(10.0, std::floor(std::log10(max)));
  for (const double m : {5.0, 2.0, 1.0}) {
    if (m * power <= max) return m * power;
  }
  return power;
}

}  // namespace

std::vector<LoopClosureLine> LoopClosureLines(
    const std::vector<KeyframeEstimate>& keyframes,
    const std::vector<LoopClosureReport>& loops) {
  std::map<KeyframeId, Eigen::Vector3d> position;
  for (const KeyframeEstimate& k : keyframes) position[k.id] = k.T_wc.t;
  std::vector<LoopClosureLine> lines;
  for (const LoopClosureReport& loop : loops) {
    const auto closing = position.find(loop.keyframe);
    const auto other = position.find(loop.other);
    if (loop.waiting || !loop.message.empty() || closing == position.end() ||
        other == position.end()) {
      continue;
    }
    lines.push_back({closing->second, other->second});
  }
  return lines;
}

std::string TopDownSvg(const GroundTruth& gt,
                       const ReplayOutputs& result,
                       const std::string& title,
                       const std::string& color,
                       const std::vector<TrajectoryPose>& front_end,
                       const std::vector<LoopClosureLine>& loops) {
  // Bounds: everything true, and the estimate where it stays within twice
  // the true extent (a diverged estimate is clipped, not zoomed out to).
  Eigen::AlignedBox2d truth;
  for (const TrajectoryPose& p : gt.keyframes) {
    truth.extend(p.T_wc.t.head<2>());
  }
  for (const GroundTruthObject& o : gt.objects)
    truth.extend(o.T_wo.t.head<2>());
  const Eigen::Vector2d extent = truth.sizes().cwiseMax(1.0);
  const Eigen::AlignedBox2d limit(truth.min() - extent, truth.max() + extent);
  Eigen::AlignedBox2d box = truth;
  for (const auto* keyframes : {&result.keyframes, &front_end}) {
    for (const TrajectoryPose& p : *keyframes) {
      if (limit.contains(p.T_wc.t.head<2>())) box.extend(p.T_wc.t.head<2>());
    }
  }
  for (const MapObjectEstimate& o : result.objects) {
    if (limit.contains(o.t_wo.head<2>())) box.extend(o.t_wo.head<2>());
  }
  const double side = 1.1 * box.sizes().maxCoeff() + 0.5;
  const Eigen::Vector2d centre = box.center();
  const Frame frame(
      centre.x() - side / 2, centre.y() + side / 2, kPlotSize / side);

  Svg svg(frame);
  svg.Raw("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(kWidth) +
          "\" height=\"" + Num(kHeight) + "\" viewBox=\"0 0 " + Num(kWidth) +
          " " + Num(kHeight) + "\" font-family=\"sans-serif\">\n");
  svg.Raw("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n");
  svg.Text(kPlotLeft, 26, title, 15, " font-weight=\"bold\"");
  svg.Raw("<defs><clipPath id=\"plot\"><rect x=\"" + Num(kPlotLeft) +
          "\" y=\"" + Num(kPlotTop) + "\" width=\"" + Num(kPlotSize) +
          "\" height=\"" + Num(kPlotSize) + "\"/></clipPath></defs>\n");
  svg.Raw("<rect x=\"" + Num(kPlotLeft) + "\" y=\"" + Num(kPlotTop) +
          "\" width=\"" + Num(kPlotSize) + "\" height=\"" + Num(kPlotSize) +
          "\" fill=\"#fafafa\" stroke=\"#999999\"/>\n");
  svg.Raw("<g clip-path=\"url(#plot)\">\n");

  std::vector<Eigen::Vector2d> points;
  for (const TrajectoryPose& p : gt.keyframes) {
    points.push_back(p.T_wc.t.head<2>());
  }
  svg.Polyline(points, kGtTrajectoryColor, 1.5, " stroke-dasharray=\"6 3\"");
  points.clear();
  for (const TrajectoryPose& p : front_end) {
    points.push_back(p.T_wc.t.head<2>());
  }
  if (!points.empty()) {
    svg.Polyline(points, kFrontEndColor, 1.5, " stroke-dasharray=\"2 3\"");
  }
  points.clear();
  for (const TrajectoryPose& p : result.keyframes) {
    points.push_back(p.T_wc.t.head<2>());
  }
  svg.Polyline(points, color, 2.0);

  // Ground-truth objects.
  for (const GroundTruthObject& o : gt.objects) {
    const Eigen::Vector3d& c = o.T_wo.t;
    if (o.symmetry == SymmetryType::kAsymmetric) {
      svg.Tick(c, o.T_wo.q * Eigen::Vector3d::UnitX(), kGtColor);
    } else {
      svg.Axis(c, o.axis_w, kGtColor);
      if (o.symmetry == SymmetryType::kContinuous) svg.Ring(c, kGtColor);
      const Eigen::Vector3d e_o = PerpendicularInObject(o.axis_o);
      for (int k = 0; k < o.order; ++k) {
        const Eigen::AngleAxisd turn(kTwoPi * k / o.order, o.axis_o);
        svg.Tick(c, o.T_wo.q * (turn * e_o), kGtColor);
      }
    }
    svg.GtMarker(frame.X(c.x()), frame.Y(c.y()));
    svg.Text(frame.X(c.x()) + 10,
             frame.Y(c.y()) + 20,
             o.class_name,
             10,
             std::string(" fill=\"") + kGtColor + "\"");
  }
  // Map objects.
  for (const MapObjectEstimate& o : result.objects) {
    const Eigen::Vector3d& c = o.t_wo;
    if (o.symmetry == SymmetryType::kAsymmetric) {
      for (const Rigid3d& T : o.poses) {
        svg.Tick(c, T.q * Eigen::Vector3d::UnitX(), color);
      }
    } else {
      svg.Axis(c, o.axis_w, color);
      if (o.symmetry == SymmetryType::kContinuous) svg.Ring(c, color);
      if (o.symmetry == SymmetryType::kDiscrete) {
        // objects.json has no a_o: every pose maps it onto a_w.
        const Eigen::Vector3d a_o = o.poses[0].q.conjugate() * o.axis_w;
        const Eigen::Vector3d e_o = PerpendicularInObject(a_o);
        for (const Rigid3d& T : o.poses) svg.Tick(c, T.q * e_o, color);
      }
    }
    svg.MapMarker(frame.X(c.x()), frame.Y(c.y()), color);
  }
  for (const LoopClosureLine& loop : loops) svg.LoopClosure(loop);
  svg.Raw("</g>\n");

  // Legend.
  double y = kPlotTop + 10;
  const double x = kLegendLeft;
  // One legend row: a line of the trajectory's style and its label.
  auto line_entry = [&](const std::string& stroke,
                        const std::string& style,
                        const std::string& label) {
    svg.Raw("<line x1=\"" + Num(x) + "\" y1=\"" + Num(y) + "\" x2=\"" +
            Num(x + 30) + "\" y2=\"" + Num(y) + "\" stroke=\"" + stroke +
            "\" " + style + "/>\n");
    svg.Text(x + 38, y + 4, label, 12);
    y += 22;
  };
  line_entry(kGtTrajectoryColor,
             "stroke-width=\"1.5\" stroke-dasharray=\"6 3\"",
             "true keyframes");
  line_entry(color, "stroke-width=\"2\"", "estimated keyframes");
  if (!front_end.empty()) {
    line_entry(kFrontEndColor,
               "stroke-width=\"1.5\" stroke-dasharray=\"2 3\"",
               "front end");
  }
  if (!loops.empty()) {
    svg.Raw(LoopClosureSvg(x + 24, y, x + 4, y, "legend"));
    svg.Text(x + 38,
             y + 4,
             "loop closure (" + std::to_string(loops.size()) + ")",
             12);
    y += 22;
  }
  svg.GtMarker(x + 15, y);
  svg.Text(x + 38, y + 4, "ground-truth object", 12);
  y += 22;
  svg.MapMarker(x + 15, y, color);
  svg.Text(x + 38, y + 4, "map object", 12);
  y += 22;
  svg.Raw("<line x1=\"" + Num(x) + "\" y1=\"" + Num(y) + "\" x2=\"" +
          Num(x + 30) + "\" y2=\"" + Num(y) +
          "\" stroke=\"#555555\" stroke-width=\"2\" "
          "stroke-dasharray=\"5 3\"/>\n");
  svg.Text(x + 38, y + 4, "symmetry axis (not vertical)", 12);
  y += 22;
  svg.Raw("<line x1=\"" + Num(x + 8) + "\" y1=\"" + Num(y) + "\" x2=\"" +
          Num(x + 24) + "\" y2=\"" + Num(y) +
          "\" stroke=\"#555555\" stroke-width=\"2\"/>\n");
  svg.Text(x + 38, y + 4, "discrete angle / heading", 12);
  y += 22;
  svg.Raw("<circle cx=\"" + Num(x + 15) + "\" cy=\"" + Num(y) + "\" r=\"" +
          Num(kRing) +
          "\" fill=\"none\" stroke=\"#555555\" stroke-width=\"1.5\" "
          "stroke-dasharray=\"3 3\"/>\n");
  svg.Text(x + 38, y + 4, "continuous symmetry", 12);
  y += 22;
  svg.Text(x, y + 4, "green: ground truth", 12);
  y += 40;

  // Scale bar.
  const double metres = ScaleBarLength(160.0 / frame.scale());
  const double pixels = metres * frame.scale();
  svg.Raw("<path d=\"M " + Num(x) + " " + Num(y - 5) + " V " + Num(y) + " H " +
          Num(x + pixels) + " V " + Num(y - 5) +
          "\" fill=\"none\" stroke=\"black\" stroke-width=\"2\"/>\n");
  char label[32];
  std::snprintf(label, sizeof(label), "%g m", metres);
  svg.Text(x, y + 18, label, 12);
  y += 40;
  svg.Text(x, y, "top view (x right, y up)", 12);
  svg.Raw("</svg>\n");
  return svg.str();
}

}  // namespace symba::bench
