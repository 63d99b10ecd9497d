#include "symba/categorization/circular_dbscan.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "symba/geometry/angle.h"

namespace symba {
namespace {

// Counter-clockwise arc from angle `from` to angle `to`, in [0, 2 pi).
double ForwardArc(double from, double to) {
  double d = to - from;
  if (d < 0.0) d += kTwoPi;
  if (d >= kTwoPi) d -= kTwoPi;
  return d;
}

}  // namespace

Status CircularDbscanOptions::Validate() const {
  if (!(eps > 0.0 && eps < kPi)) {
    return Status::Error("circular DBSCAN: eps = " + std::to_string(eps) +
                         " rad is not in (0, pi)");
  }
  if (min_points < 1) {
    return Status::Error("circular DBSCAN: min_points = " +
                         std::to_string(min_points) + " is below 1");
  }
  return Status::Ok();
}

Status CircularDbscan(const std::vector<double>& angles,
                      const CircularDbscanOptions& options,
                      CircularDbscanResult* result) {
  result->labels.clear();
  result->clusters.clear();
  result->order.clear();
  result->num_noise = 0;
  Status status = options.Validate();
  if (!status.ok()) return status;
  const int n = static_cast<int>(angles.size());
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(angles[i])) {
      return Status::Error("circular DBSCAN: angle " + std::to_string(i) +
                           " is not finite");
    }
  }
  if (n == 0) return Status::Ok();

  // Sorted wrapped angles s[k] = wrapped angle of order[k], unrolled once:
  // s[k + n] = s[k] + 2 pi.
  std::vector<int>& order = result->order;
  order.resize(n);
  std::vector<double> s(2 * n);
  for (int i = 0; i < n; ++i) {
    order[i] = i;
    s[i] = WrapToPi(angles[i]);
  }
  std::sort(order.begin(), order.end(), [&s](int a, int b) {
    return s[a] < s[b] || (s[a] == s[b] && a < b);
  });
  {
    std::vector<double> wrapped(s.begin(), s.begin() + n);
    for (int k = 0; k < n; ++k) {
      s[k] = wrapped[order[k]];
      s[k + n] = s[k] + kTwoPi;
    }
  }

  // Core points: 1 + (neighbours ahead within eps) + (behind within eps).
  // The two windows are disjoint because eps < pi.
  const double eps = options.eps;
  std::vector<char> core(n, 0);
  int num_core = 0;
  for (int k = 0; k < n; ++k) {
    const double* first = s.data() + k + 1;
    const double* last = s.data() + k + n;
    const int ahead =
        static_cast<int>(std::upper_bound(first, last, s[k] + eps) - first);
    const int behind =
        static_cast<int>(last - std::lower_bound(first, last, s[k + n] - eps));
    if (1 + ahead + behind >= options.min_points) {
      core[k] = 1;
      ++num_core;
    }
  }

  // sorted position -> cluster index (or noise); filled below.
  std::vector<int> sorted_label(n, CircularDbscanResult::kNoiseLabel);
  bool ring = false;
  if (num_core > 0) {
    // Core positions in sorted order, and where a run starts: after a gap
    // above eps between consecutive core points (circularly).
    std::vector<int> cores;
    cores.reserve(num_core);
    for (int k = 0; k < n; ++k) {
      if (core[k]) cores.push_back(k);
    }
    std::vector<char> run_start(num_core, 0);
    bool any_break = false;
    for (int c = 0; c < num_core; ++c) {
      const int prev = cores[(c + num_core - 1) % num_core];
      const double gap =
          num_core == 1 ? kTwoPi : ForwardArc(s[prev], s[cores[c]]);
      // Two coincident angles are one point apart by 0, never a break; a
      // single core point is a run of its own.
      if (gap > eps || num_core == 1) {
        run_start[c] = 1;
        any_break = true;
      }
    }
    if (!any_break) {
      // One ring: every point is within eps of a core point.
      ring = true;
      for (int k = 0; k < n; ++k) sorted_label[k] = 0;
    } else {
      // Number the runs in sorted order of their first core point.
      std::vector<int> core_label(num_core, -1);
      std::vector<int> starts;
      for (int c = 0; c < num_core; ++c) {
        if (run_start[c]) starts.push_back(c);
      }
      const int num_runs = static_cast<int>(starts.size());
      for (int r = 0; r < num_runs; ++r) {
        const int end = r + 1 < num_runs ? starts[r + 1] : starts[0] + num_core;
        for (int c = starts[r]; c < end; ++c) core_label[c % num_core] = r;
      }
      for (int c = 0; c < num_core; ++c) sorted_label[cores[c]] = core_label[c];
      // Border points: the nearest of the two neighbouring core points,
      // if within eps.
      int c_next = 0;  // index into cores of the first core after k
      for (int k = 0; k < n; ++k) {
        if (core[k]) {
          ++c_next;
          continue;
        }
        const int before = cores[(c_next + num_core - 1) % num_core];
        const int after = cores[c_next % num_core];
        const double d_before = ForwardArc(s[before], s[k]);
        const double d_after = ForwardArc(s[k], s[after]);
        if (d_before <= eps && d_before <= d_after) {
          sorted_label[k] = sorted_label[before];
        } else if (d_after <= eps) {
          sorted_label[k] = sorted_label[after];
        }
      }
    }
  }

  // Labels per input point and cluster summaries. Members of a cluster are
  // a contiguous circular run of sorted positions.
  result->labels.assign(n, CircularDbscanResult::kNoiseLabel);
  int num_clusters = 0;
  for (int k = 0; k < n; ++k) {
    result->labels[order[k]] = sorted_label[k];
    if (sorted_label[k] == CircularDbscanResult::kNoiseLabel) {
      ++result->num_noise;
    } else {
      num_clusters = std::max(num_clusters, sorted_label[k] + 1);
    }
  }
  result->clusters.resize(num_clusters);
  for (int label = 0; label < num_clusters; ++label) {
    CircularCluster& cluster = result->clusters[label];
    // First member: a member whose predecessor is not in this cluster; for
    // a ring, the member after the largest gap.
    int first = -1;
    int size = 0;
    double largest_gap = -1.0;
    int after_largest_gap = 0;
    for (int k = 0; k < n; ++k) {
      if (sorted_label[k] != label) continue;
      ++size;
      const int prev = (k + n - 1) % n;
      if (first < 0 && sorted_label[prev] != label) first = k;
      const double gap = n == 1 ? kTwoPi : ForwardArc(s[prev], s[k]);
      if (gap > largest_gap) {
        largest_gap = gap;
        after_largest_gap = k;
      }
    }
    cluster.size = size;
    // A ring, or a cluster that took every point: start after the largest
    // gap.
    cluster.ring = ring;
    if (ring || first < 0) first = after_largest_gap;
    const double start = s[first];
    double sum_offset = 0.0;
    double max_offset = 0.0;
    for (int m = 0; m < size; ++m) {
      const double offset = ForwardArc(start, s[(first + m) % n]);
      sum_offset += offset;
      max_offset = std::max(max_offset, offset);
    }
    cluster.start = start;
    cluster.extent = max_offset;
    cluster.mean = WrapToPi(start + sum_offset / size);
  }
  return Status::Ok();
}

}  // namespace symba
