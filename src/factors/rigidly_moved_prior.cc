#include "symba/factors/rigidly_moved_prior.h"

#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "symba/geometry/tangent_basis.h"

namespace symba {
namespace {

// The block moved by `motion` and the map J of its tangent difference; an
// error if the role does not fit the block.
Status MoveBlock(const PriorBlock& block,
                 const RigidBlockMotion& motion,
                 PriorBlock* moved,
                 Eigen::MatrixXd* J) {
  const Eigen::Matrix3d R = motion.W.q.normalized().toRotationMatrix();
  const int tangent = PriorBlockTangentSize(block);
  *moved = block;
  *J = Eigen::MatrixXd::Identity(tangent, tangent);
  switch (motion.role) {
    case RigidBlockRole::kUnmoved:
      return Status::Ok();
    case RigidBlockRole::kPosition:
      if (block.kind != PriorBlockKind::kEuclidean || block.x0.size() != 3) {
        return Status::Error("a moved position must be a 3-vector block");
      }
      moved->x0 = R * block.x0 + motion.W.t;
      *J = R;
      return Status::Ok();
    case RigidBlockRole::kRotation: {
      if (block.kind != PriorBlockKind::kQuaternion) {
        return Status::Error("a moved rotation must be a quaternion block");
      }
      const Eigen::Quaterniond q0(Eigen::Vector4d(block.x0));
      const Eigen::Quaterniond q = (motion.W.q.normalized() * q0).normalized();
      moved->x0 = q.coeffs();
      *J = R;
      return Status::Ok();
    }
    case RigidBlockRole::kAxis: {
      if (block.kind != PriorBlockKind::kUnitAxis) {
        return Status::Error("a moved axis must be a unit-axis block");
      }
      const Eigen::Vector3d a0 = block.x0;
      const Eigen::Vector3d a = (R * a0).normalized();
      moved->x0 = a;
      *J = TangentBasis(a).transpose() * R * TangentBasis(a0);
      return Status::Ok();
    }
  }
  return Status::Error("unknown block role");
}

}  // namespace

Status MovePriorRigidly(const MarginalPriorFactor& prior,
                        const std::vector<RigidBlockMotion>& motions,
                        std::unique_ptr<MarginalPriorFactor>* moved) {
  const std::vector<PriorBlock>& blocks = prior.blocks();
  if (motions.size() != blocks.size()) {
    return Status::Error("one motion per prior block is needed");
  }
  std::vector<PriorBlock> moved_blocks(blocks.size());
  Eigen::MatrixXd A = prior.A();
  int offset = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    Eigen::MatrixXd J;
    Status status = MoveBlock(blocks[b], motions[b], &moved_blocks[b], &J);
    if (!status.ok()) {
      return Status::Error("prior block " + std::to_string(b) + ": " +
                           status.message());
    }
    // d' = J d with J orthogonal: A' d' = A d needs A' = A J^T.
    const int n = static_cast<int>(J.rows());
    A.middleCols(offset, n) = prior.A().middleCols(offset, n) * J.transpose();
    offset += n;
  }
  return MarginalPriorFactor::Create(
      std::move(moved_blocks), std::move(A), prior.e(), moved);
}

}  // namespace symba
