#include "symba/categorization/class_prior.h"

#include <sstream>
#include <string>

namespace symba {
namespace {

bool IsKnownSymmetry(SymmetryType symmetry) {
  switch (symmetry) {
    case SymmetryType::kAsymmetric:
    case SymmetryType::kDiscrete:
    case SymmetryType::kContinuous:
      return true;
  }
  return false;
}

std::string AxisText(const Eigen::Vector3d& axis) {
  std::ostringstream text;
  text << "(" << axis.x() << ", " << axis.y() << ", " << axis.z() << ")";
  return text.str();
}

}  // namespace

Status ClassPrior::Validate() const {
  if (!IsKnownSymmetry(symmetry)) {
    return Status::Error("class prior symmetry " +
                         std::to_string(static_cast<int>(symmetry)) +
                         " is not asymmetric, discrete or continuous");
  }
  if (!axis_o.allFinite()) {
    return Status::Error("class prior axis " + AxisText(axis_o) +
                         " is not finite");
  }
  // A direction, normalised where it is used: its squared norm must neither
  // overflow nor underflow (zero: no axis given).
  if (!IsUsablePriorAxis(axis_o)) {
    return Status::Error("class prior axis " + AxisText(axis_o) +
                         " must be zero or have a norm in [1e-100, 1e100]");
  }
  if (order < 0 || order == 1) {
    return Status::Error("class prior order " + std::to_string(order) +
                         " is neither 0 (unknown) nor >= 2");
  }
  return Status::Ok();
}

}  // namespace symba
