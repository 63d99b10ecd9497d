// CategorizationOptions as an option table (symba/common/option_table.h):
// name, unit, range and one line of doc per field, in struct order; the
// default is the struct's own. BackendOptionTable nests it as
// "categorization.".
#ifndef SYMBA_CATEGORIZATION_CATEGORIZATION_OPTION_TABLE_H_
#define SYMBA_CATEGORIZATION_CATEGORIZATION_OPTION_TABLE_H_

#include "symba/categorization/categorization_options.h"
#include "symba/common/option_table.h"

namespace symba {

const OptionTable<CategorizationOptions>& CategorizationOptionTable();

}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CATEGORIZATION_OPTION_TABLE_H_
