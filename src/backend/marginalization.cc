#include "backend/marginalization.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include <Eigen/Eigenvalues>

#include "symba/factors/max_mixture.h"
#include "symba/manifolds/axis_manifold.h"

namespace symba::internal {
namespace {

using RowMajorMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Slot {
  double* block = nullptr;
  int ambient = 0;
  int tangent = 0;
  BlockDescription description;
  int offset = -1;  // tangent column; -1 for a constant block
};

// One evaluated term: whitened, loss-corrected residual and the tangent
// Jacobian of each non-constant block.
struct LinearTerm {
  Eigen::VectorXd r;
  std::vector<int> slots;
  std::vector<Eigen::MatrixXd> J;  // r.size() x tangent, per slot
};

Status KindOf(const ceres::Manifold* manifold, PriorBlockKind* kind) {
  if (manifold == nullptr) {
    *kind = PriorBlockKind::kEuclidean;
  } else if (dynamic_cast<const ceres::EigenQuaternionManifold*>(manifold)) {
    *kind = PriorBlockKind::kQuaternion;
  } else if (dynamic_cast<const AxisManifold*>(manifold)) {
    *kind = PriorBlockKind::kUnitAxis;
  } else {
    return Status::Error(
        "marginalisation: a block's manifold has no prior tangent");
  }
  return Status::Ok();
}

// The Triggs correction (see the header) applied in place.
void CorrectForLoss(const ceres::LossFunction& loss,
                    Eigen::VectorXd* r,
                    std::vector<RowMajorMatrix>* J) {
  const double s = r->squaredNorm();
  double rho[3];
  loss.Evaluate(s, rho);
  const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
  double residual_scaling = sqrt_rho1;
  double alpha_sq_norm = 0.0;
  if (s > 0.0 && rho[2] > 0.0 && rho[1] > 0.0) {
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
    residual_scaling = sqrt_rho1 / (1.0 - alpha);
    alpha_sq_norm = alpha / s;
  }
  for (RowMajorMatrix& j : *J) {
    if (j.size() == 0) continue;
    if (alpha_sq_norm != 0.0) {
      const Eigen::RowVectorXd rTJ = r->transpose() * j;
      j -= alpha_sq_norm * (*r) * rTJ;
    }
    j *= sqrt_rho1;
  }
  *r *= residual_scaling;
}

// Whether a max-mixture's winner is clear enough to be frozen.
bool ClearWinner(const ceres::CostFunction& cost,
                 const std::vector<double*>& blocks,
                 const MarginalizationOptions& options) {
  const auto* mixture = dynamic_cast<const MixtureWinnerMargin*>(&cost);
  if (mixture == nullptr) return true;
  double margin = 0.0;
  bool null_won = false;
  return mixture->WinnerMargin(
             blocks.data(), options.rival_distance, &margin, &null_won) &&
         !null_won && margin >= options.min_winner_margin;
}

class Linearizer {
 public:
  explicit Linearizer(const BlockDescriber& describe) : describe_(describe) {}

  int SlotOf(double* block, int ambient) {
    const auto it = index_.find(block);
    if (it != index_.end()) return it->second;
    Slot slot;
    slot.block = block;
    slot.ambient = ambient;
    slot.description = describe_(block);
    slot.tangent = slot.description.manifold
                       ? slot.description.manifold->TangentSize()
                       : ambient;
    slots_.push_back(slot);
    index_.emplace(block, static_cast<int>(slots_.size()) - 1);
    return static_cast<int>(slots_.size()) - 1;
  }

  // False if the term cannot be evaluated to finite values.
  bool Linearize(const MarginalizationTerm& term, LinearTerm* out) {
    const ceres::CostFunction& cost = *term.cost;
    const int m = cost.num_residuals();
    const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
    std::vector<int> slots;
    for (size_t b = 0; b < term.blocks.size(); ++b) {
      slots.push_back(SlotOf(term.blocks[b], sizes[b]));
    }
    std::vector<RowMajorMatrix> J_ambient(term.blocks.size());
    std::vector<double*> jacobian_pointers(term.blocks.size(), nullptr);
    for (size_t b = 0; b < term.blocks.size(); ++b) {
      if (slots_[slots[b]].description.role == BlockRole::kConstant) continue;
      J_ambient[b].resize(m, sizes[b]);
      jacobian_pointers[b] = J_ambient[b].data();
    }
    Eigen::VectorXd r(m);
    if (!cost.Evaluate(
            term.blocks.data(), r.data(), jacobian_pointers.data())) {
      return false;
    }
    if (!r.allFinite()) return false;
    for (const RowMajorMatrix& j : J_ambient) {
      if (!j.allFinite()) return false;
    }
    if (term.loss != nullptr) CorrectForLoss(*term.loss, &r, &J_ambient);
    if (term.weight != 1.0) {
      const double scale = std::sqrt(term.weight);
      r *= scale;
      for (RowMajorMatrix& j : J_ambient) j *= scale;
    }
    out->r = std::move(r);
    out->slots.clear();
    out->J.clear();
    for (size_t b = 0; b < term.blocks.size(); ++b) {
      const Slot& slot = slots_[slots[b]];
      if (slot.description.role == BlockRole::kConstant) continue;
      out->slots.push_back(slots[b]);
      out->J.push_back(TangentJacobian(slot, J_ambient[b]));
    }
    return true;
  }

  std::vector<Slot>& slots() { return slots_; }

 private:
  static Eigen::MatrixXd TangentJacobian(const Slot& slot,
                                         const RowMajorMatrix& J) {
    if (slot.description.manifold == nullptr) return J;
    RowMajorMatrix plus(slot.ambient, slot.tangent);
    slot.description.manifold->PlusJacobian(slot.block, plus.data());
    return J * plus;
  }

  const BlockDescriber& describe_;
  std::vector<Slot> slots_;
  std::unordered_map<const double*, int> index_;
};

// Eigenvalues of a symmetric matrix below threshold * the largest are zero.
struct Spectrum {
  Eigen::VectorXd values;   // kept eigenvalues (> 0)
  Eigen::MatrixXd vectors;  // their eigenvectors (columns)
};

Spectrum PositiveSpectrum(const Eigen::MatrixXd& S, double threshold) {
  Spectrum spectrum;
  if (S.rows() == 0) return spectrum;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(S);
  const Eigen::VectorXd& values = solver.eigenvalues();
  const double cutoff = threshold * std::max(values.maxCoeff(), 0.0);
  std::vector<int> kept;
  for (int i = 0; i < values.size(); ++i) {
    if (values[i] > cutoff && values[i] > 0.0) kept.push_back(i);
  }
  spectrum.values.resize(static_cast<int>(kept.size()));
  spectrum.vectors.resize(S.rows(), static_cast<int>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i) {
    spectrum.values[static_cast<int>(i)] = values[kept[i]];
    spectrum.vectors.col(static_cast<int>(i)) =
        solver.eigenvectors().col(kept[i]);
  }
  return spectrum;
}

}  // namespace

Status Marginalize(const std::vector<MarginalizationTerm>& terms,
                   const BlockDescriber& describe,
                   const MarginalizationOptions& options,
                   MarginalizationResult* result) {
  *result = MarginalizationResult();
  Linearizer linearizer(describe);
  std::vector<LinearTerm> linear;
  for (const MarginalizationTerm& term : terms) {
    if (!ClearWinner(*term.cost, term.blocks, options)) {
      ++result->ambiguous;
      continue;
    }
    LinearTerm lt;
    if (!linearizer.Linearize(term, &lt)) {
      ++result->failed;
      continue;
    }
    linear.push_back(std::move(lt));
  }
  result->linearized = static_cast<int>(linear.size());

  // Tangent columns: kept blocks first, then the eliminated ones.
  std::vector<Slot>& slots = linearizer.slots();
  int kept_size = 0;
  for (Slot& slot : slots) {
    if (slot.description.role != BlockRole::kKeep) continue;
    slot.offset = kept_size;
    kept_size += slot.tangent;
  }
  int size = kept_size;
  for (Slot& slot : slots) {
    if (slot.description.role != BlockRole::kEliminate) continue;
    slot.offset = size;
    size += slot.tangent;
  }
  if (kept_size == 0 || linear.empty()) return Status::Ok();

  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(size, size);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(size);
  for (const LinearTerm& lt : linear) {
    for (size_t a = 0; a < lt.slots.size(); ++a) {
      const Slot& sa = slots[lt.slots[a]];
      g.segment(sa.offset, sa.tangent) += lt.J[a].transpose() * lt.r;
      for (size_t b = 0; b < lt.slots.size(); ++b) {
        const Slot& sb = slots[lt.slots[b]];
        H.block(sa.offset, sb.offset, sa.tangent, sb.tangent) +=
            lt.J[a].transpose() * lt.J[b];
      }
    }
  }

  // Schur complement of the eliminated blocks.
  const int eliminated = size - kept_size;
  Eigen::MatrixXd H_star = H.topLeftCorner(kept_size, kept_size);
  Eigen::VectorXd g_star = g.head(kept_size);
  if (eliminated > 0) {
    const Spectrum mm =
        PositiveSpectrum(H.bottomRightCorner(eliminated, eliminated),
                         options.eigenvalue_threshold);
    const Eigen::MatrixXd H_km = H.topRightCorner(kept_size, eliminated);
    // H_km H_mm^+ = (H_km V) diag(1/l) V^T.
    const Eigen::MatrixXd H_km_V = H_km * mm.vectors;
    const Eigen::MatrixXd K =
        H_km_V * mm.values.cwiseInverse().asDiagonal() * mm.vectors.transpose();
    H_star -= K * H_km.transpose();
    g_star -= K * g.tail(eliminated);
  }
  H_star = 0.5 * (H_star + H_star.transpose()).eval();
  const Spectrum kk = PositiveSpectrum(H_star, options.eigenvalue_threshold);
  if (kk.values.size() == 0) return Status::Ok();
  const Eigen::VectorXd sqrt_values = kk.values.cwiseSqrt();
  Eigen::MatrixXd A = sqrt_values.asDiagonal() * kk.vectors.transpose();
  const Eigen::VectorXd e = sqrt_values.cwiseInverse().asDiagonal() *
                            (kk.vectors.transpose() * g_star);

  // The prior's blocks: kept blocks with some information.
  const double column_floor = 1e-12 * A.cwiseAbs().maxCoeff();
  std::vector<PriorBlock> prior_blocks;
  std::vector<int> columns;
  for (const Slot& slot : slots) {
    if (slot.description.role != BlockRole::kKeep) continue;
    if (A.middleCols(slot.offset, slot.tangent).cwiseAbs().maxCoeff() <=
        column_floor) {
      continue;
    }
    PriorBlock block;
    Status status = KindOf(slot.description.manifold, &block.kind);
    if (!status.ok()) return status;
    block.x0 = Eigen::Map<const Eigen::VectorXd>(slot.block, slot.ambient);
    if (block.kind != PriorBlockKind::kEuclidean) block.x0.normalize();
    prior_blocks.push_back(std::move(block));
    result->blocks.push_back(slot.block);
    for (int c = 0; c < slot.tangent; ++c) columns.push_back(slot.offset + c);
  }
  Eigen::MatrixXd A_kept(A.rows(), static_cast<int>(columns.size()));
  for (size_t c = 0; c < columns.size(); ++c) {
    A_kept.col(static_cast<int>(c)) = A.col(columns[c]);
  }
  return MarginalPriorFactor::Create(
      std::move(prior_blocks), std::move(A_kept), e, &result->prior);
}

}  // namespace symba::internal
