// Command-line flags made from an option table (common/option_table.h): one
// flag per field, named `--` + the field's name exactly as in C++, Python
// and summary.json ("--window_size", "--mixture.null_weight"), with the
// table's doc line, its default and its range or choices checked by CLI11.
#ifndef SYMBA_SRC_TOOLS_OPTION_FLAGS_H_
#define SYMBA_SRC_TOOLS_OPTION_FLAGS_H_

#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

#include "symba/common/option_table.h"

namespace symba::tools {

// The flag of a table field.
inline std::string FlagName(const std::string& field_name) {
  return "--" + field_name;
}

// The range of a value that is multiplied by `scale` to give the field's.
inline OptionRange ScaledRange(const OptionRange& range, double scale) {
  OptionRange scaled = range;
  scaled.low /= scale;
  scaled.high /= scale;
  return scaled;
}

// ">= 1", "(0, pi/2)": the range's text without a leading "in ".
inline std::string RangeWithoutIn(const OptionRange& range) {
  const std::string text = range.Text();
  return text.compare(0, 3, "in ") == 0 ? text.substr(3) : text;
}

// Checks that a number is in `range`, with CLI11's wording: "Value 0 not in
// range >= 1", "Value nan is not a finite number".
inline CLI::Validator RangeValidator(const OptionRange& range) {
  return CLI::Validator(
      [range](std::string& input) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(input, value)) return std::string();
        if (std::isnan(value) || (std::isinf(value) && !range.allow_infinity)) {
          return "Value " + input + " is not a finite number";
        }
        if (!range.Contains(value)) {
          return "Value " + input + " not in range " + RangeWithoutIn(range);
        }
        return std::string();
      },
      range.Text());
}

inline std::string FlagHelp(const std::string& doc, const std::string& unit) {
  return unit.empty() ? doc : doc + " (" + unit + ")";
}

// Adds the flag(s) `names` ("--window_size,--window") for `field`, writing
// into *options, which also gives the default shown by --help. `field` and
// `options` must outlive the parse.
template <typename Options>
CLI::Option* AddOptionFlag(CLI::App* command,
                           const std::string& names,
                           const OptionField<Options>& field,
                           Options* options) {
  const OptionField<Options>* f = &field;
  const std::string help = FlagHelp(field.doc, field.unit);
  CLI::Option* option = nullptr;
  switch (field.type) {
    case OptionType::kBool:
      option = command->add_option_function<bool>(
          names, [f, options](const bool& v) { f->set(v, options); }, help);
      break;
    case OptionType::kInt:
      option = command->add_option_function<int>(
          names, [f, options](const int& v) { f->set(v, options); }, help);
      option->check(RangeValidator(field.range));
      break;
    case OptionType::kDouble:
      option = command->add_option_function<double>(
          names, [f, options](const double& v) { f->set(v, options); }, help);
      option->check(RangeValidator(field.range));
      break;
    case OptionType::kEnum:
      option = command->add_option_function<std::string>(
          names,
          [f, options](const std::string& v) { f->set(v, options); },
          help);
      option->check(CLI::IsMember(field.choices));
      break;
  }
  option->default_str(FormatOptionValue(field.get(*options)));
  return option;
}

}  // namespace symba::tools

#endif  // SYMBA_SRC_TOOLS_OPTION_FLAGS_H_
