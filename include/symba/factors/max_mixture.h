// MaxMixtureCostFunction: a max-mixture of Gaussian components (Olson and
// Agarwal, IJRR 2013) as one Ceres cost function (docs/method.md, Eq. 11-13).
//
// Component j has a whitened residual r_j = L_j e_j(x) (the model's rows) and
// weight w_j (normalised so that sum_j w_j = 1). Its negative log-likelihood,
// up to a constant shared by all components, is
//
//   c_j(x) = 0.5 |r_j(x)|^2 + k_j,        k_j = -log(w_j |det L_j|)
//
// The max-mixture keeps the most likely component, j* = argmin_j c_j(x),
// re-selected at every evaluation. In least squares it is realised as the
// winner's residual plus one normalisation row:
//
//   residual(x) = [ r_j*(x) ; sqrt(2 (k_j* - k_min)) ],  k_min = min_j k_j
//   0.5 |residual|^2 = c_j*(x) - k_min
//
// so a less likely component pays its log-likelihood handicap and the cost is
// continuous where the winner switches. The normalisation row does not depend
// on x (its Jacobian row is zero).
//
// Optional null hypothesis (MixtureOptions): a component with weight w_0 and
// covariance inflated by sigma_scale^2 around the nearest component (the one
// with the smallest |r_j|): r_0 = r_near / sigma_scale, k_0 = -log(w_0) -
// log|det L_near| + d log(sigma_scale), d = the model's mixture rows. It bounds
// the pull of a wrong association.
//
// Speed: the winner is chosen in plain doubles through the model's
// MixtureSquaredNorm (no Jets); only the winner's cost function (the model's
// Component(j), with hand-written or automatic Jacobians) computes Jacobians.
// A model may also give a cheap lower bound of |r_j|^2; a component whose
// bound shows that it can neither win nor be the nearest one is then skipped
// without its exact norm. This never changes the selection (the bound never
// exceeds the computed norm, and rounding is monotone). Evaluate allocates
// nothing.
//
// A Model provides (see pose_mixture_model.h and asymmetric_object_edge.h
// for an example):
//   static constexpr int kNumResiduals;  rows of one component
//   static constexpr int kMixtureRows;   leading rows that differ per component
//   struct Prepared;                     per-evaluation shared doubles
//   int NumComponents() const;
//   double Weight(int j) const;          > 0
//   double LogDetSqrtInfo(int j) const;  log |det L_j| of the mixture rows
//   bool Prepare(double const* const* parameters, Prepared*) const;
//   double MixtureSquaredNorm(const Prepared&, int j) const;  |r_j|^2
//   const ceres::CostFunction& Component(int j) const;  all rows, Jacobians
// and optionally
//   double MixtureSquaredNormLowerBound(const Prepared&, int j) const;
//     any value <= MixtureSquaredNorm(prepared, j) as computed
// Rows past kMixtureRows are shared by all components (e.g. the continuous
// edge's axis term) and are not scaled by the null hypothesis.
#ifndef SYMBA_FACTORS_MAX_MIXTURE_H_
#define SYMBA_FACTORS_MAX_MIXTURE_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include <ceres/sized_cost_function.h>
#include <Eigen/Core>

#include "symba/factors/mixture_options.h"

namespace symba {

// Which component a max-mixture picked at some parameters.
struct MixtureSelection {
  int component = -1;         // the hypothesis index (the nearest for null)
  bool is_null = false;       // the null hypothesis won
  double log_normalizer = 0;  // k of the winner
  double cost = 0;            // c of the winner, before subtracting k_min
};

// Whether Model has MixtureSquaredNormLowerBound (see above).
template <typename Model, typename = void>
struct HasMixtureLowerBound : std::false_type {};
template <typename Model>
struct HasMixtureLowerBound<
    Model,
    std::void_t<
        decltype(std::declval<const Model&>().MixtureSquaredNormLowerBound(
            std::declval<const typename Model::Prepared&>(), 0))>>
    : std::true_type {};

// How clearly a max-mixture's winner wins at some parameters, for deciding
// whether the edge can be linearised once and for all (marginalisation,
// docs/backend.md "The window"). Not used in the solves.
class MixtureWinnerMargin {
 public:
  virtual ~MixtureWinnerMargin() = default;
  // margin: the best rival's cost c_j minus the winner's (infinity when
  // there is no rival). A rival is a component whose whitened residual at
  // `parameters` differs from the winner's by more than rival_distance
  // (Euclidean norm, each residual whitened by its own component): a
  // component that close is taken as part of the winner's mode, not as a
  // competing one. null_won: the null hypothesis won. False when the model
  // cannot evaluate there.
  virtual bool WinnerMargin(double const* const* parameters,
                            double rival_distance,
                            double* margin,
                            bool* null_won) const = 0;
};

template <typename Model, int... kBlockSizes>
class MaxMixtureCostFunction final
    : public ceres::SizedCostFunction<Model::kNumResiduals + 1, kBlockSizes...>,
      public MixtureWinnerMargin {
 public:
  static constexpr int kNumResiduals = Model::kNumResiduals + 1;
  static constexpr int kMixtureRows = Model::kMixtureRows;
  static constexpr int kBlockSizeArray[] = {kBlockSizes...};
  static_assert(kMixtureRows <= Model::kNumResiduals,
                "mixture rows must lead the component's rows");

  // The model must have at least one component with positive weights and
  // finite log-determinants (the edges' Create functions validate this).
  MaxMixtureCostFunction(Model model, const MixtureOptions& options)
      : model_(std::move(model)), options_(options) {
    const int n = model_.NumComponents();
    double weight_sum = 0.0;
    for (int j = 0; j < n; ++j) weight_sum += model_.Weight(j);
    log_normalizers_.resize(n);
    min_log_normalizer_ = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j) {
      log_normalizers_[j] =
          -std::log(model_.Weight(j) / weight_sum) - model_.LogDetSqrtInfo(j);
      min_log_normalizer_ = std::min(min_log_normalizer_, log_normalizers_[j]);
      if (options_.use_null_hypothesis) {
        min_log_normalizer_ = std::min(min_log_normalizer_, NullNormalizer(j));
      }
    }
  }

  const Model& model() const { return model_; }

  // The winning component at `parameters`, chosen in doubles. Returns false
  // when the model cannot evaluate there (e.g. non-finite parameters).
  bool Select(double const* const* parameters,
              MixtureSelection* selection) const {
    typename Model::Prepared prepared;
    if (!model_.Prepare(parameters, &prepared)) return false;
    double best_cost = std::numeric_limits<double>::infinity();
    double nearest_squared_norm = std::numeric_limits<double>::infinity();
    int best = -1;
    int nearest = -1;
    const bool use_null = options_.use_null_hypothesis;
    const int n = model_.NumComponents();
    for (int j = 0; j < n; ++j) {
      if constexpr (HasMixtureLowerBound<Model>::value) {
        // The exact norm is >= bound, so j cannot win (strictly worse than
        // the best so far) and cannot be the nearest: skip it.
        if (best >= 0) {
          const double bound = model_.MixtureSquaredNormLowerBound(prepared, j);
          if (0.5 * bound + log_normalizers_[j] > best_cost &&
              (!use_null || bound > nearest_squared_norm)) {
            continue;
          }
        }
      }
      const double squared_norm = model_.MixtureSquaredNorm(prepared, j);
      const double cost = 0.5 * squared_norm + log_normalizers_[j];
      if (cost < best_cost) {
        best_cost = cost;
        best = j;
      }
      if (use_null && squared_norm < nearest_squared_norm) {
        nearest_squared_norm = squared_norm;
        nearest = j;
      }
    }
    if (best < 0 || !std::isfinite(best_cost)) return false;
    selection->component = best;
    selection->is_null = false;
    selection->log_normalizer = log_normalizers_[best];
    selection->cost = best_cost;
    if (use_null && nearest >= 0) {
      const double scale = 1.0 / options_.null_sigma_scale;
      const double null_cost =
          0.5 * scale * scale * nearest_squared_norm + NullNormalizer(nearest);
      if (null_cost < best_cost) {
        selection->component = nearest;
        selection->is_null = true;
        selection->log_normalizer = NullNormalizer(nearest);
        selection->cost = null_cost;
      }
    }
    return true;
  }

  // Every component's cost, without the bound's shortcut.
  bool WinnerMargin(double const* const* parameters,
                    double rival_distance,
                    double* margin,
                    bool* null_won) const override {
    MixtureSelection selection;
    if (!Select(parameters, &selection)) return false;
    *null_won = selection.is_null;
    typename Model::Prepared prepared;
    if (!model_.Prepare(parameters, &prepared)) return false;
    using Residual = Eigen::Matrix<double, Model::kNumResiduals, 1>;
    Residual winner;
    if (!model_.Component(selection.component)
             .Evaluate(parameters, winner.data(), nullptr)) {
      return false;
    }
    const double rival_squared = rival_distance * rival_distance;
    double runner_up = std::numeric_limits<double>::infinity();
    for (int j = 0; j < model_.NumComponents(); ++j) {
      if (j == selection.component) continue;
      const double cost =
          0.5 * model_.MixtureSquaredNorm(prepared, j) + log_normalizers_[j];
      if (cost >= runner_up) continue;
      Residual other;
      if (!model_.Component(j).Evaluate(parameters, other.data(), nullptr)) {
        return false;
      }
      if ((other - winner).squaredNorm() > rival_squared) runner_up = cost;
    }
    *margin = runner_up - selection.cost;
    return true;
  }

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    MixtureSelection selection;
    if (!Select(parameters, &selection)) return false;
    if (!model_.Component(selection.component)
             .Evaluate(parameters, residuals, jacobians)) {
      return false;
    }
    if (selection.is_null) ScaleMixtureRows(residuals, jacobians);
    residuals[kNumResiduals - 1] = std::sqrt(
        2.0 * std::max(0.0, selection.log_normalizer - min_log_normalizer_));
    if (jacobians != nullptr) {
      for (int b = 0; b < static_cast<int>(sizeof...(kBlockSizes)); ++b) {
        if (jacobians[b] == nullptr) continue;
        const int size = kBlockSizeArray[b];
        std::fill_n(jacobians[b] + (kNumResiduals - 1) * size, size, 0.0);
      }
    }
    return true;
  }

 private:
  double NullNormalizer(int j) const {
    return -std::log(options_.null_weight) - model_.LogDetSqrtInfo(j) +
           kMixtureRows * std::log(options_.null_sigma_scale);
  }

  void ScaleMixtureRows(double* residuals, double** jacobians) const {
    const double scale = 1.0 / options_.null_sigma_scale;
    for (int i = 0; i < kMixtureRows; ++i) residuals[i] *= scale;
    if (jacobians == nullptr) return;
    for (int b = 0; b < static_cast<int>(sizeof...(kBlockSizes)); ++b) {
      if (jacobians[b] == nullptr) continue;
      const int size = kBlockSizeArray[b];
      for (int i = 0; i < kMixtureRows * size; ++i) jacobians[b][i] *= scale;
    }
  }

  Model model_;
  MixtureOptions options_;
  std::vector<double> log_normalizers_;
  double min_log_normalizer_ = 0.0;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_MAX_MIXTURE_H_
