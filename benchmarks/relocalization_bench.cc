// symba-relocalization-bench: how often a run whose first pose is unknown
// finds where it is in a map of the long simulated scene
// (docs/relocalization.md "Measured").
//
// Simulates the long scene (23 objects at six places, toured lap after
// lap; --seed), maps its first --map-keyframes keyframes with the default
// backend and saves that map. Then, from each of --starts start points
// spread over the keyframes after the map's, replays --run-keyframes
// keyframes with their first pose unknown (the identity, the rest by
// odometry alone) from the map with relocalisation on, and reports per start
// and in total:
//   relocalised   whether it matched, after how many keyframes, on how many
//                 objects;
//   right         every matched map object stands for the same true object
//                 as the search's object it matched (an object's true object
//                 is the one most of its detections are of);
//   error         the found T_map_run against the true first pose (m, deg;
//                 it includes the map's own error where it was drawn);
//   new, dropped  map objects the whole run made (duplicates where the map
//                 has the object) and loaded objects it dropped;
//   RMSE          the run's keyframe position RMSE in the map's frame
//                 against the truth (no alignment), and the same keyframes'
//                 when the whole sequence is replayed at once.
//
//   symba-relocalization-bench [--seed N] [--map-keyframes N] [--starts N]
//                              [--run-keyframes N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/backend/backend.h"
#include "symba/simulation/simulator.h"

namespace {

using symba::Backend;
using symba::KeyframeInput;
using symba::MapObjectEstimate;
using symba::Rigid3d;

constexpr double kRadToDeg = 57.29577951308232;

struct Flags {
  unsigned seed = 11;
  int map_keyframes = 600;
  int starts = 20;
  int run_keyframes = 150;
  bool reset_front_end = false;
};

std::unique_ptr<Backend> NewBackend(const symba::SimulatedSequence& s) {
  std::unique_ptr<Backend> backend;
  const symba::Status status = Backend::Create(
      symba::BackendOptions(), s.header.camera, s.header.classes, &backend);
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    std::exit(1);
  }
  return backend;
}

void Run(const std::vector<KeyframeInput>& keyframes, Backend* backend) {
  for (const KeyframeInput& keyframe : keyframes) {
    symba::Status status = backend->AddKeyframe(keyframe);
    if (status.ok()) status = backend->OptimizeWindow();
    if (!status.ok()) {
      std::fprintf(stderr,
                   "keyframe %lld: %s\n",
                   static_cast<long long>(keyframe.id),
                   status.message().c_str());
      std::exit(1);
    }
  }
}

// Each map object's true object: the one most of its detections are of.
std::map<symba::ObjectId, int> TrueObjects(const symba::SimulatedSequence& s,
                                           const Backend& backend) {
  std::map<std::string, int> truth_of_detection;
  for (const auto& keyframe : s.detections) {
    for (const symba::SimulatedDetectionTruth& d : keyframe) {
      truth_of_detection[d.id] = d.object;
    }
  }
  std::map<symba::ObjectId, std::map<int, int>> votes;
  for (const symba::DetectionAssignment& a : backend.Assignments()) {
    if (a.object < 0) continue;
    ++votes[a.object][truth_of_detection[a.detection]];
  }
  std::map<symba::ObjectId, int> truth;
  for (const auto& [object, counts] : votes) {
    int best = -1;
    int best_count = 0;
    for (const auto& [true_object, count] : counts) {
      if (count > best_count) {
        best = true_object;
        best_count = count;
      }
    }
    truth[object] = best;
  }
  return truth;
}

struct StartResult {
  int start = 0;
  bool relocalized = false;
  bool right = false;
  int keyframes_needed = 0;
  int matched = 0;
  double error_m = 0.0;
  double error_deg = 0.0;
  double seconds = 0.0;
  int new_objects = 0;      // map objects the run made
  int dropped_objects = 0;  // loaded objects it dropped
  double rmse = 0.0;        // m, the run's keyframes, relocalised runs only
  double whole_rmse = 0.0;  // m, the same keyframes in the whole run
};

// Keyframe position RMSE against the truth of the `estimates` whose ids
// `index_of` holds (id -> index into the sequence).
double KeyframeRmse(const symba::SimulatedSequence& s,
                    const std::vector<symba::KeyframeEstimate>& estimates,
                    const std::map<symba::KeyframeId, size_t>& index_of) {
  double sum = 0.0;
  size_t n = 0;
  for (const symba::KeyframeEstimate& e : estimates) {
    const auto it = index_of.find(e.id);
    if (it == index_of.end()) continue;
    sum += (e.T_wc.t - s.T_wc_true[it->second].t).squaredNorm();
    ++n;
  }
  return n == 0 ? 0.0 : std::sqrt(sum / static_cast<double>(n));
}

StartResult RunFrom(const symba::SimulatedSequence& s,
                    const symba::SavedMap& map,
                    const std::map<symba::ObjectId, int>& map_truth,
                    const std::vector<symba::KeyframeEstimate>& whole,
                    int start,
                    int count,
                    std::vector<MapObjectEstimate>* search_objects) {
  std::vector<KeyframeInput> keyframes(s.keyframes.begin() + start,
                                       s.keyframes.begin() + start + count);
  keyframes.front().T_wc = Rigid3d::Identity();
  keyframes.front().odometry.reset();
  for (size_t k = 1; k < keyframes.size(); ++k) keyframes[k].T_wc.reset();
  // The search's objects are gone once it matched: a second search that
  // stops at the same keyframe keeps them to check the match.
  symba::RelocalizationOptions options;
  std::unique_ptr<Backend> backend = NewBackend(s);
  const symba::Status loaded = backend->LoadMap(map, options);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.message().c_str());
    std::exit(1);
  }
  StartResult r;
  r.start = start;
  for (const KeyframeInput& keyframe : keyframes) {
    Run({keyframe}, backend.get());
    if (backend->Relocalization()->keyframe) break;
  }
  const symba::RelocalizationReport report = *backend->Relocalization();
  r.relocalized = report.keyframe.has_value();
  if (r.relocalized) {
    r.keyframes_needed = report.keyframes;
    r.matched = static_cast<int>(report.correspondences.size());
    r.seconds = report.seconds;
    const Rigid3d& truth = s.T_wc_true[static_cast<size_t>(start)];
    r.error_m = (report.T_map_run.t - truth.t).norm();
    r.error_deg = report.T_map_run.q.angularDistance(truth.q) * kRadToDeg;
    // The search's objects at the keyframe it matched.
    std::unique_ptr<Backend> search = NewBackend(s);
    std::vector<KeyframeInput> until(keyframes.begin(),
                                     keyframes.begin() + report.keyframes);
    Run(until, search.get());
    *search_objects = search->Objects();
    const std::map<symba::ObjectId, int> search_truth = TrueObjects(s, *search);
    r.right = true;
    for (const symba::ObjectCorrespondence& c : report.correspondences) {
      const auto local = search_truth.find(c.local);
      const auto mapped = map_truth.find(c.map);
      r.right = r.right && local != search_truth.end() &&
                mapped != map_truth.end() && local->second == mapped->second;
    }
    // The rest of the run in the map's frame: does it map anything again,
    // does it stay in the map's frame?
    std::vector<KeyframeInput> rest(keyframes.begin() + report.keyframes,
                                    keyframes.end());
    Run(rest, backend.get());
    std::map<symba::KeyframeId, size_t> index_of;
    for (int k = start; k < start + count; ++k) {
      index_of[s.keyframes[static_cast<size_t>(k)].id] = static_cast<size_t>(k);
    }
    r.rmse = KeyframeRmse(s, backend->Keyframes(), index_of);
    r.whole_rmse = KeyframeRmse(s, whole, index_of);
  }
  std::map<symba::ObjectId, bool> kept;
  for (const MapObjectEstimate& o : map.objects) kept[o.id] = false;
  for (const MapObjectEstimate& o : backend->Objects()) {
    auto it = kept.find(o.id);
    if (it == kept.end()) {
      ++r.new_objects;
    } else {
      it->second = true;
    }
  }
  for (const auto& [id, still] : kept) r.dropped_objects += still ? 0 : 1;
  return r;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "symba-relocalization-bench: relocalisation from start points "
      "of the long simulated scene against a map of its beginning"};
  Flags f;
  app.add_option("--seed", f.seed, "simulation seed");
  app.add_option("--map-keyframes",
                 f.map_keyframes,
                 "the first keyframes, mapped and saved")
      ->check(CLI::PositiveNumber);
  app.add_option("--starts", f.starts, "start points after the map's")
      ->check(CLI::PositiveNumber);
  app.add_option("--run-keyframes",
                 f.run_keyframes,
                 "keyframes replayed from each start")
      ->check(CLI::PositiveNumber);
  app.add_flag("--reset-front-end",
               f.reset_front_end,
               "simulate with the front end reset to the truth on rich "
               "keyframes (symba simulate --relocalize-on-rich): a map "
               "without the drift of featureless walks");
  CLI11_PARSE(app, argc, argv);

  symba::SimulationOptions options;
  const int total =
      f.map_keyframes + f.starts * f.run_keyframes + f.run_keyframes;
  options.num_keyframes = total;
  options.relocalize_on_rich = f.reset_front_end;
  symba::SimulatedSequence s;
  symba::Status status = symba::Simulate("long", options, f.seed, &s);
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    return 1;
  }
  std::unique_ptr<Backend> mapper = NewBackend(s);
  Run({s.keyframes.begin(), s.keyframes.begin() + f.map_keyframes},
      mapper.get());
  symba::SavedMap map;
  status = mapper->SaveMap(&map);
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    return 1;
  }
  const std::map<symba::ObjectId, int> map_truth = TrueObjects(s, *mapper);
  // The whole sequence at once: the mapper goes on.
  Run({s.keyframes.begin() + f.map_keyframes, s.keyframes.end()}, mapper.get());
  const std::vector<symba::KeyframeEstimate> whole = mapper->Keyframes();
  std::printf(
      "- Command: `build/bin/symba-relocalization-bench --seed %u "
      "--map-keyframes %d --starts %d --run-keyframes %d%s`\n",
      f.seed,
      f.map_keyframes,
      f.starts,
      f.run_keyframes,
      f.reset_front_end ? " --reset-front-end" : "");
  std::printf(
      "- Map: the long scene's first %d keyframes, %zu map objects "
      "for %zu objects\n\n",
      f.map_keyframes,
      map.objects.size(),
      s.objects.size());
  std::printf(
      "| start | relocalised after | matched objects | right | "
      "error [m] | error [deg] | new map objects | dropped | time [s] | "
      "keyframe RMSE [m] | whole run's [m] |\n");
  std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
  int relocalized = 0;
  int right = 0;
  int no_new_object = 0;
  std::vector<double> needed, error_m, error_deg, seconds, ratios;
  for (int i = 0; i < f.starts; ++i) {
    const int start = f.map_keyframes + i * f.run_keyframes;
    std::vector<MapObjectEstimate> search_objects;
    const StartResult r = RunFrom(
        s, map, map_truth, whole, start, f.run_keyframes, &search_objects);
    if (r.relocalized) {
      ++relocalized;
      right += r.right ? 1 : 0;
      no_new_object += r.new_objects == 0 ? 1 : 0;
      needed.push_back(r.keyframes_needed);
      error_m.push_back(r.error_m);
      error_deg.push_back(r.error_deg);
      seconds.push_back(r.seconds);
      ratios.push_back(r.rmse / r.whole_rmse);
      std::printf(
          "| %d | %d | %d | %s | %.3f | %.2f | %d | %d | %.3f | %.3f | %.3f "
          "|\n",
          start,
          r.keyframes_needed,
          r.matched,
          r.right ? "yes" : "**no**",
          r.error_m,
          r.error_deg,
          r.new_objects,
          r.dropped_objects,
          r.seconds,
          r.rmse,
          r.whole_rmse);
    } else {
      std::printf("| %d | not in %d | | | | | %d | %d | | | |\n",
                  start,
                  f.run_keyframes,
                  r.new_objects,
                  r.dropped_objects);
    }
  }
  std::printf(
      "\nRelocalised from %d of %d start points (%d right, %d "
      "wrong); median %.0f keyframes to relocalise, median error "
      "%.3f m / %.2f deg, median time %.3f s; %d of the relocalised "
      "runs made no new map object; keyframe RMSE over the whole run's on "
      "the same keyframes: median %.2f, max %.2f.\n",
      relocalized,
      f.starts,
      right,
      relocalized - right,
      Median(needed),
      Median(error_m),
      Median(error_deg),
      Median(seconds),
      no_new_object,
      Median(ratios),
      ratios.empty() ? 0.0 : *std::max_element(ratios.begin(), ratios.end()));
  return 0;
}
