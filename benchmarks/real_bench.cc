// symba-real-bench: symba, MH and SH on real detector output. For every
// sequence directory under --data (default: the vendored YCB-Video
// sequences, data/real/ycbv/, data/real/SOURCES.md) it imports the front
// end's trajectory and the DOPE detections into a log (symba import tum:
// stride 5, the ground truth's first pose, odometry 5 mm / 0.01 rad by default,
// --odometry-sigma-t/-r),
// replays it with each method (window mode, default options, one Ceres
// thread) and scores the result against the ground truth
// (docs/evaluation.md, "symba-real-bench"):
//   - camera ATE: position RMSE of the keyframes against gt_T_wc at the same
//     timestamps (no alignment: the log starts at the ground truth's first
//     pose), next to the front end's ATE computed the same way
//     (T_gt(0) T_fe(0)^-1 T_fe(k)), and their ratio;
//   - map objects per real object (map objects of its class);
//   - object position error of the map object of its class with the most
//     observations against the true position (the median over frames of
//     gt_T_wc gt_T_co), next to two naive estimates from the detections at
//     the keyframes: the median of gt_T_wc T_co (ground-truth camera) and
//     the mean of T_wc,fe T_co (front-end camera);
//   - symmetry upgrades (BackendStatistics::object_upgrades).
// Prints one table per method and a summary table; writes every log, replay
// output and a top-down picture per sequence and method, and a bar chart of
// the ATE ratios, into --out-dir; --json writes every number as JSON.
// --drift-yaw and --drift-scale replace the front end by a drifting one made
// from it (front_end_drift.h): the odometry the backends get and the front
// end the ratios compare with are then the drifted ones, and the report is
// a section of its own, "### A drifting front end (...)", under "## Real
// data".
//
//   build/bin/symba-real-bench [--data DIR] [--sequences 0001,0004]
//       [--methods symba,mh,sh] [--out-dir DIR] [--json FILE]
//       [--results-md FILE] [--drift-yaw DEG_PER_M] [--drift-scale S]
//       [--quiet]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_report.h"
#include "front_end_drift.h"
#include "io/json_writer.h"
#include "symba/backend/backend_options.h"
#include "symba/evaluation/evaluate.h"
#include "symba/evaluation/trajectory_error.h"
#include "symba/import/tum_import.h"
#include "symba/io/file_output.h"
#include "symba/io/tum_trajectory.h"
#include "symba/replay/replay.h"
#include "symba/replay/replay_output.h"
#include "tools/commands.h"
#include "top_down_svg.h"

namespace {

namespace fs = std::filesystem;
using symba::Rigid3d;
using symba::Status;
using symba::TrajectoryPose;
using symba::bench::Fixed;
using symba::bench::FrontEndDrift;
using symba::bench::Mean;
using symba::bench::Median;

constexpr int kStride = 5;
// Per method, in --methods order, in the pictures.
constexpr const char* kColors[] = {"#1f77b4", "#ff7f0e", "#d62728"};

struct Flags {
  std::string data = SYMBA_SOURCE_DIR "/data/real/ycbv";
  std::vector<std::string> sequences;  // empty: every directory of --data
  std::vector<std::string> methods = {"symba", "mh", "sh"};
  std::string out_dir = SYMBA_REAL_BENCH_DEFAULT_OUT_DIR;
  std::string json;
  std::string results_md;
  std::string picture;
  std::string picture_link;
  bool quiet = false;
  // Replay options other than the defaults, for measuring their effect.
  symba::BackendOptions backend;
  // --drift-yaw (deg per metre) and --drift-scale: the front end drifts.
  double drift_yaw_deg_per_m = 0.0;
  double drift_scale = 1.0;
  // The noise the log states for each keyframe step of the odometry.
  double odometry_sigma_t = 0.005;  // m
  double odometry_sigma_r = 0.01;   // rad
  FrontEndDrift Drift() const {
    return {drift_yaw_deg_per_m * symba::kPi / 180.0, drift_scale};
  }
};

// The heading of a drifting front end's report, e.g. "### A drifting front
// end (20 deg/m, x1.10)"; it starts with kDriftHeadingStart.
constexpr const char* kDriftHeadingStart = "### A drifting front end (";
std::string DriftHeading(const Flags& flags) {
  std::ostringstream yaw;
  yaw << flags.drift_yaw_deg_per_m;
  return kDriftHeadingStart + yaw.str() + " deg/m, x" +
         Fixed(flags.drift_scale, 2) + ")\n";
}

// A real object of a sequence: its gt_<name>_T_co.txt, and what the naive
// estimates from its detections give.
struct RealObject {
  std::string name;
  Rigid3d T_wo;        // true pose: median position over frames, first rotation
  int detections = 0;  // at keyframes
  double naive_gt_error = std::nan("");         // m
  double naive_front_end_error = std::nan("");  // m
};

struct Sequence {
  std::string name;
  fs::path dir;
  std::vector<TrajectoryPose> gt;         // every frame
  std::vector<TrajectoryPose> front_end;  // every frame (drifted: --drift-*)
  std::vector<TrajectoryPose> front_end_keyframes;  // in gt's world
  double front_end_ate = std::nan("");
  int keyframes = 0;
  int detections = 0;
  std::vector<RealObject> objects;
};

// symba's other ways to solve, beside the run's window policy.
struct PolicyVariant {
  const char* label;
  symba::ReplayMode mode;
  symba::WindowPolicy policy;
};
constexpr PolicyVariant kPolicyVariants[] = {
    {"condition", symba::ReplayMode::kWindow, symba::WindowPolicy::kCondition},
    {"batch", symba::ReplayMode::kBatch, symba::WindowPolicy::kMarginalize},
};
constexpr int kNumPolicyVariants = 2;

// One replay of one sequence, scored.
struct Run {
  double ate = std::nan("");
  double ratio = std::nan("");        // ate / the front end's
  std::vector<int> map_objects;       // per real object
  std::vector<double> object_errors;  // per real object, m (NaN: none)
  // Per real object, the main map object's position NEES (NaN: none).
  std::vector<double> object_nees;
  int upgrades = 0;
  double ms_per_keyframe = 0.0;
  symba::ReplayOutputs outputs;                              // for the picture
  std::vector<symba::bench::LoopClosureLine> loop_closures;  // as drawn
};

// The pose of `poses` (increasing timestamps) at `timestamp`, or null.
const TrajectoryPose* PoseAt(const std::vector<TrajectoryPose>& poses,
                             double timestamp) {
  const auto it = std::lower_bound(
      poses.begin(),
      poses.end(),
      timestamp - symba::kTimestampTolerance,
      [](const TrajectoryPose& p, double t) { return p.timestamp < t; });
  if (it == poses.end() ||
      !(std::abs(it->timestamp - timestamp) <= symba::kTimestampTolerance)) {
    return nullptr;
  }
  return &*it;
}

Eigen::Vector3d ComponentMedian(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d median;
  for (int i = 0; i < 3; ++i) {
    std::vector<double> values;
    for (const Eigen::Vector3d& p : points) values.push_back(p[i]);
    median[i] = Median(values);
  }
  return median;
}

// The front end's poses (every frame) with `drift` applied to its keyframe
// steps (a keyframe every kStride frames).
std::vector<TrajectoryPose> DriftedFrontEnd(std::vector<TrajectoryPose> poses,
                                            const FrontEndDrift& drift) {
  std::vector<Rigid3d> T_wc;
  for (const TrajectoryPose& pose : poses) T_wc.push_back(pose.T_wc);
  T_wc = symba::bench::DriftFrontEnd(T_wc, kStride, drift);
  for (std::size_t f = 0; f < poses.size(); ++f) poses[f].T_wc = T_wc[f];
  return poses;
}

// Reads the ground truth and the front end (drifted by `drift`), and
// computes everything that does not depend on the method.
Status LoadSequence(const fs::path& dir,
                    const FrontEndDrift& drift,
                    Sequence* s) {
  s->name = dir.filename().string();
  s->dir = dir;
  std::vector<TrajectoryPose> front_end;
  Status status =
      symba::ReadTumTrajectory((dir / "gt_T_wc.txt").string(), &s->gt);
  if (status.ok()) {
    status = symba::ReadTumTrajectory((dir / "orbslam3_T_wc.txt").string(),
                                      &front_end);
  }
  if (!status.ok()) return status;
  if (!drift.IsNone()) front_end = DriftedFrontEnd(front_end, drift);
  s->front_end = front_end;

  std::vector<TrajectoryPose> front_end_in_gt;  // every frame
  const Rigid3d T_gt_fe = s->gt.front().T_wc * front_end.front().T_wc.Inverse();
  for (std::size_t f = 0; f < front_end.size(); ++f) {
    TrajectoryPose pose = front_end[f];
    pose.T_wc = T_gt_fe * pose.T_wc;
    front_end_in_gt.push_back(pose);
    if (f % kStride == 0) s->front_end_keyframes.push_back(pose);
  }
  s->keyframes = static_cast<int>(s->front_end_keyframes.size());
  symba::TrajectoryError error;
  status = symba::CompareTrajectories(s->front_end_keyframes,
                                      "front end " + s->name,
                                      s->gt,
                                      (dir / "gt_T_wc.txt").string(),
                                      &error);
  if (!status.ok()) return status;
  s->front_end_ate = error.position_rmse;

  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    const std::string prefix = "gt_";
    const std::string suffix = "_T_co.txt";
    if (file.size() > prefix.size() + suffix.size() &&
        file.compare(0, prefix.size(), prefix) == 0 &&
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0) {
      names.push_back(file.substr(prefix.size(),
                                  file.size() - prefix.size() - suffix.size()));
    }
  }
  std::sort(names.begin(), names.end());
  symba::TumReadOptions rows_options;
  rows_options.skip_all_zero_rows = true;
  rows_options.allow_empty = true;
  for (const std::string& name : names) {
    RealObject o;
    o.name = name;
    std::vector<TrajectoryPose> rows;
    const std::string gt_path = (dir / ("gt_" + name + "_T_co.txt")).string();
    status = symba::ReadTumTrajectory(gt_path, rows_options, &rows);
    if (!status.ok()) return status;
    std::vector<Eigen::Vector3d> positions;
    for (const TrajectoryPose& row : rows) {
      const TrajectoryPose* camera = PoseAt(s->gt, row.timestamp);
      if (camera == nullptr) {
        return Status::Error(gt_path + ":" + std::to_string(row.line) +
                             ": no ground-truth camera at this time");
      }
      const Rigid3d T_wo = camera->T_wc * row.T_wc;
      if (positions.empty()) o.T_wo = T_wo;
      positions.push_back(T_wo.t);
    }
    if (positions.empty()) return Status::Error(gt_path + ": no poses");
    o.T_wo.t = ComponentMedian(positions);

    const fs::path dope = dir / ("dope_" + name + "_T_co.txt");
    if (fs::exists(dope)) {
      status = symba::ReadTumTrajectory(dope.string(), rows_options, &rows);
      if (!status.ok()) return status;
      std::vector<Eigen::Vector3d> with_gt;
      std::vector<double> x, y, z;
      for (const TrajectoryPose& row : rows) {
        const TrajectoryPose* frame = PoseAt(front_end_in_gt, row.timestamp);
        if (frame == nullptr ||
            (frame - front_end_in_gt.data()) % kStride != 0) {
          continue;  // not a keyframe (the importer checks the rest)
        }
        const TrajectoryPose* camera = PoseAt(s->gt, row.timestamp);
        if (camera == nullptr) continue;
        with_gt.push_back((camera->T_wc * row.T_wc).t);
        const Eigen::Vector3d p = (frame->T_wc * row.T_wc).t;
        x.push_back(p.x());
        y.push_back(p.y());
        z.push_back(p.z());
      }
      o.detections = static_cast<int>(with_gt.size());
      if (!with_gt.empty()) {
        o.naive_gt_error = (ComponentMedian(with_gt) - o.T_wo.t).norm();
        o.naive_front_end_error =
            (Eigen::Vector3d(Mean(x), Mean(y), Mean(z)) - o.T_wo.t).norm();
      }
    }
    s->detections += o.detections;
    s->objects.push_back(o);
  }
  return Status::Ok();
}

// The front end's trajectory file to import: the sequence's own, or the
// drifted front end written into `out_dir`.
Status FrontEndFile(const Flags& flags,
                    const Sequence& s,
                    const fs::path& out_dir,
                    std::string* path) {
  if (flags.Drift().IsNone()) {
    *path = (s.dir / "orbslam3_T_wc.txt").string();
    return Status::Ok();
  }
  *path = (out_dir / "drifted_front_end_T_wc.txt").string();
  std::vector<std::pair<double, Rigid3d>> trajectory;
  for (const TrajectoryPose& pose : s.front_end) {
    trajectory.emplace_back(pose.timestamp, pose.T_wc);
  }
  return symba::WriteTumTrajectory(*path, trajectory);
}

Status ImportSequence(const Flags& flags, const Sequence& s, std::string* log) {
  const fs::path dir = fs::path(flags.out_dir) / s.name;
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) return Status::Error(dir.string() + ": " + error.message());
  symba::TumImportOptions options;
  const Status status = FrontEndFile(flags, s, dir, &options.trajectory);
  if (!status.ok()) return status;
  options.first_pose = (s.dir / "gt_T_wc.txt").string();
  options.stride = kStride;
  options.odometry_sigma_t = flags.odometry_sigma_t;
  options.odometry_sigma_r = flags.odometry_sigma_r;
  for (const RealObject& o : s.objects) {
    const fs::path dope = s.dir / ("dope_" + o.name + "_T_co.txt");
    if (fs::exists(dope)) options.objects.push_back({o.name, dope.string()});
  }
  *log = (dir / "log.jsonl").string();
  return symba::ImportTumToLog(options, *log, nullptr);
}

std::vector<TrajectoryPose> ToPoses(
    const std::vector<symba::KeyframeEstimate>& keyframes) {
  std::vector<TrajectoryPose> poses;
  for (const symba::KeyframeEstimate& k : keyframes) {
    TrajectoryPose pose;
    pose.timestamp = k.timestamp;
    pose.T_wc = k.T_wc;
    poses.push_back(pose);
  }
  return poses;
}

// Replays `log` with `options` into <out-dir>/<sequence>/<name> and scores
// it.
Status RunMethod(const Flags& flags,
                 const Sequence& s,
                 const std::string& log,
                 const symba::ReplayOptions& options,
                 const std::string& name,
                 Run* run) {
  symba::ReplayResult result;
  Status status = symba::ReplayLog(log, options, &result);
  if (!status.ok()) return status;
  const fs::path out = fs::path(flags.out_dir) / s.name / name;
  status = symba::WriteDirectoryAtomically(
      out.string(), symba::ReplayOutputFiles(log, options, result));
  if (!status.ok()) return status;

  run->outputs.keyframes = ToPoses(result.keyframes);
  run->outputs.objects = result.objects;
  run->loop_closures =
      symba::bench::LoopClosureLines(result.keyframes, result.loop_closures);
  symba::TrajectoryError error;
  status = symba::CompareTrajectories(run->outputs.keyframes,
                                      out.string(),
                                      s.gt,
                                      (s.dir / "gt_T_wc.txt").string(),
                                      &error);
  if (!status.ok()) return status;
  run->ate = error.position_rmse;
  run->ratio = run->ate / s.front_end_ate;
  for (const RealObject& o : s.objects) {
    int count = 0;
    const symba::MapObjectEstimate* main = nullptr;
    for (const symba::MapObjectEstimate& m : result.objects) {
      if (m.class_name != o.name) continue;
      ++count;
      if (main == nullptr || m.observations > main->observations) main = &m;
    }
    run->map_objects.push_back(count);
    run->object_errors.push_back(
        main == nullptr ? std::nan("") : (main->t_wo - o.T_wo.t).norm());
    run->object_nees.push_back(
        main == nullptr ? std::nan("") : symba::PositionNees(*main, o.T_wo.t));
  }
  run->upgrades = result.statistics.object_upgrades;
  run->ms_per_keyframe =
      result.keyframes.empty()
          ? 0.0
          : 1e3 * result.seconds / static_cast<double>(result.keyframes.size());
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Tables.

// "12, 9": map objects per real object.
std::string Join(const std::vector<int>& values) {
  std::string text;
  for (int v : values) text += (text.empty() ? "" : ", ") + std::to_string(v);
  return text;
}
std::string Join(const std::vector<double>& values, int decimals) {
  std::string text;
  for (double v : values) {
    text += (text.empty() ? "" : ", ") + Fixed(v, decimals);
  }
  return text;
}

// Per (sequence, real object) values of a run, flattened.
std::vector<double> PerObject(const std::vector<Run>& runs, bool map_objects) {
  std::vector<double> values;
  for (const Run& run : runs) {
    if (map_objects) {
      for (int n : run.map_objects) values.push_back(n);
    } else {
      for (double e : run.object_errors) values.push_back(e);
    }
  }
  return values;
}

std::string MethodTable(const std::vector<Sequence>& sequences,
                        const std::vector<Run>& runs) {
  std::ostringstream out;
  out << "| sequence | keyframes | detections | ATE [m] | front-end ATE [m] "
         "| ratio | map objects per object | object error [m] | naive, gt "
         "camera [m] | naive, front-end camera [m] | upgrades | ms / "
         "keyframe |\n"
      << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::vector<double> ate, fe, ratio, naive_gt, naive_fe, upgrades, ms;
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const Sequence& s = sequences[i];
    const Run& r = runs[i];
    std::vector<double> gt_errors, fe_errors;
    for (const RealObject& o : s.objects) {
      gt_errors.push_back(o.naive_gt_error);
      fe_errors.push_back(o.naive_front_end_error);
      naive_gt.push_back(o.naive_gt_error);
      naive_fe.push_back(o.naive_front_end_error);
    }
    out << "| " << s.name << " | " << s.keyframes << " | " << s.detections
        << " | " << Fixed(r.ate, 3) << " | " << Fixed(s.front_end_ate, 3)
        << " | " << Fixed(r.ratio, 3) << " | " << Join(r.map_objects) << " | "
        << Join(r.object_errors, 3) << " | " << Join(gt_errors, 3) << " | "
        << Join(fe_errors, 3) << " | " << r.upgrades << " | "
        << Fixed(r.ms_per_keyframe, 1) << " |\n";
    ate.push_back(r.ate);
    fe.push_back(s.front_end_ate);
    ratio.push_back(r.ratio);
    upgrades.push_back(r.upgrades);
    ms.push_back(r.ms_per_keyframe);
  }
  const std::vector<double> map_objects = PerObject(runs, true);
  const std::vector<double> errors = PerObject(runs, false);
  for (const bool median : {true, false}) {
    const auto f = [&](const std::vector<double>& v) {
      return median ? Median(v) : Mean(v);
    };
    out << "| **" << (median ? "median" : "mean") << "** | | | "
        << Fixed(f(ate), 3) << " | " << Fixed(f(fe), 3) << " | "
        << Fixed(f(ratio), 3) << " | " << Fixed(f(map_objects), 1) << " | "
        << Fixed(f(errors), 3) << " | " << Fixed(f(naive_gt), 3) << " | "
        << Fixed(f(naive_fe), 3) << " | " << Fixed(f(upgrades), 1) << " | "
        << Fixed(f(ms), 1) << " |\n";
  }
  return out.str();
}

// Every map object that was upgraded from asymmetric, with its evidence.
std::string UpgradeTable(const Flags& flags,
                         const std::vector<Sequence>& sequences,
                         const std::vector<std::vector<Run>>& runs) {
  std::ostringstream out;
  out << "| method | sequence | map object | class | now | at keyframe | "
         "evidence | order | flip angle [deg] |\n"
      << "|---|---|---:|---|---|---:|---:|---:|---:|\n";
  int rows = 0;
  for (std::size_t m = 0; m < flags.methods.size(); ++m) {
    for (std::size_t i = 0; i < runs[m].size(); ++i) {
      for (const symba::MapObjectEstimate& o : runs[m][i].outputs.objects) {
        if (!o.upgrade) continue;
        ++rows;
        out << "| " << flags.methods[m] << " | " << sequences[i].name << " | "
            << o.id << " | " << o.class_name << " | "
            << symba::ToString(o.symmetry) << " | " << o.upgrade->keyframe
            << " | " << o.upgrade->evidence << " | "
            << (o.upgrade->order > 0 ? std::to_string(o.upgrade->order)
                                     : std::string("-"))
            << " | "
            << (o.upgrade->order > 0 ? Fixed(o.upgrade->angle * 180.0 / M_PI, 1)
                                     : std::string("-"))
            << " |\n";
      }
    }
  }
  if (rows == 0) return "No map object was upgraded.\n";
  return out.str() +
         "\nEvidence: the number of agreeing flips in different keyframes "
         "(order and angle: the symmetry they fit), or 1 for a detection "
         "whose own hypotheses showed the symmetry (no flip angle).\n";
}

// "median / share within the chi-square 95 % bound" of the objects' NEES.
std::string NeesSummary(const std::vector<Run>& runs) {
  constexpr double kChi2Dof3At95 = 7.814728;
  std::vector<double> nees;
  for (const Run& run : runs) {
    for (double v : run.object_nees) {
      if (std::isfinite(v)) nees.push_back(v);
    }
  }
  if (nees.empty()) return "n/a";
  const auto within = std::count_if(
      nees.begin(), nees.end(), [](double v) { return v <= kChi2Dof3At95; });
  return Fixed(Median(nees), 1) + " / " +
         Fixed(100.0 * static_cast<double>(within) /
                   static_cast<double>(nees.size()),
               0) +
         " %";
}

std::string SummaryTable(const Flags& flags,
                         const std::vector<std::vector<Run>>& runs) {
  std::ostringstream out;
  out << "| method | median ATE ratio | sequences better than the front end "
         "| worst ratio | map objects per object, mean / max | median object "
         "error [m] | object position NEES, median / within 95 % | upgrades "
         "|\n"
      << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t m = 0; m < flags.methods.size(); ++m) {
    std::vector<double> ratios;
    int better = 0;
    int upgrades = 0;
    for (const Run& r : runs[m]) {
      ratios.push_back(r.ratio);
      better += r.ratio < 1.0 ? 1 : 0;
      upgrades += r.upgrades;
    }
    const std::vector<double> map_objects = PerObject(runs[m], true);
    out << "| " << flags.methods[m] << " | " << Fixed(Median(ratios), 3)
        << " | " << better << " / " << runs[m].size() << " | "
        << Fixed(*std::max_element(ratios.begin(), ratios.end()), 3) << " | "
        << Fixed(Mean(map_objects), 1) << " / "
        << Fixed(*std::max_element(map_objects.begin(), map_objects.end()), 0)
        << " | " << Fixed(Median(PerObject(runs[m], false)), 3) << " | "
        << NeesSummary(runs[m]) << " | " << upgrades << " |\n";
  }
  return out.str();
}

// ---------------------------------------------------------------------------
// Pictures and JSON.

// Horizontal bars of the ATE ratio per sequence, one per method, with the
// front end's 1.0 as a vertical line.
std::string RatioBarChart(const Flags& flags,
                          const std::vector<Sequence>& sequences,
                          const std::vector<std::vector<Run>>& runs) {
  const double bar = 10.0;
  const double group = bar * static_cast<double>(flags.methods.size()) + 8.0;
  const double left = 70.0, top = 50.0, width = 520.0;
  double max_ratio = 1.0;
  for (const auto& per_method : runs) {
    for (const Run& r : per_method) {
      if (std::isfinite(r.ratio)) max_ratio = std::max(max_ratio, r.ratio);
    }
  }
  max_ratio = std::ceil(max_ratio);
  const double scale = width / max_ratio;
  const double height = top + group * sequences.size() + 60.0;
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\""
      << left + width + 40 << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << left << "\" y=\"24\" font-size=\"14\" "
      << "font-weight=\"bold\">Keyframe ATE / front-end ATE per sequence "
      << "(below 1: better than the front end)</text>\n";
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const double y0 = top + group * i;
    svg << "<text x=\"" << left - 8 << "\" y=\"" << y0 + group / 2
        << "\" text-anchor=\"end\">" << sequences[i].name << "</text>\n";
    for (std::size_t m = 0; m < flags.methods.size(); ++m) {
      const double ratio = runs[m][i].ratio;
      if (!std::isfinite(ratio)) continue;
      svg << "<rect x=\"" << left << "\" y=\"" << y0 + bar * m << "\" width=\""
          << ratio * scale << "\" height=\"" << bar - 1 << "\" fill=\""
          << kColors[m % 3] << "\"/>\n";
    }
  }
  const double axis_y = top + group * sequences.size();
  for (int k = 0; k <= static_cast<int>(max_ratio); ++k) {
    svg << "<line x1=\"" << left + k * scale << "\" y1=\"" << top - 5
        << "\" x2=\"" << left + k * scale << "\" y2=\"" << axis_y
        << "\" stroke=\"" << (k == 1 ? "black" : "#cccccc")
        << "\" stroke-width=\"" << (k == 1 ? 1.5 : 0.5) << "\"/>\n"
        << "<text x=\"" << left + k * scale << "\" y=\"" << axis_y + 14
        << "\" text-anchor=\"middle\">" << k << "</text>\n";
  }
  for (std::size_t m = 0; m < flags.methods.size(); ++m) {
    const double x = left + 90.0 * m;
    svg << "<rect x=\"" << x << "\" y=\"" << axis_y + 28
        << "\" width=\"12\" height=\"10\" fill=\"" << kColors[m % 3]
        << "\"/>\n<text x=\"" << x + 16 << "\" y=\"" << axis_y + 37 << "\">"
        << flags.methods[m] << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

// The ground truth as the top-down picture wants it: the true keyframes and
// the real objects (drawn as asymmetric).
symba::GroundTruth PictureTruth(const Sequence& s) {
  symba::GroundTruth gt;
  for (const TrajectoryPose& k : s.front_end_keyframes) {
    const TrajectoryPose* pose = PoseAt(s.gt, k.timestamp);
    if (pose != nullptr) gt.keyframes.push_back(*pose);
  }
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    symba::GroundTruthObject o;
    o.id = static_cast<int>(i);
    o.class_name = s.objects[i].name;
    o.T_wo = s.objects[i].T_wo;
    gt.objects.push_back(o);
  }
  return gt;
}

std::string Json(const Flags& flags,
                 const std::vector<Sequence>& sequences,
                 const std::vector<std::vector<Run>>& runs) {
  using symba::io_internal::JsonWriter;
  std::string out;
  JsonWriter json(&out, JsonWriter::kWrapEverything);
  json.BeginObject()
      .Member("stride", kStride)
      .Member("odometry_sigma_t", flags.odometry_sigma_t)
      .Member("odometry_sigma_r", flags.odometry_sigma_r)
      .Key("sequences")
      .BeginArray();
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const Sequence& s = sequences[i];
    json.BeginObject()
        .Member("sequence", s.name)
        .Member("keyframes", s.keyframes)
        .Member("detections", s.detections)
        .Member("front_end_ate", s.front_end_ate)
        .Key("objects")
        .BeginArray();
    for (const RealObject& o : s.objects) {
      json.BeginObject().Member("class", o.name);
      json.Key("t_wo").Doubles(o.T_wo.t.data(), 3);
      json.Member("detections", o.detections)
          .Member("naive_gt_camera_error", o.naive_gt_error)
          .Member("naive_front_end_camera_error", o.naive_front_end_error)
          .EndObject();
    }
    json.EndArray().Key("methods").BeginObject();
    for (std::size_t m = 0; m < flags.methods.size(); ++m) {
      const Run& r = runs[m][i];
      json.Key(flags.methods[m])
          .BeginObject()
          .Member("ate", r.ate)
          .Member("ate_ratio", r.ratio)
          .Key("map_objects")
          .BeginArray();
      for (const int count : r.map_objects) json.Int(count);
      json.EndArray()
          .Key("object_errors")
          .Doubles(r.object_errors.data(),
                   static_cast<int>(r.object_errors.size()))
          .Member("upgrades", r.upgrades)
          .Member("ms_per_keyframe", r.ms_per_keyframe)
          .EndObject();
    }
    json.EndObject().EndObject();
  }
  json.EndArray().EndObject();
  out.push_back('\n');
  return out;
}

// symba under the run's window policy (the first method's runs if it is
// symba), under condition and as a batch solve, per sequence.
std::string PolicyTable(const Flags& flags,
                        const std::vector<Sequence>& sequences,
                        const std::vector<std::vector<Run>>& runs,
                        const std::vector<std::vector<Run>>& variant_runs) {
  const auto symba_at =
      std::find(flags.methods.begin(), flags.methods.end(), "symba");
  if (symba_at == flags.methods.end()) return "";
  const std::vector<Run>& window = runs[symba_at - flags.methods.begin()];
  const std::string policy =
      symba::WindowPolicyName(flags.backend.window_policy);
  std::ostringstream out;
  out << "| sequence | " << policy << " ATE [m] | condition ATE [m] | "
      << policy << " / condition | final batch ATE [m] | map objects per "
      << "object (" << policy << "; condition; final batch) |\n"
      << "|---|---:|---:|---:|---:|---|\n";
  std::vector<double> ratios;
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const Run& condition = variant_runs[0][i];
    const Run& batch = variant_runs[1][i];
    ratios.push_back(window[i].ate / condition.ate);
    out << "| " << sequences[i].name << " | " << Fixed(window[i].ate, 4)
        << " | " << Fixed(condition.ate, 4) << " | " << Fixed(ratios.back(), 3)
        << " | " << Fixed(batch.ate, 4) << " | " << Join(window[i].map_objects)
        << "; " << Join(condition.map_objects) << "; "
        << Join(batch.map_objects) << " |\n";
  }
  out << "| **median** | | | " << Fixed(Median(ratios), 3) << " | | |\n"
      << "| **worst** | | | "
      << Fixed(*std::max_element(ratios.begin(), ratios.end()), 3)
      << " | | |\n";
  return out.str();
}

std::string Markdown(const Flags& flags,
                     const std::vector<Sequence>& sequences,
                     const std::vector<std::vector<Run>>& runs,
                     const std::vector<std::vector<Run>>& variant_runs,
                     const std::string& command) {
  const bool drift = !flags.Drift().IsNone();
  // A drift run is a subsection of "## Real data".
  const std::string sub = drift ? "#### " : "### ";
  std::ostringstream out;
  if (drift) {
    out << DriftHeading(flags) << "\n"
        << "symba, MH and SH on YCB-Video (ORB-SLAM3 + DOPE) with a drifting "
           "front end made from ORB-SLAM3's: each keyframe step (the motion "
           "between consecutive keyframes, in the previous keyframe's camera "
           "frame) has its translation scaled by "
        << Fixed(flags.drift_scale, 2)
        << " and is then turned about the camera's y axis by "
        << flags.drift_yaw_deg_per_m
        << " degrees per metre of its original length; the keyframes are "
           "chained again from the first (`benchmarks/front_end_drift.h`). "
           "The odometry the backends get and the front end of the "
           "front-end ATE are the drifted ones, so the ratio is a method's "
           "ATE over the drifted front end's.\n\n";
  } else {
    out << symba::bench::kRealDataHeading << "\n"
        << "symba, MH and SH on YCB-Video (ORB-SLAM3 + DOPE).\n\n";
  }
  out << "Generated by `symba-real-bench` (`benchmarks/real_bench.cc`); the "
         "metrics are defined in docs/evaluation.md (\"symba-real-bench\"), "
         "the data in data/real/SOURCES.md.\n\n"
      << "- Command: `" << command << "`\n"
      << "- Date: " << symba::bench::UtcDate() << "\n"
      << "- Machine: " << symba::bench::Machine() << "\n"
      << "- Build: " << SYMBA_BUILD_TYPE << ", " << __VERSION__ << "\n"
      << "- Import: stride " << kStride
      << ", first pose = the ground truth's, odometry from the front end "
         "with sigma_t "
      << flags.odometry_sigma_t << " m, sigma_r " << flags.odometry_sigma_r
      << " rad; replay: window mode, default options.\n\n";
  out << sub << "Summary\n\n"
      << SummaryTable(flags, runs) << "\n"
      << "Object position NEES: e^T P^-1 e of the main map object (the one "
         "of the object's class with the most detections) against the "
         "ground truth, with P its position covariance in objects.json "
         "([backend.md](backend.md) \"Covariances\"), over every object of "
         "every sequence; a right covariance gives a median near 2.4 (chi "
         "square, 3 degrees of freedom) and 95 % within the bound 7.81. No "
         "alignment: the first keyframe fixes the frame.\n\n";
  if (!flags.picture.empty()) {
    out << "![ATE over the front end's per sequence](" << flags.picture_link
        << ")\n\n";
  }
  out << sub << "Symmetry upgrades\n\n"
      << UpgradeTable(flags, sequences, runs) << "\n";
  const std::string policies =
      PolicyTable(flags, sequences, runs, variant_runs);
  if (!policies.empty()) {
    out << sub << "Window policies (symba)\n\n"
        << policies << "\n"
        << "symba's ATE with the run's window policy, with `condition` "
           "(keyframes that leave the window held constant with all their "
           "factors) and after one batch solve over every factor at the end of "
           "the run (`--final-batch`; [backend.md](backend.md) \"The "
           "window\").\n\n";
  }
  for (std::size_t m = 0; m < flags.methods.size(); ++m) {
    out << sub << flags.methods[m] << "\n\n"
        << MethodTable(sequences, runs[m]) << "\n";
  }
  out << "ATE: keyframe position RMSE against gt_T_wc, no alignment; "
         "front-end ATE: the front end's keyframes chained from the ground "
         "truth's first pose, the same way; ratio: ATE / front-end ATE. Map "
         "objects per object: map objects of the object's class, one value "
         "per real object (1 is right). Object error: the distance of the "
         "map object of that class with the most observations to the true "
         "position (median over frames of gt_T_wc gt_T_co). Naive: the "
         "detections at the keyframes put in the world with the "
         "ground-truth camera (component-wise median) and with the front "
         "end's camera (mean). Median and mean rows are over sequences "
         "(over real objects for the per-object columns).\n";
  return out.str();
}

// The report in --results-md: "## Real data" is the file's last section
// (symba-bench writes the rest); a drift run is a subsection after it,
// replacing the one of the same drift or added at the end, and a run
// without drift keeps the drift subsections after it.
Status WriteResultsMarkdown(const Flags& flags, const std::string& markdown) {
  if (!flags.Drift().IsNone()) {
    return symba::bench::ReplaceSection(
        flags.results_md, DriftHeading(flags), kDriftHeadingStart, markdown);
  }
  const std::string drift_runs =
      symba::bench::TailFrom(flags.results_md, kDriftHeadingStart);
  return symba::bench::ReplaceTail(
      flags.results_md,
      symba::bench::kRealDataHeading,
      drift_runs.empty() ? markdown : markdown + "\n" + drift_runs);
}

}  // namespace

int main(int argc, char** argv) {
  Flags flags;
  CLI::App app{
      "symba-real-bench: symba, MH and SH on real detector output "
      "(YCB-Video: ORB-SLAM3 front end, DOPE detections), scored against "
      "ground truth"};
  app.add_option("--data", flags.data, "directory of sequence directories")
      ->capture_default_str();
  app.add_option("--sequences",
                 flags.sequences,
                 "sequences to run, comma-separated (default: all)")
      ->delimiter(',');
  app.add_option("--methods", flags.methods, "methods, comma-separated")
      ->delimiter(',')
      ->check(CLI::IsMember({"symba", "mh", "sh"}))
      ->capture_default_str();
  app.add_option("--out-dir",
                 flags.out_dir,
                 "logs, replay outputs and pictures (created if missing)")
      ->capture_default_str();
  app.add_option("--json", flags.json, "also write every number as JSON");
  app.add_option("--results-md",
                 flags.results_md,
                 "also write the report as the file's last section, \"## "
                 "Real data\" (e.g. docs/results.md)");
  app.add_option("--picture",
                 flags.picture,
                 "also write the ATE-ratio chart here (e.g. "
                 "docs/img/real-ate-ratio.svg)");
  app.add_option("--picture-link",
                 flags.picture_link,
                 "how the report links the picture (e.g. "
                 "img/real-ate-ratio.svg)");
  app.add_option("--estimate-noise",
                 flags.backend.estimate_noise,
                 "replay option: estimate the detection noise")
      ->capture_default_str();
  app.add_option("--uncalibrated-sigma-t",
                 flags.backend.uncalibrated_sigma_t,
                 "replay option: the least noise an uncalibrated detection "
                 "is weighed with (m)")
      ->capture_default_str();
  app.add_option("--uncalibrated-sigma-r",
                 flags.backend.uncalibrated_sigma_r,
                 "the same for rotation (rad)")
      ->capture_default_str();
  std::string window_policy =
      symba::WindowPolicyName(flags.backend.window_policy);
  app.add_option("--window-policy",
                 window_policy,
                 "keyframes leaving the window: condition, marginalize or drop")
      ->check(CLI::IsMember({"condition", "marginalize", "drop"}))
      ->capture_default_str();
  std::string chain_prior = symba::ChainPriorName(flags.backend.chain_prior);
  app.add_option("--chain-prior",
                 chain_prior,
                 "marginalize: the keyframe chain's prior, conditional or "
                 "marginal")
      ->check(CLI::IsMember({"conditional", "marginal"}))
      ->capture_default_str();
  std::string detection_errors =
      symba::DetectionErrorsName(flags.backend.detection_errors);
  app.add_option("--detection-errors",
                 detection_errors,
                 "replay option: what a detection's sigmas are the noise of, "
                 "log or independent")
      ->check(CLI::IsMember({"log", "independent"}))
      ->capture_default_str();
  app.add_option("--drift-yaw",
                 flags.drift_yaw_deg_per_m,
                 "make the front end drift: turn each keyframe step about "
                 "the camera's y axis by this many degrees per metre of its "
                 "length")
      ->check(symba::tools::FiniteNumber())
      ->capture_default_str();
  app.add_option("--drift-scale",
                 flags.drift_scale,
                 "make the front end drift: scale each keyframe step's "
                 "translation by this factor (> 0)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  app.add_option("--odometry-sigma-t",
                 flags.odometry_sigma_t,
                 "the noise the log states for each keyframe step of the "
                 "front end's odometry (m)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  app.add_option("--odometry-sigma-r",
                 flags.odometry_sigma_r,
                 "the same for rotation (rad)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  app.add_flag("--quiet", flags.quiet, "no progress on stderr");
  CLI11_PARSE(app, argc, argv);
  symba::ParseWindowPolicy(window_policy, &flags.backend.window_policy);
  symba::ParseChainPrior(chain_prior, &flags.backend.chain_prior);
  symba::ParseDetectionErrors(detection_errors,
                              &flags.backend.detection_errors);

  const auto fail = [](const std::string& message) {
    std::fprintf(stderr, "symba-real-bench: %s\n", message.c_str());
    return 1;
  };
  std::error_code error;
  fs::create_directories(flags.out_dir, error);
  if (error) return fail(flags.out_dir + ": " + error.message());
  if (flags.sequences.empty()) {
    for (const auto& entry : fs::directory_iterator(flags.data, error)) {
      if (entry.is_directory()) {
        flags.sequences.push_back(entry.path().filename().string());
      }
    }
    if (error) return fail(flags.data + ": " + error.message());
    std::sort(flags.sequences.begin(), flags.sequences.end());
  }
  if (flags.sequences.empty()) return fail(flags.data + ": no sequences");

  std::vector<Sequence> sequences(flags.sequences.size());
  std::vector<std::vector<Run>> runs(flags.methods.size());
  std::vector<std::vector<Run>> variant_runs(kNumPolicyVariants);
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    Sequence& s = sequences[i];
    Status status = LoadSequence(
        fs::path(flags.data) / flags.sequences[i], flags.Drift(), &s);
    std::string log;
    if (status.ok()) status = ImportSequence(flags, s, &log);
    if (!status.ok()) return fail(status.message());
    for (std::size_t m = 0; m < flags.methods.size(); ++m) {
      if (!flags.quiet) {
        std::fprintf(stderr,
                     "symba-real-bench: %s %s (%d keyframes)\n",
                     s.name.c_str(),
                     flags.methods[m].c_str(),
                     s.keyframes);
      }
      symba::ReplayOptions options;
      options.backend = flags.backend;
      symba::ParseMethod(flags.methods[m], &options.backend.method);
      Run run;
      status = RunMethod(flags, s, log, options, flags.methods[m], &run);
      if (!status.ok()) return fail(s.name + ": " + status.message());
      const std::string title =
          s.name + ", " + flags.methods[m] + ": ATE " + Fixed(run.ate, 3) +
          " m (front end " + Fixed(s.front_end_ate, 3) + " m), " +
          symba::bench::Count(static_cast<int>(run.outputs.objects.size()),
                              "map object") +
          " for " +
          symba::bench::Count(static_cast<int>(s.objects.size()), "object") +
          (run.loop_closures.empty()
               ? std::string()
               : ", " + symba::bench::Count(
                            static_cast<int>(run.loop_closures.size()),
                            "loop closure"));
      status = symba::bench::WriteText(
          (fs::path(flags.out_dir) / (s.name + "-" + flags.methods[m] + ".svg"))
              .string(),
          symba::bench::TopDownSvg(PictureTruth(s),
                                   run.outputs,
                                   title,
                                   kColors[m % 3],
                                   s.front_end_keyframes,
                                   run.loop_closures));
      if (!status.ok()) return fail(status.message());
      runs[m].push_back(std::move(run));
    }
    const auto symba_at =
        std::find(flags.methods.begin(), flags.methods.end(), "symba");
    for (int v = 0; symba_at != flags.methods.end() && v < kNumPolicyVariants;
         ++v) {
      const bool same_as_window =
          kPolicyVariants[v].mode == symba::ReplayMode::kWindow &&
          kPolicyVariants[v].policy == flags.backend.window_policy;
      if (same_as_window) {
        variant_runs[v].push_back(runs[symba_at - flags.methods.begin()][i]);
        continue;
      }
      symba::ReplayOptions options;
      options.backend = flags.backend;
      options.backend.method = symba::Method::kSymba;
      options.backend.window_policy = kPolicyVariants[v].policy;
      // "batch": the window run with a final batch solve.
      options.final_batch =
          kPolicyVariants[v].mode == symba::ReplayMode::kBatch;
      Run run;
      status = RunMethod(flags,
                         s,
                         log,
                         options,
                         std::string("symba-") + kPolicyVariants[v].label,
                         &run);
      if (!status.ok()) return fail(s.name + ": " + status.message());
      variant_runs[v].push_back(std::move(run));
    }
  }

  const std::string markdown = Markdown(
      flags, sequences, runs, variant_runs, symba::bench::Command(argc, argv));
  std::fputs(markdown.c_str(), stdout);
  Status status = symba::bench::WriteText(
      (fs::path(flags.out_dir) / "ate-ratio.svg").string(),
      RatioBarChart(flags, sequences, runs));
  if (status.ok() && !flags.json.empty()) {
    status = symba::bench::WriteText(flags.json, Json(flags, sequences, runs));
  }
  if (status.ok() && !flags.picture.empty()) {
    status = symba::bench::WriteText(flags.picture,
                                     RatioBarChart(flags, sequences, runs));
  }
  if (status.ok() && !flags.results_md.empty()) {
    status = WriteResultsMarkdown(flags, markdown);
  }
  if (!status.ok()) return fail(status.message());
  if (!flags.quiet) {
    std::fprintf(stderr,
                 "symba-real-bench: logs, outputs and pictures in %s\n",
                 flags.out_dir.c_str());
  }
  return 0;
}
