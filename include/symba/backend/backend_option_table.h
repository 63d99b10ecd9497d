// The option tables of the backend's option structs (common/option_table.h):
// every field of BackendOptions, MixtureOptions and CategorizationOptions
// with its name, type, unit, range and a one-line doc, in the struct's
// order. They are the one source that BackendOptions::Validate, summary.json
// "options", the flags of `symba replay`, the Python keywords and
// docs/backend.md's table (checked by a test) follow; the defaults are the
// structs' member initializers.
#ifndef SYMBA_BACKEND_BACKEND_OPTION_TABLE_H_
#define SYMBA_BACKEND_BACKEND_OPTION_TABLE_H_

#include <vector>

#include "symba/backend/backend_options.h"
#include "symba/categorization/categorization_option_table.h"
#include "symba/common/option_table.h"

namespace symba {

// The enums' names, in declaration order.
const std::vector<EnumName<Method>>& MethodNames();
const std::vector<EnumName<WindowPolicy>>& WindowPolicyNames();
const std::vector<EnumName<ChainPrior>>& ChainPriorNames();
const std::vector<EnumName<LossType>>& LossNames();
const std::vector<EnumName<DetectionErrors>>& DetectionErrorsNames();

const OptionTable<MixtureOptions>& MixtureOptionTable();
// BackendOptions' own fields, then mixture.* and categorization.*, each at
// the place of its member.
const OptionTable<BackendOptions>& BackendOptionTable();

}  // namespace symba

#endif  // SYMBA_BACKEND_BACKEND_OPTION_TABLE_H_
