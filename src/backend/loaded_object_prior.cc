#include "backend/loaded_object_prior.h"

#include <utility>
#include <vector>

#include <Eigen/Cholesky>

#include "symba/factors/marginal_prior_factor.h"
#include "symba/geometry/tangent_basis.h"

namespace symba::internal {
namespace {

// The blocks of the prior with their tangent information, collected group
// by group.
struct PriorGroups {
  std::vector<PriorBlock> blocks;
  std::vector<double*> pointers;
  std::vector<Eigen::MatrixXd> information;

  // Adds the group if `covariance` is positive definite.
  void Add(PriorBlockKind kind,
           double* block,
           int ambient,
           const Eigen::MatrixXd& covariance) {
    if (!covariance.allFinite()) return;
    const Eigen::LLT<Eigen::MatrixXd> llt(covariance);
    if (llt.info() != Eigen::Success) return;
    const Eigen::MatrixXd inverse = llt.solve(
        Eigen::MatrixXd::Identity(covariance.rows(), covariance.cols()));
    if (!inverse.allFinite()) return;
    blocks.push_back({kind, Eigen::Map<const Eigen::VectorXd>(block, ambient)});
    pointers.push_back(block);
    information.push_back(inverse);
  }

  int TangentSize() const {
    int size = 0;
    for (const Eigen::MatrixXd& m : information) size += m.rows();
    return size;
  }
};

}  // namespace

bool MakeLoadedObjectPrior(int o,
                           ObjectState* object,
                           const MapObjectCovariance& covariance,
                           FactorRecord* record) {
  PriorGroups groups;
  groups.Add(PriorBlockKind::kEuclidean, object->t, 3, covariance.position);
  if (object->type == SymmetryType::kAsymmetric) {
    if (covariance.rotation) {
      groups.Add(
          PriorBlockKind::kQuaternion, object->q, 4, *covariance.rotation / 4);
    }
  } else if (covariance.axis) {
    const Eigen::Matrix<double, 3, 2> B =
        TangentBasis(Eigen::Vector3d(object->axis_w()));
    groups.Add(PriorBlockKind::kUnitAxis,
               object->a_w,
               3,
               B.transpose() * *covariance.axis * B);
  }
  for (size_t i = 0;
       i < object->thetas.size() && i < covariance.angle_variances.size();
       ++i) {
    if (!covariance.angle_variances[i]) continue;
    groups.Add(PriorBlockKind::kEuclidean,
               object->thetas[i].get(),
               1,
               Eigen::MatrixXd::Constant(1, 1, *covariance.angle_variances[i]));
  }
  if (groups.blocks.empty()) return false;
  const int n = groups.TangentSize();
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(n, n);
  int offset = 0;
  for (const Eigen::MatrixXd& m : groups.information) {
    information.block(offset, offset, m.rows(), m.cols()) = m;
    offset += static_cast<int>(m.rows());
  }
  // A = U with U^T U = information, so that |A d|^2 = d^T information d.
  const Eigen::MatrixXd A =
      Eigen::LLT<Eigen::MatrixXd>(information).matrixU().toDenseMatrix();
  std::unique_ptr<MarginalPriorFactor> factor;
  const Status status = MarginalPriorFactor::Create(
      groups.blocks, A, Eigen::VectorXd::Zero(n), &factor);
  if (!status.ok()) return false;
  record->cost = std::move(factor);
  record->blocks = std::move(groups.pointers);
  record->object = o;
  return true;
}

}  // namespace symba::internal
