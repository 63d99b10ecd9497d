// An object edge with three more rows: where the detection puts the object
// given the camera, weighed along and across its line of sight
// (docs/backend.md "Real detectors", mechanism 8):
//
//   w  = R_wc t_co + t_wc              the detection in the world (m), with
//                                      the camera T_wc held as given
//   u  = R_wc t_co / |t_co|            its line of sight (world, unit)
//   S  = u u^T / s_along + (I - u u^T) / s_across
//   r  = [r_edge; S (t_wo - w)]        (the wrapped edge's rows, then 3)
//
// The three rows depend on the object's position t_wo alone: the camera is
// data here (Refresh sets it), so they place the object from the cameras
// without pulling the cameras. A detector whose errors lie along its lines
// of sight (an image detector's depth) then places the object by
// triangulation: the sight lines of views from around it cross where it is.
// Parameter blocks: the wrapped edge's; t_wo (3) is one of them.
#ifndef SYMBA_FACTORS_LINE_OF_SIGHT_ROWS_H_
#define SYMBA_FACTORS_LINE_OF_SIGHT_ROWS_H_

#include <memory>

#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/max_mixture.h"

namespace symba {

class LineOfSightRows : public ceres::CostFunction, public MixtureWinnerMargin {
 public:
  // `edge`'s parameter block `position_block` is t_wo. `t_co` the measured
  // position (camera frame, m, nonzero), `sigma_along` and `sigma_across`
  // positive (m). The camera is T_wc = (q_wc, t_wc) until Refresh.
  LineOfSightRows(std::unique_ptr<ceres::CostFunction> edge,
                  int position_block,
                  const Eigen::Vector3d& t_co,
                  double sigma_along,
                  double sigma_across,
                  const Eigen::Quaterniond& q_wc,
                  const Eigen::Vector3d& t_wc);

  // Holds the camera at T_wc = (q_wc, t_wc) from now on.
  void Refresh(const Eigen::Quaterniond& q_wc, const Eigen::Vector3d& t_wc);

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override;

  // The wrapped edge's, if it is a max-mixture; otherwise there is no rival.
  bool WinnerMargin(double const* const* parameters,
                    double rival_distance,
                    double* margin,
                    bool* null_won) const override;

  const ceres::CostFunction& edge() const { return *edge_; }
  // The three rows' whitening S and the detection's world position w.
  const Eigen::Matrix3d& sqrt_information() const { return sqrt_info_; }
  const Eigen::Vector3d& world_position() const { return w_; }

 private:
  std::unique_ptr<ceres::CostFunction> edge_;
  int position_block_;
  Eigen::Vector3d t_co_;
  double sigma_along_;
  double sigma_across_;
  Eigen::Matrix3d sqrt_info_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_ = Eigen::Vector3d::Zero();
};

}  // namespace symba

#endif  // SYMBA_FACTORS_LINE_OF_SIGHT_ROWS_H_
