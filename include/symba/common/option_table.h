// OptionTable: every option of an options struct as a list of OptionField
// (option_field.h), in the struct's order, with the builders that make the
// entries from member pointers and the range check that Validate uses.
#ifndef SYMBA_COMMON_OPTION_TABLE_H_
#define SYMBA_COMMON_OPTION_TABLE_H_

#include <string>
#include <utility>
#include <vector>

#include "symba/common/option_field.h"
#include "symba/common/status.h"

namespace symba {

template <typename Options>
using OptionTable = std::vector<OptionField<Options>>;

// A value as text: "10", "0.05" (the shortest text that reads back as the
// same double), "true", "marginalize".
std::string FormatOptionValue(const OptionValue& value);

// "must be >= 1", "must be finite and > 0", "must be finite and in [0, 1]".
std::string RangeRequirement(OptionType type, const OptionRange& range);

template <typename Options>
OptionField<Options> BoolOption(const char* name,
                                bool Options::*member,
                                const char* doc) {
  OptionField<Options> field;
  field.name = name;
  field.type = OptionType::kBool;
  field.doc = doc;
  field.get = [member](const Options& o) { return OptionValue(o.*member); };
  field.set = [member](const OptionValue& value, Options* o) {
    const bool* b = std::get_if<bool>(&value);
    if (b != nullptr) o->*member = *b;
    return b != nullptr;
  };
  return field;
}

template <typename Options>
OptionField<Options> IntOption(const char* name,
                               int Options::*member,
                               OptionRange range,
                               const char* doc) {
  OptionField<Options> field;
  field.name = name;
  field.type = OptionType::kInt;
  field.range = range;
  field.doc = doc;
  field.get = [member](const Options& o) { return OptionValue(o.*member); };
  field.set = [member](const OptionValue& value, Options* o) {
    const int* i = std::get_if<int>(&value);
    if (i != nullptr) o->*member = *i;
    return i != nullptr;
  };
  return field;
}

// An int is also taken as a double.
template <typename Options>
OptionField<Options> DoubleOption(const char* name,
                                  double Options::*member,
                                  const char* unit,
                                  OptionRange range,
                                  const char* doc) {
  OptionField<Options> field;
  field.name = name;
  field.type = OptionType::kDouble;
  field.unit = unit;
  field.range = range;
  field.doc = doc;
  field.get = [member](const Options& o) { return OptionValue(o.*member); };
  field.set = [member](const OptionValue& value, Options* o) {
    if (const double* d = std::get_if<double>(&value)) {
      o->*member = *d;
    } else if (const int* i = std::get_if<int>(&value)) {
      o->*member = *i;
    } else {
      return false;
    }
    return true;
  };
  return field;
}

// `names` must outlive the field (a function-local static list).
template <typename Options, typename Enum>
OptionField<Options> EnumOption(const char* name,
                                Enum Options::*member,
                                const std::vector<EnumName<Enum>>& names,
                                const char* doc) {
  OptionField<Options> field;
  field.name = name;
  field.type = OptionType::kEnum;
  field.doc = doc;
  for (const EnumName<Enum>& entry : names) field.choices.push_back(entry.name);
  const std::vector<EnumName<Enum>>* list = &names;
  field.get = [member, list](const Options& o) {
    return OptionValue(std::string(NameOf(o.*member, *list)));
  };
  field.set = [member, list](const OptionValue& value, Options* o) {
    const std::string* text = std::get_if<std::string>(&value);
    return text != nullptr && ValueOf(*text, *list, &(o->*member));
  };
  return field;
}

// Appends the fields of the nested struct `o.*member` as "group.name".
template <typename Options, typename Inner>
void AppendNested(const char* group,
                  Inner Options::*member,
                  const OptionTable<Inner>& inner,
                  OptionTable<Options>* table) {
  for (const OptionField<Inner>& in : inner) {
    OptionField<Options> field;
    field.name = std::string(group) + "." + in.name;
    field.type = in.type;
    field.unit = in.unit;
    field.range = in.range;
    field.choices = in.choices;
    field.doc = in.doc;
    auto get = in.get;
    auto set = in.set;
    field.get = [member, get](const Options& o) { return get(o.*member); };
    field.set = [member, set](const OptionValue& value, Options* o) {
      return set(value, &(o->*member));
    };
    table->push_back(std::move(field));
  }
}

// Whether a field lives in a nested struct ("mixture.null_weight").
template <typename Options>
bool IsNested(const OptionField<Options>& field) {
  return field.name.find('.') != std::string::npos;
}

// The field called `name`, or null.
template <typename Options>
const OptionField<Options>* FindOption(const OptionTable<Options>& table,
                                       const std::string& name) {
  for (const OptionField<Options>& field : table) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

// OK when the field's value is in its range; else "NAME must be ...".
template <typename Options>
Status CheckRange(const OptionField<Options>& field, const Options& options) {
  const OptionValue value = field.get(options);
  double number = 0.0;
  if (const int* i = std::get_if<int>(&value)) {
    number = *i;
  } else if (const double* d = std::get_if<double>(&value)) {
    number = *d;
  } else {
    return Status::Ok();
  }
  if (field.range.Contains(number)) return Status::Ok();
  return Status::Error(field.name + " " +
                       RangeRequirement(field.type, field.range));
}

// The first of the struct's own (not nested) fields out of its range.
template <typename Options>
Status CheckOwnRanges(const OptionTable<Options>& table,
                      const Options& options) {
  for (const OptionField<Options>& field : table) {
    if (IsNested(field)) continue;
    Status status = CheckRange(field, options);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

}  // namespace symba

#endif  // SYMBA_COMMON_OPTION_TABLE_H_
