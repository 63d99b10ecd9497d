// A class prior written on one command-line argument (symba import's
// --class-prior, docs/import.md):
//
//   NAME=asymmetric
//   NAME=discrete:ORDER[:ax,ay,az]     ORDER an integer from 2 to 1000000
//   NAME=continuous[:ax,ay,az]
//
// The axis (object frame, need not be unit, not all zero) is optional, as
// in the log header's "classes" (docs/log-format.md).
#ifndef SYMBA_IMPORT_CLASS_PRIOR_SPEC_H_
#define SYMBA_IMPORT_CLASS_PRIOR_SPEC_H_

#include <string>

#include "symba/categorization/categorize.h"
#include "symba/common/status.h"

namespace symba {

// Errors read `class prior "SPEC": reason`.
Status ParseClassPriorSpec(const std::string& spec,
                           std::string* name,
                           ClassPrior* prior);

}  // namespace symba

#endif  // SYMBA_IMPORT_CLASS_PRIOR_SPEC_H_
