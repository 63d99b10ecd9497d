#include <charconv>
#include <cmath>
#include <string>

#include "symba/common/option_field.h"
#include "symba/common/option_table.h"

namespace symba {
namespace {

constexpr double kPiValue = 3.14159265358979323846;

std::string ShortestText(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + 32, value).ptr);
}

// A range end: "pi", "pi/2", "inf" or the shortest number.
std::string EndText(double value) {
  if (value == kPiValue) return "pi";
  if (value == kPiValue / 2) return "pi/2";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return ShortestText(value);
}

bool AboveLow(const OptionRange& range, double value) {
  return range.low_open ? value > range.low : value >= range.low;
}

bool BelowHigh(const OptionRange& range, double value) {
  return range.high_open ? value < range.high : value <= range.high;
}

}  // namespace

bool OptionRange::Contains(double value) const {
  if (std::isnan(value)) return false;
  if (std::isinf(value) && !allow_infinity) return false;
  return AboveLow(*this, value) && BelowHigh(*this, value);
}

std::string OptionRange::Text() const {
  const bool has_low = !std::isinf(low);
  const bool has_high = !std::isinf(high);
  if (has_low && has_high) {
    return std::string("in ") + (low_open ? "(" : "[") + EndText(low) + ", " +
           EndText(high) + (high_open ? ")" : "]");
  }
  if (has_low) return (low_open ? "> " : ">= ") + EndText(low);
  if (has_high) return (high_open ? "< " : "<= ") + EndText(high);
  return "any";
}

OptionRange AtLeast(double low) {
  OptionRange range;
  range.low = low;
  return range;
}

OptionRange Above(double low) {
  OptionRange range = AtLeast(low);
  range.low_open = true;
  return range;
}

OptionRange Between(double low, double high) {
  OptionRange range = AtLeast(low);
  range.high = high;
  return range;
}

OptionRange AboveBelow(double low, double high) {
  OptionRange range = Between(low, high);
  range.low_open = true;
  range.high_open = true;
  return range;
}

OptionRange AtLeastBelow(double low, double high) {
  OptionRange range = Between(low, high);
  range.high_open = true;
  return range;
}

std::string FormatOptionValue(const OptionValue& value) {
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const int* i = std::get_if<int>(&value)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&value)) return ShortestText(*d);
  return std::get<std::string>(value);
}

std::string RangeRequirement(OptionType type, const OptionRange& range) {
  const bool finite = type == OptionType::kDouble && !range.allow_infinity;
  return std::string("must be ") + (finite ? "finite and " : "") + range.Text();
}

}  // namespace symba
