// An object edge with rows along and across its line of sight
// (line_of_sight_rows.h).
#include "symba/factors/line_of_sight_rows.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "symba/common/check.h"

namespace symba {

LineOfSightRows::LineOfSightRows(std::unique_ptr<ceres::CostFunction> edge,
                                 int position_block,
                                 const Eigen::Vector3d& t_co,
                                 double sigma_along,
                                 double sigma_across,
                                 const Eigen::Quaterniond& q_wc,
                                 const Eigen::Vector3d& t_wc)
    : edge_(std::move(edge)),
      position_block_(position_block),
      t_co_(t_co),
      sigma_along_(sigma_along),
      sigma_across_(sigma_across) {
  *mutable_parameter_block_sizes() = edge_->parameter_block_sizes();
  SYMBA_CHECK(position_block_ >= 0 &&
              position_block_ <
                  static_cast<int>(parameter_block_sizes().size()) &&
              parameter_block_sizes()[position_block_] == 3);
  set_num_residuals(edge_->num_residuals() + 3);
  Refresh(q_wc, t_wc);
}

void LineOfSightRows::Refresh(const Eigen::Quaterniond& q_wc,
                              const Eigen::Vector3d& t_wc) {
  const Eigen::Vector3d sight = q_wc.normalized() * t_co_;
  w_ = sight + t_wc;
  const Eigen::Vector3d u = sight.normalized();
  const Eigen::Matrix3d along = u * u.transpose();
  sqrt_info_ = along / sigma_along_ +
               (Eigen::Matrix3d::Identity() - along) / sigma_across_;
}

bool LineOfSightRows::Evaluate(double const* const* parameters,
                               double* residuals,
                               double** jacobians) const {
  // The wrapped rows come first; a row-major Jacobian's first rows are
  // where the wrapped edge writes them.
  if (!edge_->Evaluate(parameters, residuals, jacobians)) return false;
  const int n = edge_->num_residuals();
  const Eigen::Map<const Eigen::Vector3d> t_wo(parameters[position_block_]);
  Eigen::Map<Eigen::Vector3d>(residuals + n) = sqrt_info_ * (t_wo - w_);
  if (jacobians == nullptr) return true;
  const std::vector<int32_t>& sizes = parameter_block_sizes();
  for (size_t b = 0; b < sizes.size(); ++b) {
    if (jacobians[b] == nullptr) continue;
    double* rows = jacobians[b] + static_cast<size_t>(n) * sizes[b];
    std::fill(rows, rows + 3 * sizes[b], 0.0);
    if (static_cast<int>(b) == position_block_) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> position(rows);
      position = sqrt_info_;
    }
  }
  return true;
}

bool LineOfSightRows::WinnerMargin(double const* const* parameters,
                                   double rival_distance,
                                   double* margin,
                                   bool* null_won) const {
  const auto* mixture = dynamic_cast<const MixtureWinnerMargin*>(edge_.get());
  if (mixture != nullptr) {
    return mixture->WinnerMargin(parameters, rival_distance, margin, null_won);
  }
  *margin = std::numeric_limits<double>::infinity();
  *null_won = false;
  return true;
}

}  // namespace symba
