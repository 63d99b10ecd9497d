#include "symba/categorization/categorize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "symba/categorization/circular_dbscan.h"
#include "symba/common/check.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/swing_twist.h"

namespace symba {
namespace {

// Quaternions must be unit within this (the log format's tolerance).
constexpr double kUnitQuaternionTolerance = 1e-3;

std::string Deg(double rad) { return std::to_string(rad * 180.0 / kPi); }

bool IsAngleIn0Pi(double a) { return a > 0.0 && a < kPi; }

// Rotation angle of unit q, in [0, pi].
double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

// Counter-clockwise arc from `from` to `to`, in [0, 2 pi).
double ForwardArc(double from, double to) {
  double d = WrapToPi(to) - WrapToPi(from);
  if (d < 0.0) d += kTwoPi;
  if (d >= kTwoPi) d -= kTwoPi;
  return d;
}

// Per-call working memory.
struct Work {
  std::vector<Eigen::Quaterniond> q;  // normalised R_j
  std::vector<Eigen::Matrix3d> R;
  std::vector<double> w;
  std::vector<char> usable;  // passed the translation gate
  std::vector<int> support;  // neighbours within min_axis_angle
  // Per pass.
  std::vector<Eigen::Vector3d> dir;  // omega_j / theta_j (far rows)
  std::vector<double> theta;
  std::vector<int> far;
  std::vector<char> axis_inlier;
  std::vector<int> twist_owner;  // hypothesis of each DBSCAN input
  std::vector<double> twist_in;  // DBSCAN input
  std::vector<double> psi;       // per hypothesis, twist relative to q_ref
  CircularDbscanResult dbscan;
  std::vector<double> scratch;
};

// Outcome of one pass with a given reference.
struct Pass {
  bool retry = false;  // the reference is an outlier; try `next_reference`
  int next_reference = -1;
  SymmetryType type = SymmetryType::kAsymmetric;
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_c = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_ref = Eigen::Quaterniond::Identity();
};

Status ValidateHypotheses(const std::vector<PoseHypothesis>& hypotheses) {
  if (hypotheses.empty()) {
    return Status::Error("categorize: the detection has no hypotheses");
  }
  for (int j = 0; j < static_cast<int>(hypotheses.size()); ++j) {
    const PoseHypothesis& h = hypotheses[j];
    // Built only on failure: no allocation on the normal path.
    const auto where = [j] {
      return "categorize: hypothesis " + std::to_string(j);
    };
    if (!h.T_co.q.coeffs().allFinite()) {
      return Status::Error(where() + ": rotation is not finite");
    }
    if (!h.T_co.t.allFinite()) {
      return Status::Error(where() + ": translation is not finite");
    }
    const double norm = h.T_co.q.norm();
    if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) {
      return Status::Error(where() + ": quaternion norm " +
                           std::to_string(norm) + " is not 1");
    }
    if (!(std::isfinite(h.weight) && h.weight > 0.0)) {
      return Status::Error(where() + ": weight " + std::to_string(h.weight) +
                           " is not positive and finite");
    }
  }
  return Status::Ok();
}

// Step 1: the highest-weight hypothesis (ties: lowest index) among those
// with at least min_points usable hypotheses (itself included) within
// min_axis_angle of rotation; if none has, the highest-weight one.
int ChooseReference(const CategorizationOptions& options, Work* work) {
  const int n = static_cast<int>(work->w.size());
  // |q_i . q_j| >= cos(angle / 2)  <=>  rotation angle between them <= angle.
  const double cos_half = std::cos(0.5 * options.min_axis_angle);
  std::vector<int>& support = work->support;
  support.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!work->usable[i]) continue;
    ++support[i];
    for (int j = i + 1; j < n; ++j) {
      if (work->usable[j] &&
          std::abs(work->q[i].coeffs().dot(work->q[j].coeffs())) >= cos_half) {
        ++support[i];
        ++support[j];
      }
    }
  }
  int best = -1;
  int best_any = -1;
  for (int j = 0; j < n; ++j) {
    if (!work->usable[j]) continue;
    if (best_any < 0 || work->w[j] > work->w[best_any]) best_any = j;
    if (support[j] >= options.min_points &&
        (best < 0 || work->w[j] > work->w[best])) {
      best = j;
    }
  }
  return best >= 0 ? best : best_any;
}

// Step 0: drop hypotheses whose translation is farther than the gate from the
// coordinate-wise median; if that drops everything, keep everything.
void GateTranslations(const std::vector<PoseHypothesis>& hypotheses,
                      double gate,
                      Work* work) {
  const int n = static_cast<int>(hypotheses.size());
  work->usable.assign(n, 1);
  if (!std::isfinite(gate)) return;
  Eigen::Vector3d median;
  for (int axis = 0; axis < 3; ++axis) {
    work->scratch.resize(n);
    for (int j = 0; j < n; ++j) work->scratch[j] = hypotheses[j].T_co.t[axis];
    auto mid = work->scratch.begin() + n / 2;
    std::nth_element(work->scratch.begin(), mid, work->scratch.end());
    median[axis] = *mid;
  }
  int kept = 0;
  for (int j = 0; j < n; ++j) {
    work->usable[j] = (hypotheses[j].T_co.t - median).norm() <= gate;
    kept += work->usable[j];
  }
  if (kept == 0) work->usable.assign(n, 1);
}

// The singular pair of B = sum_{j in set} w_j R_j whose right vector is the
// nearest to `guess`; returns false if B vanishes.
bool FitAxis(const Work& work,
             const std::vector<char>& in_set,
             const Eigen::Vector3d& guess,
             Eigen::Vector3d* axis_o,
             Eigen::Vector3d* axis_c) {
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
  for (int j = 0; j < static_cast<int>(in_set.size()); ++j) {
    if (in_set[j]) B += work.w[j] * work.R[j];
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  int best = 0;
  double best_dot = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double dot = std::abs(svd.matrixV().col(k).dot(guess));
    if (dot > best_dot) {
      best_dot = dot;
      best = k;
    }
  }
  Eigen::Vector3d a_o = svd.matrixV().col(best);
  if (a_o.dot(guess) < 0.0) a_o = -a_o;
  const Eigen::Vector3d b = B * a_o;
  if (!(b.norm() > 1e-12 * (1.0 + B.norm()))) return false;
  *axis_o = a_o;
  *axis_c = b.normalized();
  return true;
}

// Step 6b: neighbouring clusters closer than min_cluster_separation whose
// union is still within max_cluster_extent are one mode split by DBSCAN
// (a gap above eps inside a noisy mode): merge them, closest pair first.
// Labels are renumbered in order of the merged clusters' first label; the
// summaries keep start, extent and size (mean is not maintained).
void MergeCloseClusters(const CategorizationOptions& options,
                        CircularDbscanResult* dbscan) {
  std::vector<CircularCluster>& clusters = dbscan->clusters;
  const int num_raw = static_cast<int>(clusters.size());
  if (num_raw < 2 || clusters[0].ring) return;
  std::vector<int> merged_into(num_raw);
  for (int c = 0; c < num_raw; ++c) merged_into[c] = c;
  std::vector<char> alive(num_raw, 1);
  while (true) {
    int best_from = -1;
    int best_to = -1;
    double best_gap = options.min_cluster_separation;
    for (int c = 0; c < num_raw; ++c) {
      if (!alive[c]) continue;
      const double end = clusters[c].start + clusters[c].extent;
      // The next live cluster counter-clockwise.
      int next = -1;
      double gap = kTwoPi;
      for (int d = 0; d < num_raw; ++d) {
        if (d == c || !alive[d]) continue;
        const double arc = ForwardArc(end, clusters[d].start);
        if (arc < gap) {
          gap = arc;
          next = d;
        }
      }
      if (next < 0 || gap >= best_gap) continue;
      const double union_extent = ForwardArc(
          clusters[c].start, clusters[next].start + clusters[next].extent);
      if (union_extent <= options.max_cluster_extent) {
        best_gap = gap;
        best_from = c;
        best_to = next;
      }
    }
    if (best_from < 0) break;
    CircularCluster& a = clusters[best_from];
    const CircularCluster& b = clusters[best_to];
    a.extent = ForwardArc(a.start, b.start + b.extent);
    a.size += b.size;
    alive[best_to] = 0;
    for (int c = 0; c < num_raw; ++c) {
      if (merged_into[c] == best_to) merged_into[c] = best_from;
    }
  }
  // Renumber the survivors 0..M-1 in their original order.
  std::vector<int> new_label(num_raw, -1);
  int num_alive = 0;
  for (int c = 0; c < num_raw; ++c) {
    if (alive[c]) {
      new_label[c] = num_alive;
      clusters[num_alive++] = clusters[c];
    }
  }
  if (num_alive == num_raw) return;
  clusters.resize(num_alive);
  for (int& label : dbscan->labels) {
    if (label != CircularDbscanResult::kNoiseLabel) {
      label = new_label[merged_into[label]];
    }
  }
}

// Step 7b (discrete only, after the decision): a mode with too few or too
// spread members to hold a core point is DBSCAN noise. DBSCAN of the noise
// points with rescue_min_points finds such groups; each that is compact and
// at least min_cluster_separation from every cluster becomes a cluster.
void RescueSmallModes(const CategorizationOptions& options, Work* work) {
  CircularDbscanResult& dbscan = work->dbscan;
  std::vector<double>& noise_angles = work->scratch;
  std::vector<int> noise_index;  // position in twist_in
  noise_angles.clear();
  for (int i = 0; i < static_cast<int>(dbscan.labels.size()); ++i) {
    if (dbscan.labels[i] == CircularDbscanResult::kNoiseLabel) {
      noise_angles.push_back(work->twist_in[i]);
      noise_index.push_back(i);
    }
  }
  CircularDbscanOptions rescue_options;
  rescue_options.eps = options.cluster_eps;
  rescue_options.min_points = options.rescue_min_points;
  CircularDbscanResult rescue;
  // The caller runs this only with rescue_min_points > 0; cluster_eps is
  // validated and the twists are finite, so DBSCAN cannot refuse its input.
  const Status status = CircularDbscan(noise_angles, rescue_options, &rescue);
  SYMBA_CHECK(status.ok()) << status.message();
  const int num_existing = static_cast<int>(dbscan.clusters.size());
  for (int r = 0; r < static_cast<int>(rescue.clusters.size()); ++r) {
    const CircularCluster& candidate = rescue.clusters[r];
    if (candidate.ring || candidate.extent > options.max_cluster_extent) {
      continue;
    }
    bool apart = true;
    for (int c = 0; c < num_existing && apart; ++c) {
      const CircularCluster& cluster = dbscan.clusters[c];
      const double after =
          ForwardArc(cluster.start + cluster.extent, candidate.start);
      const double before =
          ForwardArc(candidate.start + candidate.extent, cluster.start);
      apart = after >= options.min_cluster_separation &&
              before >= options.min_cluster_separation &&
              after + before + cluster.extent + candidate.extent <
                  kTwoPi + 1e-9;  // the arcs do not overlap
    }
    if (!apart) continue;
    const int label = static_cast<int>(dbscan.clusters.size());
    dbscan.clusters.push_back(candidate);
    for (int k = 0; k < static_cast<int>(rescue.labels.size()); ++k) {
      if (rescue.labels[k] == r) {
        dbscan.labels[noise_index[k]] = label;
        --dbscan.num_noise;
      }
    }
  }
}

// Step 2: relative rotations omega_j = Log(q_r^-1 q_j) in the reference's
// object frame; rows farther than min_axis_angle get a direction and vote.
void RelativeRotations(const CategorizationOptions& options,
                       int r,
                       Work* work) {
  const int n = static_cast<int>(work->q.size());
  const Eigen::Quaterniond q_r_inv = work->q[r].conjugate();
  work->theta.assign(n, 0.0);
  work->dir.assign(n, Eigen::Vector3d::Zero());
  work->far.clear();
  for (int j = 0; j < n; ++j) {
    if (!work->usable[j]) continue;
    const Eigen::Vector3d omega =
        LogSO3(Eigen::Quaterniond(q_r_inv * work->q[j]));
    const double theta = omega.norm();
    work->theta[j] = theta;
    if (theta > options.min_axis_angle) {
      work->dir[j] = omega / theta;
      work->far.push_back(j);
    }
  }
}

// The winner of the axis votes of step 3.
struct AxisVote {
  Eigen::Vector3d guess = Eigen::Vector3d::UnitZ();
  int support = 0;
  double support_weight = 0.0;
};

// Step 3: axis votes. With a prior axis, the far rows that agree with it;
// otherwise the far row whose direction collects the most vote weight.
AxisVote VoteAxis(const CategorizationOptions& options,
                  const ClassPrior* prior,
                  bool use_prior_axis,
                  const Work& work,
                  CategorizationDiagnostics* diagnostics) {
  const double cos_vote = std::cos(options.axis_vote_angle);
  AxisVote vote;
  if (use_prior_axis) {
    vote.guess = prior->axis_o.normalized();
    for (int k : work.far) {
      if (std::abs(work.dir[k].dot(vote.guess)) >= cos_vote) {
        ++vote.support;
        vote.support_weight += work.w[k];
      }
    }
    diagnostics->prior_axis_used = true;
  } else {
    double best_weight = -1.0;
    for (int i : work.far) {
      int count = 0;
      double weight = 0.0;
      for (int k : work.far) {
        if (std::abs(work.dir[i].dot(work.dir[k])) >= cos_vote) {
          ++count;
          weight += work.w[k];
        }
      }
      if (weight > best_weight) {
        best_weight = weight;
        vote.support = count;
        vote.support_weight = weight;
        vote.guess = work.dir[i];
      }
    }
  }
  diagnostics->axis_support = vote.support_weight;
  return vote;
}

// Step 4: axis from B = sum w_j R_j over near rows and voters, then over
// the axis inliers (work->axis_inlier holds the final inlier set).
void FitAxisToInliers(const CategorizationOptions& options,
                      bool use_prior_axis,
                      int r,
                      const Eigen::Vector3d& guess,
                      Work* work,
                      CategorizationDiagnostics* diagnostics,
                      Eigen::Vector3d* axis_o_out,
                      Eigen::Vector3d* axis_c_out) {
  const int n = static_cast<int>(work->q.size());
  const double cos_vote = std::cos(options.axis_vote_angle);
  std::vector<char>& in_set = work->axis_inlier;
  in_set.assign(n, 0);
  for (int j = 0; j < n; ++j) {
    if (!work->usable[j]) continue;
    in_set[j] = work->theta[j] <= options.min_axis_angle ||
                std::abs(work->dir[j].dot(guess)) >= cos_vote;
  }
  Eigen::Vector3d axis_o = guess;
  Eigen::Vector3d axis_c = work->R[r] * guess;
  const double cos_swing = std::cos(options.swing_tolerance);
  constexpr int kAxisIterations = 3;
  for (int iteration = 0; iteration < kAxisIterations; ++iteration) {
    if (use_prior_axis) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 0; j < n; ++j) {
        if (in_set[j]) sum += work->w[j] * (work->R[j] * axis_o);
      }
      if (sum.norm() > 1e-12) axis_c = sum.normalized();
    } else {
      Eigen::Vector3d a_o, a_c;
      if (FitAxis(*work, in_set, axis_o, &a_o, &a_c)) {
        axis_o = a_o;
        axis_c = a_c;
      }
    }
    int count = 0;
    for (int j = 0; j < n; ++j) {
      in_set[j] =
          work->usable[j] && (work->R[j] * axis_o).dot(axis_c) >= cos_swing;
      count += in_set[j];
    }
    diagnostics->num_axis_inliers = count;
    if (count == 0) break;
  }
  *axis_o_out = axis_o;
  *axis_c_out = axis_c;
}

// Step 5: signed twists relative to the reference with its swing aligned.
// Fills work->psi (every hypothesis) and work->twist_in / twist_owner (the
// axis inliers); returns q_ref.
Eigen::Quaterniond ComputeTwists(int r,
                                 const Eigen::Vector3d& axis_o,
                                 const Eigen::Vector3d& axis_c,
                                 Work* work) {
  const int n = static_cast<int>(work->q.size());
  const Eigen::Quaterniond q_ref =
      (MinimalRotation<double>(work->R[r] * axis_o, axis_c) * work->q[r])
          .normalized();
  const Eigen::Quaterniond q_ref_inv = q_ref.conjugate();
  work->psi.assign(n, 0.0);
  work->twist_in.clear();
  work->twist_owner.clear();
  for (int j = 0; j < n; ++j) {
    work->psi[j] = TwistAngle<double>(q_ref_inv * work->q[j], axis_o);
    if (work->axis_inlier[j]) {
      work->twist_in.push_back(work->psi[j]);
      work->twist_owner.push_back(j);
    }
  }
  return q_ref;
}

// Step 6: circular DBSCAN of the twists into work->dbscan, then (6b) the
// merge of close clusters.
void ClusterTwists(const CategorizationOptions& options,
                   Work* work,
                   CategorizationDiagnostics* diagnostics) {
  CircularDbscanOptions dbscan_options;
  dbscan_options.eps = options.cluster_eps;
  dbscan_options.min_points = options.min_points;
  CircularDbscanResult& dbscan = work->dbscan;
  // Validate() keeps cluster_eps in (0, pi) and min_points >= 1, and twists
  // are finite, so DBSCAN cannot refuse its input.
  const Status status = CircularDbscan(work->twist_in, dbscan_options, &dbscan);
  SYMBA_CHECK(status.ok()) << status.message();
  diagnostics->num_raw_clusters = static_cast<int>(dbscan.clusters.size());
  if (options.merge_close_clusters) MergeCloseClusters(options, &dbscan);
  diagnostics->num_noise = dbscan.num_noise;
}

// Step 7: the DBSCAN label of the reference r (kNoiseLabel if it is noise or
// not an axis inlier).
int ReferenceLabel(const Work& work, int r) {
  int reference_label = CircularDbscanResult::kNoiseLabel;
  for (int i = 0; i < static_cast<int>(work.twist_owner.size()); ++i) {
    if (work.twist_owner[i] == r) reference_label = work.dbscan.labels[i];
  }
  return reference_label;
}

// Step 7, the reference is noise: the reference for the retry is the
// highest-weight member of the largest cluster (ties: the lower cluster
// index, then the lower hypothesis index).
int NextReference(const Work& work) {
  const CircularDbscanResult& dbscan = work.dbscan;
  const int num_clusters = static_cast<int>(dbscan.clusters.size());
  int largest = 0;
  for (int c = 1; c < num_clusters; ++c) {
    if (dbscan.clusters[c].size > dbscan.clusters[largest].size) {
      largest = c;
    }
  }
  int next = -1;
  for (int i = 0; i < static_cast<int>(work.twist_owner.size()); ++i) {
    const int j = work.twist_owner[i];
    if (dbscan.labels[i] == largest &&
        (next < 0 || work.w[j] > work.w[next] ||
         (work.w[j] == work.w[next] && j < next))) {
      next = j;
    }
  }
  return next;
}

// The shape of the clusters that step 7 decides on.
struct ClusterShape {
  double max_extent = 0.0;
  bool all_compact = true;
  double min_separation = 0.0;
  bool separated = false;
};

// Step 7: extents, and the arcs between neighbouring clusters: for cluster
// c, from its end to the start of the next cluster counter-clockwise. Each
// must be at least min_cluster_separation and separation_ratio times the
// mean extent of the two clusters it separates.
ClusterShape MeasureClusters(const CategorizationOptions& options,
                             const CircularDbscanResult& dbscan) {
  const int num_clusters = static_cast<int>(dbscan.clusters.size());
  ClusterShape shape;
  for (const CircularCluster& c : dbscan.clusters) {
    shape.max_extent = std::max(shape.max_extent, c.ring ? kTwoPi : c.extent);
    shape.all_compact =
        shape.all_compact && !c.ring && c.extent <= options.max_cluster_extent;
  }
  if (num_clusters >= 2 && shape.all_compact) {
    shape.min_separation = kTwoPi;
    shape.separated = true;
    for (int c = 0; c < num_clusters; ++c) {
      const CircularCluster& cluster = dbscan.clusters[c];
      const double end = cluster.start + cluster.extent;
      double gap = kTwoPi;
      int next = c;
      for (int d = 0; d < num_clusters; ++d) {
        if (d == c) continue;
        const double arc = ForwardArc(end, dbscan.clusters[d].start);
        if (arc < gap) {
          gap = arc;
          next = d;
        }
      }
      shape.min_separation = std::min(shape.min_separation, gap);
      const double mean_extent =
          0.5 * (cluster.extent + dbscan.clusters[next].extent);
      shape.separated = shape.separated &&
                        gap >= options.min_cluster_separation &&
                        gap >= options.separation_ratio * mean_extent;
    }
  }
  return shape;
}

// Step 7: empty fraction, the share of the circle in gaps wider than
// empty_gap_angle between consecutive axis-inlier twists.
double EmptyFraction(const CategorizationOptions& options, const Work& work) {
  const int num_in = static_cast<int>(work.twist_in.size());
  double empty = 0.0;
  for (int k = 0; k < num_in; ++k) {
    const double from = work.twist_in[work.dbscan.order[k]];
    const double to = work.twist_in[work.dbscan.order[(k + 1) % num_in]];
    const double gap = num_in == 1 ? kTwoPi : ForwardArc(from, to);
    if (gap > options.empty_gap_angle) empty += gap;
  }
  return empty / kTwoPi;
}

// Steps 2-7 with reference r.
Pass RunPass(const CategorizationOptions& options,
             const ClassPrior* prior,
             int r,
             bool last_pass,
             Work* work,
             CategorizationDiagnostics* diagnostics) {
  Pass pass;
  RelativeRotations(options, r, work);

  const bool use_prior_axis = prior != nullptr &&
                              prior->symmetry != SymmetryType::kAsymmetric &&
                              prior->axis_o.norm() > 0.0;
  const AxisVote vote =
      VoteAxis(options, prior, use_prior_axis, *work, diagnostics);
  if (vote.support < options.min_points) {
    pass.type = SymmetryType::kAsymmetric;  // no second mode
    return pass;
  }

  Eigen::Vector3d axis_o, axis_c;
  FitAxisToInliers(options,
                   use_prior_axis,
                   r,
                   vote.guess,
                   work,
                   diagnostics,
                   &axis_o,
                   &axis_c);
  pass.axis_o = axis_o;
  pass.axis_c = axis_c;
  pass.q_ref = ComputeTwists(r, axis_o, axis_c, work);

  ClusterTwists(options, work, diagnostics);
  const CircularDbscanResult& dbscan = work->dbscan;
  const int num_clusters = static_cast<int>(dbscan.clusters.size());

  if (ReferenceLabel(*work, r) == CircularDbscanResult::kNoiseLabel) {
    // Without any cluster, axis inliers too sparse for DBSCAN are spread
    // around the axis: continuous. Otherwise the reference is an outlier.
    pass.type = num_clusters == 0 && static_cast<int>(work->twist_in.size()) >=
                                         options.min_points
                    ? SymmetryType::kContinuous
                    : SymmetryType::kAsymmetric;
    if (!last_pass && num_clusters > 0) {
      pass.retry = true;
      pass.next_reference = NextReference(*work);
    }
    return pass;
  }

  const ClusterShape shape = MeasureClusters(options, dbscan);
  diagnostics->max_cluster_extent = shape.max_extent;
  diagnostics->min_cluster_separation = shape.min_separation;
  const double empty = EmptyFraction(options, *work);
  diagnostics->empty_fraction = empty;
  const int num_in = static_cast<int>(work->twist_in.size());
  const bool few_noise =
      dbscan.num_noise <= options.max_noise_fraction * num_in;
  if (num_clusters == 1 && shape.all_compact && few_noise) {
    pass.type = SymmetryType::kAsymmetric;
  } else if (num_clusters >= 2 && shape.all_compact && few_noise &&
             shape.separated && empty >= options.min_empty_fraction) {
    pass.type = SymmetryType::kDiscrete;
    if (options.rescue_min_points > 0 && dbscan.num_noise > 0) {
      RescueSmallModes(options, work);
      if (options.merge_close_clusters) {
        MergeCloseClusters(options, &work->dbscan);
      }
    }
  } else {
    pass.type = SymmetryType::kContinuous;
  }
  return pass;
}

// Weighted mean translation of the hypotheses flagged in `in`.
Eigen::Vector3d MeanTranslation(const std::vector<PoseHypothesis>& hypotheses,
                                const std::vector<int>& members,
                                const Work& work) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (int j : members) {
    sum += work.w[j] * hypotheses[j].T_co.t;
    weight += work.w[j];
  }
  return weight > 0.0 ? Eigen::Vector3d(sum / weight)
                      : Eigen::Vector3d(hypotheses[0].T_co.t);
}

// Asymmetric outputs: the inliers are the hypotheses near the mean rotation of
// those near the reference.
void FillAsymmetric(const std::vector<PoseHypothesis>& hypotheses,
                    const CategorizationOptions& options,
                    int r,
                    const Work& work,
                    CategorizedDetection* out) {
  const int n = static_cast<int>(hypotheses.size());
  Eigen::Quaterniond q_mean = work.q[r];
  for (int iteration = 0; iteration < 2; ++iteration) {
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (int j = 0; j < n; ++j) {
      if (!work.usable[j]) continue;
      const Eigen::Quaterniond& q = work.q[j];
      if (RotationAngle(q_mean.conjugate() * q) >
          options.asymmetric_inlier_angle) {
        continue;
      }
      const double sign = q.coeffs().dot(q_mean.coeffs()) < 0.0 ? -1.0 : 1.0;
      sum += sign * work.w[j] * q.coeffs();
    }
    if (sum.norm() > 1e-12) {
      q_mean = Eigen::Quaterniond(sum.normalized());
    }
  }
  out->inliers.clear();
  for (int j = 0; j < n; ++j) {
    if (work.usable[j] && RotationAngle(q_mean.conjugate() * work.q[j]) <=
                              options.asymmetric_inlier_angle) {
      out->inliers.push_back(j);
    }
  }
  if (out->inliers.empty()) {
    out->inliers.push_back(r);
    q_mean = work.q[r];
  }
  out->type = SymmetryType::kAsymmetric;
  out->t_co = MeanTranslation(hypotheses, out->inliers, work);
  out->T_co_base = Rigid3d(q_mean, out->t_co);
  out->axis_o.setZero();
  out->axis_c.setZero();
  out->clusters.clear();
  out->twist.assign(n, 0.0);
}

// Discrete outputs from the last pass's DBSCAN.
void FillDiscrete(const std::vector<PoseHypothesis>& hypotheses,
                  const CategorizationOptions& options,
                  const ClassPrior* prior,
                  int r,
                  const Pass& pass,
                  const Work& work,
                  CategorizedDetection* out) {
  const int n = static_cast<int>(hypotheses.size());
  const CircularDbscanResult& dbscan = work.dbscan;
  const int num_clusters = static_cast<int>(dbscan.clusters.size());
  // Weighted arc mean of every cluster's twists.
  std::vector<double> mean(num_clusters, 0.0);
  std::vector<double> weight(num_clusters, 0.0);
  std::vector<int> label(n, CircularDbscanResult::kNoiseLabel);
  for (int i = 0; i < static_cast<int>(work.twist_owner.size()); ++i) {
    const int c = dbscan.labels[i];
    if (c == CircularDbscanResult::kNoiseLabel) continue;
    const int j = work.twist_owner[i];
    label[j] = c;
    mean[c] += work.w[j] * ForwardArc(dbscan.clusters[c].start, work.psi[j]);
    weight[c] += work.w[j];
  }
  for (int c = 0; c < num_clusters; ++c) {
    mean[c] = WrapToPi(dbscan.clusters[c].start + mean[c] / weight[c]);
  }
  const int c_ref = label[r];
  double offset = mean[c_ref];  // twist of R_base relative to q_ref
  std::vector<double> theta(num_clusters);
  for (int c = 0; c < num_clusters; ++c) {
    theta[c] = WrapToPi(mean[c] - offset);
  }
  theta[c_ref] = 0.0;

  // Class prior order: snap to multiples of 2 pi / order and re-estimate the
  // common offset from every member.
  out->diagnostics.prior_order_snapped = false;
  if (prior != nullptr && prior->symmetry == SymmetryType::kDiscrete &&
      prior->order >= 2) {
    const double step = kTwoPi / prior->order;
    std::vector<int> multiple(num_clusters);
    bool snaps = true;
    for (int c = 0; c < num_clusters && snaps; ++c) {
      multiple[c] = static_cast<int>(std::lround(theta[c] / step));
      snaps =
          std::abs(theta[c] - multiple[c] * step) <= options.prior_snap_angle;
      multiple[c] =
          ((multiple[c] % prior->order) + prior->order) % prior->order;
      for (int d = 0; d < c && snaps; ++d) snaps = multiple[d] != multiple[c];
    }
    if (snaps) {
      double sum = 0.0;
      double total = 0.0;
      for (int j = 0; j < n; ++j) {
        if (label[j] == CircularDbscanResult::kNoiseLabel) continue;
        sum += work.w[j] *
               WrapToPi(work.psi[j] - offset - multiple[label[j]] * step);
        total += work.w[j];
      }
      offset = WrapToPi(offset + sum / total);
      for (int c = 0; c < num_clusters; ++c) {
        theta[c] = WrapToPi(multiple[c] * step);
      }
      out->diagnostics.prior_order_snapped = true;
    }
  }

  const Eigen::Quaterniond q_base =
      (pass.q_ref * Eigen::Quaterniond(Eigen::AngleAxisd(offset, pass.axis_o)))
          .normalized();
  out->twist.resize(n);
  for (int j = 0; j < n; ++j) out->twist[j] = WrapToPi(work.psi[j] - offset);

  // Clusters: the reference's first, the others counter-clockwise.
  std::vector<int> cluster_order(num_clusters);
  for (int c = 0; c < num_clusters; ++c) cluster_order[c] = c;
  std::sort(cluster_order.begin(), cluster_order.end(), [&](int a, int b) {
    const double arc_a = a == c_ref ? -1.0 : ForwardArc(0.0, theta[a]);
    const double arc_b = b == c_ref ? -1.0 : ForwardArc(0.0, theta[b]);
    return arc_a < arc_b;
  });
  out->clusters.resize(num_clusters);
  out->inliers.clear();
  for (int k = 0; k < num_clusters; ++k) {
    const int c = cluster_order[k];
    AngleCluster& cluster = out->clusters[k];
    cluster.theta = theta[c];
    cluster.weight = weight[c];
    cluster.members.clear();
    double sum_sq = 0.0;
    for (int j = 0; j < n; ++j) {
      if (label[j] != c) continue;
      cluster.members.push_back(j);
      const double e = WrapToPi(out->twist[j] - theta[c]);
      sum_sq += work.w[j] * e * e;
    }
    cluster.spread = std::sqrt(sum_sq / weight[c]);
  }
  for (int j = 0; j < n; ++j) {
    if (label[j] != CircularDbscanResult::kNoiseLabel)
      out->inliers.push_back(j);
  }
  out->type = SymmetryType::kDiscrete;
  out->t_co = MeanTranslation(hypotheses, out->inliers, work);
  out->T_co_base = Rigid3d(q_base, out->t_co);
  out->axis_o = pass.axis_o;
  out->axis_c = pass.axis_c;
}

// Continuous outputs: every axis inlier survives.
void FillContinuous(const std::vector<PoseHypothesis>& hypotheses,
                    const Pass& pass,
                    const Work& work,
                    CategorizedDetection* out) {
  const int n = static_cast<int>(hypotheses.size());
  out->inliers.clear();
  for (int j = 0; j < n; ++j) {
    if (work.axis_inlier[j]) out->inliers.push_back(j);
  }
  out->type = SymmetryType::kContinuous;
  out->t_co = MeanTranslation(hypotheses, out->inliers, work);
  out->T_co_base = Rigid3d(pass.q_ref, out->t_co);
  out->axis_o = pass.axis_o;
  out->axis_c = pass.axis_c;
  out->clusters.clear();
  out->twist.assign(work.psi.begin(), work.psi.end());
}

// True when a one-mode detection of a class with `prior` is read with the
// prior's type: the prior is symmetric and knows its axis.
bool ReadsOneModeWithPrior(const CategorizationOptions& options,
                           const ClassPrior* prior) {
  return options.read_one_mode_with_prior && prior != nullptr &&
         prior->symmetry != SymmetryType::kAsymmetric &&
         prior->axis_o.norm() > 0.0;
}

// One mode read with the prior's type, from FillAsymmetric's outputs: the
// mean pose is the base, a_o the prior axis, a_c = R_base a_o, and every
// hypothesis' twist about a_o relative to R_base,
//   twist_j = Twist(R_base^T R_j, a_o).
// Discrete: one cluster at theta = 0 of the inliers, its spread the weighted
// RMS of their twists.
void ReadOneModeWithPrior(const ClassPrior& prior,
                          const Work& work,
                          CategorizedDetection* out) {
  const Eigen::Vector3d a_o = prior.axis_o.normalized();
  const Eigen::Quaterniond& q_base = out->T_co_base.q;
  out->axis_o = a_o;
  out->axis_c = q_base * a_o;
  const int n = static_cast<int>(work.q.size());
  for (int j = 0; j < n; ++j) {
    out->twist[j] = WrapToPi(
        TwistAngle(Eigen::Quaterniond(q_base.conjugate() * work.q[j]), a_o));
  }
  out->type = prior.symmetry;
  out->diagnostics.prior_type_used = true;
  if (prior.symmetry != SymmetryType::kDiscrete) return;
  AngleCluster cluster;
  cluster.members = out->inliers;
  double sum_sq = 0.0;
  for (int j : out->inliers) {
    cluster.weight += work.w[j];
    sum_sq += work.w[j] * out->twist[j] * out->twist[j];
  }
  cluster.spread = std::sqrt(sum_sq / cluster.weight);
  out->clusters.assign(1, cluster);
  // The reference's cluster is clusters[0] (categorize.h).
  out->reference = out->inliers.front();
  for (int j : out->inliers) {
    if (work.w[j] > work.w[out->reference]) out->reference = j;
  }
}

void Reset(CategorizedDetection* out) {
  out->type = SymmetryType::kAsymmetric;
  out->reference = 0;
  out->T_co_base = Rigid3d();
  out->t_co.setZero();
  out->axis_o.setZero();
  out->axis_c.setZero();
  out->clusters.clear();
  out->inliers.clear();
  out->twist.clear();
  out->diagnostics = CategorizationDiagnostics();
}

}  // namespace

Status CategorizationOptions::Validate() const {
  const std::pair<const char*, double> angles[] = {
      {"min_axis_angle", min_axis_angle},
      {"axis_vote_angle", axis_vote_angle},
      {"swing_tolerance", swing_tolerance},
      {"cluster_eps", cluster_eps},
      {"max_cluster_extent", max_cluster_extent},
      {"min_cluster_separation", min_cluster_separation},
      {"empty_gap_angle", empty_gap_angle},
      {"asymmetric_inlier_angle", asymmetric_inlier_angle},
      {"prior_snap_angle", prior_snap_angle}};
  for (const auto& [name, value] : angles) {
    if (!IsAngleIn0Pi(value)) {
      return Status::Error(std::string("categorization options: ") + name +
                           " = " + Deg(value) + " deg is not in (0, 180) deg");
    }
  }
  if (min_points < 1) {
    return Status::Error("categorization options: min_points = " +
                         std::to_string(min_points) + " is below 1");
  }
  if (rescue_min_points < 0) {
    return Status::Error("categorization options: rescue_min_points = " +
                         std::to_string(rescue_min_points) + " is negative");
  }
  if (!(max_noise_fraction >= 0.0 && max_noise_fraction <= 1.0)) {
    return Status::Error("categorization options: max_noise_fraction = " +
                         std::to_string(max_noise_fraction) +
                         " is not in [0, 1]");
  }
  if (!(separation_ratio >= 0.0 && std::isfinite(separation_ratio))) {
    return Status::Error("categorization options: separation_ratio = " +
                         std::to_string(separation_ratio) +
                         " is not finite and >= 0");
  }
  if (!(min_empty_fraction >= 0.0 && min_empty_fraction <= 1.0)) {
    return Status::Error("categorization options: min_empty_fraction = " +
                         std::to_string(min_empty_fraction) +
                         " is not in [0, 1]");
  }
  if (!(translation_gate > 0.0)) {
    return Status::Error("categorization options: translation_gate = " +
                         std::to_string(translation_gate) +
                         " m is not positive");
  }
  return Status::Ok();
}

Status Categorize(const std::vector<PoseHypothesis>& hypotheses,
                  const CategorizationOptions& options,
                  const ClassPrior* prior,
                  CategorizedDetection* out) {
  Reset(out);
  Status status = options.Validate();
  if (!status.ok()) return status;
  if (prior != nullptr) {
    status = prior->Validate();
    if (!status.ok()) return Status::Error("categorize: " + status.message());
  }
  status = ValidateHypotheses(hypotheses);
  if (!status.ok()) return status;

  const int n = static_cast<int>(hypotheses.size());
  Work work;
  work.q.resize(n);
  work.R.resize(n);
  work.w.resize(n);
  for (int j = 0; j < n; ++j) {
    work.q[j] = hypotheses[j].T_co.q.normalized();
    work.R[j] = work.q[j].toRotationMatrix();
    work.w[j] = hypotheses[j].weight;
  }
  GateTranslations(hypotheses, options.translation_gate, &work);

  // Step 1 and at most one retry with a confirmed reference.
  int r = ChooseReference(options, &work);
  Pass pass;
  for (int attempt = 0; attempt < 2; ++attempt) {
    out->diagnostics = CategorizationDiagnostics();
    out->diagnostics.passes = attempt + 1;
    pass = RunPass(options, prior, r, attempt == 1, &work, &out->diagnostics);
    if (!pass.retry) break;
    r = pass.next_reference;
  }
  const bool prior_axis_used = out->diagnostics.prior_axis_used;
  out->reference = r;
  switch (pass.type) {
    case SymmetryType::kAsymmetric:
      FillAsymmetric(hypotheses, options, r, work, out);
      if (ReadsOneModeWithPrior(options, prior)) {
        ReadOneModeWithPrior(*prior, work, out);
      }
      break;
    case SymmetryType::kDiscrete:
      FillDiscrete(hypotheses, options, prior, r, pass, work, out);
      break;
    case SymmetryType::kContinuous:
      FillContinuous(hypotheses, pass, work, out);
      break;
  }
  out->diagnostics.prior_axis_used =
      out->diagnostics.prior_type_used ||
      (prior_axis_used && pass.type != SymmetryType::kAsymmetric);
  return Status::Ok();
}

}  // namespace symba
