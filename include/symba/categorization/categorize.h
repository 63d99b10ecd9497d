// Categorization of one multi-hypothesis detection (paper Sec. IV-B, method
// notes Sec. 2; the full algorithm with its measurements is in
// docs/categorization.md).
//
// Input: N hypotheses T_co^j = (R_j, t_j) with positive weights w_j. Output:
// the symmetry type and the unambiguous parameters. Conventions:
//
//   axis_o   unit symmetry axis in the object frame. For every inlier j,
//            R_j axis_o ~= axis_c: the axis is the same in the object frame
//            of every hypothesis, whichever mode it shows. Its sign is
//            arbitrary (aligned with the map's axis at association).
//   axis_c   unit axis in the camera frame; axis_c = R_base axis_o exactly.
//   T_co_base = (R_base, t_co), the representative pose ("angle 0"):
//            discrete   the reference hypothesis' cluster, its swing aligned
//                       to axis_c and its twist set to the cluster's mean;
//            continuous the reference hypothesis with its swing aligned;
//            asymmetric the mean rotation of the inliers.
//   theta    a discrete cluster's signed angle (rad, (-pi, pi]) about axis_o
//            such that R_j ~= R_base * Rot(axis_o, theta) for its members
//            (right-multiplied: a rotation of the object about its own axis).
//            The reference's cluster is clusters[0] with theta = 0 exactly.
//            With the backend's R_wo_i = Swing(a_w0 -> a_w) R_base_w
//            Rot(a_o, theta_i), R_base_w = R_wc R_base.
//   twist    per hypothesis, its signed twist about axis_o relative to
//            R_base (the theta it would have alone).
//
// Steps (docs/categorization.md has the equations and every threshold):
//   0. Translation gate: hypotheses farther than translation_gate from the
//      coordinate-wise median translation are outliers.
//   1. Reference r: the highest-weight hypothesis (ties: lowest index) among
//      those with at least min_points hypotheses within min_axis_angle of
//      rotation (itself included); if none has, the highest-weight one.
//   2. omega_j = log(R_r^T R_j), theta_j = |omega_j|.
//   3. Axis votes: rows with theta_j > min_axis_angle; the row whose
//      direction agrees (within axis_vote_angle, up to sign) with the most
//      weight of rows wins. Fewer than min_points votes: no second mode, the
//      detection is asymmetric.
//   4. Axis refinement: (axis_o, axis_c) = the singular pair of
//      B = sum_j w_j R_j nearest the voted axis, which minimises
//      sum_j w_j |R_j axis_o - axis_c|^2; hypotheses whose axis R_j axis_o
//      is more than swing_tolerance from axis_c are outliers; three rounds.
//   5. Signed twists psi_j of R_ref^T R_j about axis_o (R_ref = R_r with
//      its swing aligned to axis_c).
//   6. Circular DBSCAN (cluster_eps, min_points) of the axis inliers' psi_j;
//      neighbouring clusters closer than min_cluster_separation whose union
//      is compact are merged (one mode split by noise).
//   7. Decision. The reference must be in a cluster; if it is not, the
//      highest-weight member of the largest cluster becomes the reference
//      and steps 2-7 run once more. Then: one compact cluster holding all
//      but max_noise_fraction of the axis inliers -> asymmetric; >= 2
//      compact clusters, pairwise separated, little noise and at least
//      min_empty_fraction of the circle in wide empty gaps -> discrete
//      (then small modes are rescued from the DBSCAN noise); otherwise
//      continuous.
//   8. Outputs: inliers (cluster members / axis inliers / hypotheses near
//      the mean pose), t_co = their weighted mean translation, base pose,
//      cluster angles as weighted arc means of the members' twists.
//
// A class prior (log header `classes`) can refine the result: a prior axis
// replaces the voted axis, and a discrete order snaps the cluster angles to
// multiples of 2 pi / order. The type comes from the hypotheses, with one
// exception (read_one_mode_with_prior): hypotheses that show one mode (N = 1
// included: a single-pose detector) of a class whose prior is discrete or
// continuous with an axis are read with the prior's type, so that the next
// frame's flip to another symmetric pose is no contradiction. Then
//   axis_o = prior axis (unit), T_co_base = the asymmetric mean pose,
//   axis_c = R_base axis_o, discrete: one cluster at theta = 0 holding the
//   inliers, whose highest-weight member is then the reference (the
//   backend reads its angle modulo 2 pi / order when the prior gives the
//   order; without one a flip opens a new angle).
#ifndef SYMBA_CATEGORIZATION_CATEGORIZE_H_
#define SYMBA_CATEGORIZATION_CATEGORIZE_H_

#include <vector>

#include <Eigen/Core>

#include "symba/categorization/categorization_options.h"
#include "symba/categorization/class_prior.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/detection/pose_hypothesis.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// One mode of a discrete detection.
struct AngleCluster {
  double theta = 0.0;        // rad, (-pi, pi]; see the header comment
  double spread = 0.0;       // weighted RMS of member twists about theta, rad
  double weight = 0.0;       // sum of the members' weights
  std::vector<int> members;  // hypothesis indices, ascending
};

// Numbers behind the decision, for diagnostics and the benchmark.
struct CategorizationDiagnostics {
  int passes = 0;            // 1, or 2 when the first reference was an outlier
  double axis_support = 0;   // weight of the axis votes (step 3)
  int num_axis_inliers = 0;  // step 4
  int num_raw_clusters = 0;  // DBSCAN clusters (step 6)
  int num_noise = 0;         // DBSCAN noise among the axis inliers
  double max_cluster_extent = 0;      // rad
  double min_cluster_separation = 0;  // rad; 0 with fewer than 2 clusters
  double empty_fraction = 0;          // share of the circle in wide gaps
  bool prior_axis_used = false;
  bool prior_order_snapped = false;
  bool prior_type_used = false;  // one mode read with the prior's type
};

struct CategorizedDetection {
  SymmetryType type = SymmetryType::kAsymmetric;
  int reference = 0;  // index of the reference hypothesis
  Rigid3d T_co_base;  // representative pose, see the header comment
  Eigen::Vector3d t_co = Eigen::Vector3d::Zero();    // = T_co_base.t
  Eigen::Vector3d axis_o = Eigen::Vector3d::Zero();  // zero if asymmetric
  Eigen::Vector3d axis_c = Eigen::Vector3d::Zero();  // zero if asymmetric
  std::vector<AngleCluster> clusters;  // discrete only; [0] is the reference's
  std::vector<int> inliers;            // surviving hypotheses, ascending
  std::vector<double> twist;           // per hypothesis (0 if asymmetric), rad
  CategorizationDiagnostics diagnostics;
};

// Categorizes one detection. `prior` may be null. On success fills `out`
// (its vectors are reused). Returns an error, naming the hypothesis and what
// is wrong, for an empty set, a non-finite or non-unit (|1 - |q|| > 1e-3)
// quaternion, a non-finite translation, a weight that is not positive and
// finite, invalid options (CategorizationOptions::Validate) or an invalid
// prior (ClassPrior::Validate); `out` is then reset.
Status Categorize(const std::vector<PoseHypothesis>& hypotheses,
                  const CategorizationOptions& options,
                  const ClassPrior* prior,
                  CategorizedDetection* out);

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CATEGORIZE_H_
