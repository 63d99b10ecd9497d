// OptionField: one option of an options struct described as data: its name,
// its type, its allowed values, a one-line doc and how to read and write it
// in a struct. A list of them (option_table.h) is the one place an options
// struct is spelled out; validation, summary.json, the command line, Python
// and the docs' table visit the list instead of naming every field again.
//
// The default is not repeated here: it is what the struct's member
// initializer says (read it with Get(Options{})).
#ifndef SYMBA_COMMON_OPTION_FIELD_H_
#define SYMBA_COMMON_OPTION_FIELD_H_

#include <functional>
#include <limits>
#include <string>
#include <variant>
#include <vector>

namespace symba {

// An option's value as any of its types; an enum is its name.
using OptionValue = std::variant<bool, int, double, std::string>;

enum class OptionType { kBool, kInt, kDouble, kEnum };

// The allowed values of a numeric option: between low and high, each end
// open or closed; finite unless allow_infinity.
struct OptionRange {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = false;
  bool high_open = false;
  bool allow_infinity = false;

  bool Contains(double value) const;
  // ">= 1", "> 0", "in [0, 1]", "in (0, pi/2)", "any" (pi shown as pi).
  std::string Text() const;
};

// The usual ranges.
OptionRange AtLeast(double low);                    // [low, inf)
OptionRange Above(double low);                      // (low, inf)
OptionRange Between(double low, double high);       // [low, high]
OptionRange AboveBelow(double low, double high);    // (low, high)
OptionRange AtLeastBelow(double low, double high);  // [low, high)

// One enum value and its name.
template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value` in `names` (the first entry's name if it is missing).
template <typename Enum>
const char* NameOf(Enum value, const std::vector<EnumName<Enum>>& names) {
  for (const EnumName<Enum>& entry : names) {
    if (entry.value == value) return entry.name;
  }
  return names.front().name;
}

// The value called `name` in `names`; false when no value has that name.
template <typename Enum>
bool ValueOf(const std::string& name,
             const std::vector<EnumName<Enum>>& names,
             Enum* value) {
  for (const EnumName<Enum>& entry : names) {
    if (name == entry.name) {
      *value = entry.value;
      return true;
    }
  }
  return false;
}

template <typename Options>
struct OptionField {
  std::string name;  // the member's name; "group.name" inside a nested struct
  OptionType type = OptionType::kDouble;
  std::string unit;                  // "m", "rad", "px" or empty
  OptionRange range;                 // kInt and kDouble
  std::vector<std::string> choices;  // kEnum: the names, in order
  std::string doc;                   // one line
  std::function<OptionValue(const Options&)> get;
  // False (and nothing changed) when the value has the wrong type or is
  // not one of the choices; the range is Validate's.
  std::function<bool(const OptionValue&, Options*)> set;

  bool IsNumeric() const {
    return type == OptionType::kInt || type == OptionType::kDouble;
  }
};

}  // namespace symba

#endif  // SYMBA_COMMON_OPTION_FIELD_H_
