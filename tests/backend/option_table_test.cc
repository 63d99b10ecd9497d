// The option tables (backend_option_table.h) against the places that follow
// them: BackendOptions::Validate and the nested structs' own checks,
// summary.json "options", and docs/backend.md's options table (which must be
// exactly the table below, generated here from the C++ table).
#include "symba/backend/backend_option_table.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "symba/geometry/angle.h"
#include "symba/replay/replay_output.h"

namespace symba {
namespace {

using Field = OptionField<BackendOptions>;
using ::testing::HasSubstr;

const OptionTable<BackendOptions>& Table() { return BackendOptionTable(); }

// The member's own name: "null_weight" for "mixture.null_weight".
std::string MemberOf(const std::string& name) {
  return name.substr(name.find('.') + 1);
}

// Defaults under which every single field can reach its range's ends: the
// null hypothesis on (its fields are checked only then) and
// noise_min_samples 1 (noise_window must be at least that).
BackendOptions Base() {
  BackendOptions options;
  options.mixture.use_null_hypothesis = true;
  options.noise_min_samples = 1;
  return options;
}

OptionValue NumberOfType(const Field& field, double value) {
  if (field.type == OptionType::kInt) return static_cast<int>(value);
  return value;
}

// Values just outside the field's range.
std::vector<double> OutsideValues(const Field& field) {
  const OptionRange& r = field.range;
  const bool is_int = field.type == OptionType::kInt;
  std::vector<double> values;
  if (!std::isinf(r.low)) {
    values.push_back(r.low_open ? r.low
                     : is_int   ? r.low - 1
                                : std::nextafter(r.low, -INFINITY));
  }
  if (!std::isinf(r.high)) {
    values.push_back(r.high_open ? r.high
                     : is_int    ? r.high + 1
                                 : std::nextafter(r.high, INFINITY));
  }
  if (!is_int) {
    values.push_back(std::numeric_limits<double>::quiet_NaN());
    if (!r.allow_infinity) values.push_back(INFINITY);
  }
  return values;
}

// Values just inside the range's finite ends.
std::vector<double> InsideValues(const Field& field) {
  const OptionRange& r = field.range;
  const bool is_int = field.type == OptionType::kInt;
  std::vector<double> values;
  if (!std::isinf(r.low)) {
    values.push_back(!r.low_open ? r.low
                     : is_int    ? r.low + 1
                                 : std::nextafter(r.low, INFINITY));
  }
  if (!std::isinf(r.high)) {
    values.push_back(!r.high_open ? r.high
                     : is_int     ? r.high - 1
                                  : std::nextafter(r.high, -INFINITY));
  }
  if (r.allow_infinity) values.push_back(INFINITY);
  return values;
}

TEST(OptionTable, NamesAreUniqueAndEveryFieldIsDescribed) {
  std::set<std::string> names;
  for (const Field& field : Table()) {
    EXPECT_TRUE(names.insert(field.name).second) << field.name;
    EXPECT_FALSE(field.doc.empty()) << field.name;
    EXPECT_EQ(field.type == OptionType::kEnum, !field.choices.empty())
        << field.name;
  }
}

// Converts to any member type: T{AnyValue{}, ...} compiles for as many
// values as the aggregate T has members.
struct AnyValue {
  template <typename T>
  operator T() const;  // NOLINT: only in unevaluated contexts
};

template <typename T, std::size_t... I>
constexpr auto BraceInitializable(std::index_sequence<I...>)
    -> decltype(T{(void(I), AnyValue{})...}, bool()) {
  return true;
}

template <typename T>
constexpr bool BraceInitializable(...) {
  return false;
}

template <typename T, std::size_t N = 0>
constexpr std::size_t MemberCount() {
  if constexpr (BraceInitializable<T>(std::make_index_sequence<N + 1>())) {
    return MemberCount<T, N + 1>();
  } else {
    return N;
  }
}

// A member added to an options struct without its table entry fails here.
TEST(OptionTable, EveryMemberOfTheStructsIsInTheTables) {
  EXPECT_EQ(MemberCount<MixtureOptions>(), MixtureOptionTable().size());
  EXPECT_EQ(MemberCount<CategorizationOptions>(),
            CategorizationOptionTable().size());
  std::set<std::string> members;  // own fields and nested structs
  for (const Field& field : Table()) {
    members.insert(field.name.substr(0, field.name.find('.')));
  }
  EXPECT_EQ(MemberCount<BackendOptions>(), members.size());
}

TEST(OptionTable, EveryDefaultIsInItsRange) {
  EXPECT_TRUE(BackendOptions().Validate().ok());
  const BackendOptions defaults;
  for (const Field& field : Table()) {
    if (!field.IsNumeric()) continue;
    const OptionValue value = field.get(defaults);
    const double number = field.type == OptionType::kInt
                              ? std::get<int>(value)
                              : std::get<double>(value);
    EXPECT_TRUE(field.range.Contains(number)) << field.name;
  }
}

TEST(OptionTable, ValidateRejectsEveryValueOutsideTheRange) {
  for (const Field& field : Table()) {
    if (!field.IsNumeric()) continue;
    for (double value : OutsideValues(field)) {
      BackendOptions options = Base();
      ASSERT_TRUE(field.set(NumberOfType(field, value), &options));
      const Status status = options.Validate();
      EXPECT_FALSE(status.ok()) << field.name << " = " << value;
      EXPECT_THAT(status.message(), HasSubstr(MemberOf(field.name)));
    }
  }
}

TEST(OptionTable, ValidateAcceptsTheEndsOfEveryRange) {
  ASSERT_TRUE(Base().Validate().ok());
  for (const Field& field : Table()) {
    if (!field.IsNumeric()) continue;
    for (double value : InsideValues(field)) {
      BackendOptions options = Base();
      ASSERT_TRUE(field.set(NumberOfType(field, value), &options));
      const Status status = options.Validate();
      EXPECT_TRUE(status.ok())
          << field.name << " = " << value << ": " << status.message();
    }
  }
}

TEST(OptionTable, AnOwnFieldOutOfRangeIsNamedWithItsRange) {
  BackendOptions options;
  options.window_size = 0;
  EXPECT_EQ(options.Validate().message(), "window_size must be >= 1");
  options = BackendOptions();
  options.gate_axis = 2.0;
  EXPECT_EQ(options.Validate().message(),
            "gate_axis must be finite and in (0, pi/2)");
}

TEST(OptionTable, EnumFieldsTakeTheirNamesOnly) {
  for (const Field& field : Table()) {
    if (field.type != OptionType::kEnum) continue;
    for (const std::string& choice : field.choices) {
      BackendOptions options;
      ASSERT_TRUE(field.set(choice, &options)) << field.name;
      EXPECT_EQ(std::get<std::string>(field.get(options)), choice);
    }
    BackendOptions options;
    EXPECT_FALSE(field.set(std::string("bogus"), &options)) << field.name;
  }
  EXPECT_STREQ(MethodName(Method::kMultiHypothesis), "mh");
  WindowPolicy policy = WindowPolicy::kMarginalize;
  EXPECT_TRUE(ParseWindowPolicy("drop", &policy));
  EXPECT_EQ(policy, WindowPolicy::kDrop);
}

// An in-range value that differs from `value`.
OptionValue OtherValue(const Field& field, const OptionValue& value) {
  if (const bool* b = std::get_if<bool>(&value)) return !*b;
  if (const std::string* s = std::get_if<std::string>(&value)) {
    return field.choices[0] == *s ? field.choices[1] : field.choices[0];
  }
  if (const int* i = std::get_if<int>(&value)) {
    return field.range.Contains(*i + 1) ? *i + 1 : *i - 1;
  }
  const double d = std::get<double>(value);
  if (field.range.Contains(1.5 * d + 0.25)) return 1.5 * d + 0.25;
  return 0.5 * (d + field.range.low);
}

// The member of summary.json "options" for a table name ("a.b": ["a"]["b"]).
const nlohmann::json& JsonOption(const nlohmann::json& options,
                                 const std::string& name) {
  const size_t dot = name.find('.');
  if (dot == std::string::npos) return options.at(name);
  return options.at(name.substr(0, dot)).at(name.substr(dot + 1));
}

void ExpectJsonEquals(const nlohmann::json& json, const OptionValue& value) {
  std::visit([&json](const auto& v) { EXPECT_EQ(json, v); }, value);
}

TEST(OptionTable, SummaryJsonReportsEveryOptionUnderItsName) {
  ReplayOptions replay;
  for (const Field& field : Table()) {
    ASSERT_TRUE(field.set(OtherValue(field, field.get(replay.backend)),
                          &replay.backend));
  }
  ASSERT_TRUE(replay.backend.Validate().ok())
      << replay.backend.Validate().message();
  const nlohmann::json summary = nlohmann::json::parse(
      FormatReplaySummaryJson("log.jsonl", replay, ReplayResult()));
  const nlohmann::json& options = summary.at("options");
  size_t reported = 0;
  for (const Field& field : Table()) {
    SCOPED_TRACE(field.name);
    ExpectJsonEquals(JsonOption(options, field.name),
                     field.get(replay.backend));
    ++reported;
  }
  EXPECT_EQ(reported, Table().size());
  // The keys older readers know.
  EXPECT_EQ(options.at("window"), replay.backend.window_size);
  EXPECT_EQ(options.at("threads"), replay.backend.num_threads);
  EXPECT_EQ(options.at("null_hypothesis"),
            replay.backend.mixture.use_null_hypothesis);
}

// docs/backend.md's table, as the table gives it. An angle that is a
// whole number of degrees also shows them.
std::string DefaultText(const Field& field, const OptionValue& value) {
  const std::string text = FormatOptionValue(value);
  if (field.unit != "rad") {
    return field.unit.empty() ? text : text + " " + field.unit;
  }
  const double degrees = std::get<double>(value) * 180.0 / kPi;
  if (std::abs(degrees - std::round(degrees)) > 1e-9) return text + " rad";
  char buffer[64];
  std::snprintf(buffer,
                sizeof buffer,
                "%.6g rad (%.0f deg)",
                std::get<double>(value),
                degrees);
  return buffer;
}

std::string AllowedText(const Field& field) {
  if (field.type == OptionType::kBool) return "`true`, `false`";
  if (field.type == OptionType::kEnum) {
    std::string text;
    for (const std::string& choice : field.choices) {
      text += (text.empty() ? "`" : ", `") + choice + "`";
    }
    return text;
  }
  return field.range.Text() + (field.range.allow_infinity ? " (inf too)" : "");
}

std::string MarkdownTable() {
  const BackendOptions defaults;
  std::string text =
      "| option | default | allowed | meaning |\n|---|---|---|---|\n";
  for (const Field& field : Table()) {
    text += "| `" + field.name + "` | " +
            DefaultText(field, field.get(defaults)) + " | " +
            AllowedText(field) + " | " + field.doc + " |\n";
  }
  return text;
}

// The lines of the table after `marker` in `path`, up to a blank line.
std::string TableAfter(const std::string& path, const std::string& marker) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line) && line.find(marker) == std::string::npos) {
  }
  std::string table;
  while (std::getline(in, line) && !line.empty()) table += line + "\n";
  return table;
}

TEST(OptionTable, BackendDocsTableIsTheTable) {
  const std::string docs =
      TableAfter(SYMBA_DOCS_DIR "/backend.md", "<!-- the options table:");
  EXPECT_EQ(docs, MarkdownTable())
      << "docs/backend.md's options table differs from the C++ table; "
         "replace it with the expected text above";
}

// The cells of a markdown row: "| a | b |" -> {"a", "b"}.
std::vector<std::string> Cells(const std::string& row) {
  std::vector<std::string> cells;
  std::stringstream in(row.substr(1));
  std::string cell;
  while (std::getline(in, cell, '|')) {
    const size_t first = cell.find_first_not_of(' ');
    const size_t last = cell.find_last_not_of(' ');
    if (first != std::string::npos) {
      cells.push_back(cell.substr(first, last - first + 1));
    }
  }
  return cells;
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const size_t first = item.find_first_not_of(" `");
    const size_t last = item.find_last_not_of(" `");
    items.push_back(item.substr(first, last - first + 1));
  }
  return items;
}

// A default as docs/categorization.md writes it: angles in degrees without
// a unit, metres with " m".
std::string CategorizationDocsDefault(const Field& field) {
  const OptionValue value = field.get(BackendOptions());
  if (field.unit == "rad") {
    return FormatOptionValue(std::round(std::get<double>(value) * 180 / kPi));
  }
  const std::string text = FormatOptionValue(value);
  if (field.type == OptionType::kDouble &&
      text.find('.') == std::string::npos &&
      text.find('e') == std::string::npos) {
    return field.unit.empty() ? text + ".0" : text + " " + field.unit;
  }
  return field.unit.empty() ? text : text + " " + field.unit;
}

// docs/categorization.md's table of defaults ("| `a`, `b` | 20, 0.7 |")
// names table fields with their defaults.
TEST(OptionTable, CategorizationDocsDefaultsAreTheTable) {
  std::ifstream in(SYMBA_DOCS_DIR "/categorization.md");
  std::string line;
  while (std::getline(in, line) && line != "| option | default | why |") {
  }
  ASSERT_TRUE(std::getline(in, line));  // |---|---|---|
  int checked = 0;
  while (std::getline(in, line) && !line.empty()) {
    const std::vector<std::string> cells = Cells(line);
    ASSERT_GE(cells.size(), 2u) << line;
    const std::vector<std::string> names = SplitList(cells[0]);
    const std::vector<std::string> defaults = SplitList(cells[1]);
    ASSERT_EQ(names.size(), defaults.size()) << line;
    for (size_t i = 0; i < names.size(); ++i) {
      const Field* field = FindOption(Table(), "categorization." + names[i]);
      ASSERT_NE(field, nullptr) << names[i];
      EXPECT_EQ(defaults[i], CategorizationDocsDefault(*field)) << names[i];
      ++checked;
    }
  }
  EXPECT_GE(checked, 16);
}

}  // namespace
}  // namespace symba
