// The categorization's entry points: the checks, then the stages of
// docs/categorization.md in order. Each stage lives in the file its name
// says (src/categorization/):
//   hypothesis_set      step 0, the checked, gated hypotheses
//   reference_choice    step 1
//   symmetry_axis       steps 2-4
//   signed_twists       step 5
//   twist_clusters      step 6 and the rescue of small modes
//   symmetry_decision   step 7
//   categorization_pass steps 2-7 with one reference
//   asymmetric_result, discrete_result, continuous_result   step 8
//   one_mode_with_prior the class prior's reading of one mode
// and the checks: categorization_options (CategorizationOptions::Validate),
// class_prior (ClassPrior::Validate), hypothesis_set (the hypotheses).
#include "symba/categorization/categorize.h"

#include <optional>

#include "categorization/asymmetric_result.h"
#include "categorization/categorization_pass.h"
#include "categorization/categorize_with_valid_options.h"
#include "categorization/continuous_result.h"
#include "categorization/discrete_result.h"
#include "categorization/hypothesis_set.h"
#include "categorization/one_mode_with_prior.h"
#include "categorization/reference_choice.h"

namespace symba {
namespace {

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

// The prior's axis (unit) when it replaces the voted one: a symmetric prior
// with a non-zero axis.
std::optional<Eigen::Vector3d> PriorAxis(const ClassPrior* prior) {
  if (prior != nullptr && prior->symmetry != SymmetryType::kAsymmetric &&
      prior->axis_o.norm() > 0.0) {
    return prior->axis_o.normalized();
  }
  return std::nullopt;
}

}  // namespace

namespace categorization {

Status CategorizeWithValidOptions(const std::vector<PoseHypothesis>& hypotheses,
                                  const CategorizationOptions& options,
                                  const ClassPrior* prior,
                                  CategorizedDetection* out) {
  Reset(out);
  const Status status = ValidateHypotheses(hypotheses);
  if (!status.ok()) return status;
  const HypothesisSet set =
      MakeHypothesisSet(hypotheses, options.translation_gate);
  const std::optional<Eigen::Vector3d> prior_axis = PriorAxis(prior);

  // Step 1 and at most one retry with a confirmed reference.
  int r = ChooseReference(set, options.min_axis_angle, options.min_points);
  Pass pass = RunPass(set, options, prior_axis, r, /*may_retry=*/true);
  int passes = 1;
  if (pass.retry) {
    r = pass.next_reference;
    pass = RunPass(set, options, prior_axis, r, /*may_retry=*/false);
    passes = 2;
  }
  out->diagnostics = pass.diagnostics;
  out->diagnostics.passes = passes;
  out->reference = r;
  switch (pass.type) {
    case SymmetryType::kAsymmetric:
      AssembleAsymmetric(set, options.asymmetric_inlier_angle, r, out);
      if (ReadsOneModeWithPrior(options, prior)) {
        ReadOneModeWithPrior(*prior, set, out);
      }
      break;
    case SymmetryType::kDiscrete:
      AssembleDiscrete(set, pass, r, prior, options.prior_snap_angle, out);
      break;
    case SymmetryType::kContinuous:
      AssembleContinuous(set, pass, out);
      break;
  }
  out->diagnostics.prior_axis_used = out->diagnostics.prior_type_used ||
                                     (pass.diagnostics.prior_axis_used &&
                                      pass.type != SymmetryType::kAsymmetric);
  return Status::Ok();
}

}  // namespace categorization

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
  return categorization::CategorizeWithValidOptions(
      hypotheses, options, prior, out);
}

}  // namespace symba
