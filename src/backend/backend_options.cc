#include "symba/backend/backend_options.h"

#include <cmath>
#include <string>

namespace symba {
namespace {

bool PositiveFinite(double value) {
  return std::isfinite(value) && value > 0.0;
}

}  // namespace

const char* MethodName(Method method) {
  switch (method) {
    case Method::kSymba:
      return "symba";
    case Method::kMultiHypothesis:
      return "mh";
    case Method::kSingleHypothesis:
      return "sh";
  }
  return "symba";
}

bool ParseMethod(const std::string& name, Method* method) {
  for (Method m :
       {Method::kSymba, Method::kMultiHypothesis, Method::kSingleHypothesis}) {
    if (name == MethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

const char* LossName(LossType loss) {
  switch (loss) {
    case LossType::kNone:
      return "none";
    case LossType::kHuber:
      return "huber";
    case LossType::kCauchy:
      return "cauchy";
  }
  return "none";
}

bool ParseLoss(const std::string& name, LossType* loss) {
  for (LossType l : {LossType::kNone, LossType::kHuber, LossType::kCauchy}) {
    if (name == LossName(l)) {
      *loss = l;
      return true;
    }
  }
  return false;
}

const char* WindowPolicyName(WindowPolicy policy) {
  switch (policy) {
    case WindowPolicy::kMarginalize:
      return "marginalize";
    case WindowPolicy::kCondition:
      return "condition";
    case WindowPolicy::kDrop:
      return "drop";
  }
  return "marginalize";
}

bool ParseWindowPolicy(const std::string& name, WindowPolicy* policy) {
  for (WindowPolicy p : {WindowPolicy::kMarginalize,
                         WindowPolicy::kCondition,
                         WindowPolicy::kDrop}) {
    if (name == WindowPolicyName(p)) {
      *policy = p;
      return true;
    }
  }
  return false;
}

const char* ChainPriorName(ChainPrior prior) {
  switch (prior) {
    case ChainPrior::kConditional:
      return "conditional";
    case ChainPrior::kMarginal:
      return "marginal";
  }
  return "conditional";
}

bool ParseChainPrior(const std::string& name, ChainPrior* prior) {
  for (ChainPrior p : {ChainPrior::kConditional, ChainPrior::kMarginal}) {
    if (name == ChainPriorName(p)) {
      *prior = p;
      return true;
    }
  }
  return false;
}

Status BackendOptions::Validate() const {
  if (window_size < 1) return Status::Error("window_size must be >= 1");
  if (!(std::isfinite(marginalize_min_margin) &&
        marginalize_min_margin >= 0.0)) {
    return Status::Error("marginalize_min_margin must be finite and >= 0");
  }
  if (!(std::isfinite(marginalize_rival_distance) &&
        marginalize_rival_distance >= 0.0)) {
    return Status::Error("marginalize_rival_distance must be finite and >= 0");
  }
  if (max_iterations < 1 || batch_max_iterations < 1) {
    return Status::Error(
        "max_iterations and batch_max_iterations must be >= 1");
  }
  if (num_threads < 1) return Status::Error("num_threads must be >= 1");
  const struct {
    const char* name;
    double value;
  } positive[] = {
      {"hypothesis_sigma_t", hypothesis_sigma_t},
      {"hypothesis_sigma_r", hypothesis_sigma_r},
      {"axis_sigma", axis_sigma},
      {"object_loss_scale", object_loss_scale},
      {"frontend_sigma_t", frontend_sigma_t},
      {"frontend_sigma_r", frontend_sigma_r},
      {"point_sigma_px", point_sigma_px},
      {"point_loss_scale", point_loss_scale},
      {"gate_position", gate_position},
      {"gate_axis", gate_axis},
      {"gate_rotation", gate_rotation},
      {"gate_angle", gate_angle},
      {"reanchor_angle", reanchor_angle},
      {"upgrade_angle_tolerance", upgrade_angle_tolerance},
      {"uncalibrated_sigma_t", uncalibrated_sigma_t},
      {"uncalibrated_sigma_r", uncalibrated_sigma_r},
  };
  for (const auto& option : positive) {
    if (!PositiveFinite(option.value)) {
      return Status::Error(std::string(option.name) +
                           " must be positive and finite");
    }
  }
  if (!std::isfinite(point_depth_sigma_relative) ||
      point_depth_sigma_relative < 0.0) {
    return Status::Error(
        "point_depth_sigma_relative must be finite and >= 0 (0 disables)");
  }
  if (!std::isfinite(gamma) || gamma < 0.0) {
    return Status::Error("gamma must be finite and >= 0");
  }
  if (gate_angle >= kPi || gate_axis >= kPi / 2 || reanchor_angle >= kPi) {
    return Status::Error(
        "gate_angle and reanchor_angle must be < pi, gate_axis < pi/2");
  }
  if (confirm_keyframes < 1 || tentative_timeout < 1 || upgrade_evidence < 1 ||
      noise_min_samples < 1 || noise_window < noise_min_samples) {
    return Status::Error(
        "confirm_keyframes, tentative_timeout, upgrade_evidence and "
        "noise_min_samples must be >= 1, noise_window >= noise_min_samples");
  }
  if (!(std::isfinite(upgrade_min_fraction) && upgrade_min_fraction >= 0.0 &&
        upgrade_min_fraction <= 1.0)) {
    return Status::Error("upgrade_min_fraction must be in [0, 1]");
  }
  if (!(std::isfinite(min_support) && min_support >= 0.0 &&
        min_support <= 1.0) ||
      min_support_views < 1) {
    return Status::Error(
        "min_support must be in [0, 1] and min_support_views >= 1");
  }
  if (max_upgrade_order < 2) {
    return Status::Error("max_upgrade_order must be >= 2");
  }
  if (!std::isfinite(gate_sigmas) || gate_sigmas < 0.0) {
    return Status::Error("gate_sigmas must be finite and >= 0 (0 disables)");
  }
  if (!(std::isfinite(noise_update_ratio) && noise_update_ratio >= 1.0)) {
    return Status::Error("noise_update_ratio must be finite and >= 1");
  }
  if (upgrade_angle_tolerance >= kPi / 2) {
    return Status::Error("upgrade_angle_tolerance must be < pi/2");
  }
  if (!mixture.IsValid()) {
    return Status::Error(
        "mixture: null_weight must be positive and null_sigma_scale > 1");
  }
  Status status = categorization.Validate();
  if (!status.ok()) return Status::Error("categorization: " + status.message());
  return Status::Ok();
}

}  // namespace symba
