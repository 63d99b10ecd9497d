#include "symba/backend/backend_options.h"

#include <string>

#include "symba/backend/backend_option_table.h"

namespace symba {

const char* MethodName(Method method) { return NameOf(method, MethodNames()); }

bool ParseMethod(const std::string& name, Method* method) {
  return ValueOf(name, MethodNames(), method);
}

const char* LossName(LossType loss) { return NameOf(loss, LossNames()); }

bool ParseLoss(const std::string& name, LossType* loss) {
  return ValueOf(name, LossNames(), loss);
}

const char* DetectionErrorsName(DetectionErrors errors) {
  return NameOf(errors, DetectionErrorsNames());
}

bool ParseDetectionErrors(const std::string& name, DetectionErrors* errors) {
  return ValueOf(name, DetectionErrorsNames(), errors);
}

const char* WindowPolicyName(WindowPolicy policy) {
  return NameOf(policy, WindowPolicyNames());
}

bool ParseWindowPolicy(const std::string& name, WindowPolicy* policy) {
  return ValueOf(name, WindowPolicyNames(), policy);
}

const char* ChainPriorName(ChainPrior prior) {
  return NameOf(prior, ChainPriorNames());
}

bool ParseChainPrior(const std::string& name, ChainPrior* prior) {
  return ValueOf(name, ChainPriorNames(), prior);
}

// The ranges are the table's (backend_option_table.cc); the nested structs
// check their own fields.
Status BackendOptions::Validate() const {
  Status status = CheckOwnRanges(BackendOptionTable(), *this);
  if (!status.ok()) return status;
  if (noise_window < noise_min_samples) {
    return Status::Error("noise_window must be >= noise_min_samples");
  }
  if (!mixture.IsValid()) {
    return Status::Error(
        "mixture: null_weight must be positive and null_sigma_scale > 1");
  }
  status = categorization.Validate();
  if (!status.ok()) return Status::Error("categorization: " + status.message());
  return Status::Ok();
}

}  // namespace symba
