// JsonWriter, the one JSON writing path (src/io/json_writer.h): its three
// layouts written out exactly, the wrapped layout against nlohmann's dump(2)
// (which it replaced), and numbers that read back bit for bit.
#include "io/json_writer.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace symba::io_internal {
namespace {

// {"a": 1, "b": [1.5, -0.0, true, null, "x\"y"], "c": {}, "d": [],
//  "e": {"f": [[1.0], {"g": "h"}]}} with the given wrap depth.
std::string Document(int wrap_depth) {
  std::string out;
  JsonWriter json(&out, wrap_depth);
  json.BeginObject().Member("a", 1).Key("b").BeginArray();
  json.Double(1.5).Double(-0.0).Bool(true).Null().String("x\"y");
  json.EndArray();
  json.Key("c").BeginObject().EndObject();
  json.Key("d").BeginArray().EndArray();
  json.Key("e").BeginObject().Key("f").BeginArray();
  json.BeginArray().Double(1.0).EndArray();
  json.BeginObject().Member("g", "h").EndObject();
  json.EndArray().EndObject().EndObject();
  EXPECT_TRUE(json.Complete());
  return out;
}

TEST(JsonWriter, CompactHasNoWhitespace) {
  EXPECT_EQ(Document(0),
            R"({"a":1,"b":[1.5,-0.0,true,null,"x\"y"],"c":{},"d":[],)"
            R"("e":{"f":[[1.0],{"g":"h"}]}})");
}

TEST(JsonWriter, WrapDepthTwoPutsEachSecondLevelElementOnALine) {
  EXPECT_EQ(Document(2),
            "{\n"
            "  \"a\": 1,\n"
            "  \"b\": [\n"
            "    1.5,\n"
            "    -0.0,\n"
            "    true,\n"
            "    null,\n"
            "    \"x\\\"y\"\n"
            "  ],\n"
            "  \"c\": {},\n"
            "  \"d\": [],\n"
            "  \"e\": {\n"
            "    \"f\": [[1.0], {\"g\": \"h\"}]\n"
            "  }\n"
            "}");
}

TEST(JsonWriter, WrapEverythingIsTheLayoutOfNlohmannDump2) {
  const std::string text = Document(JsonWriter::kWrapEverything);
  const nlohmann::ordered_json parsed = nlohmann::ordered_json::parse(text);
  EXPECT_EQ(text, parsed.dump(2));
}

TEST(JsonWriter, DoublesReadBackBitForBit) {
  const double values[] = {0.1,
                           -2.0,
                           1e5,
                           1e-4,
                           1e300,
                           -0.0,
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::max(),
                           0.1 + 0.2};
  std::string out;
  JsonWriter json(&out);
  json.Doubles(values, static_cast<int>(std::size(values)));
  const nlohmann::json parsed = nlohmann::json::parse(out);
  ASSERT_EQ(parsed.size(), std::size(values));
  for (std::size_t i = 0; i < std::size(values); ++i) {
    ASSERT_TRUE(parsed[i].is_number_float()) << out;
    const double read = parsed[i].get<double>();
    EXPECT_EQ(std::memcmp(&read, &values[i], sizeof(double)), 0)
        << i << ": " << out;
  }
  EXPECT_EQ(out,
            "[0.1,-2.0,1e+05,1e-04,1e+300,-0.0,5e-324,"
            "1.7976931348623157e+308,0.30000000000000004]");
}

TEST(JsonWriter, NonFiniteNumbersAreNull) {
  std::string out;
  JsonWriter json(&out);
  json.BeginArray()
      .Double(std::nan(""))
      .Double(std::numeric_limits<double>::infinity())
      .Double(-std::numeric_limits<double>::infinity())
      .EndArray();
  EXPECT_EQ(out, "[null,null,null]");
}

TEST(JsonWriter, StringsAndKeysAreEscaped) {
  std::string out;
  JsonWriter json(&out);
  json.BeginObject().Member("k\\\n", std::string("a\tb\x01\x1f\xc3\xa9", 7));
  json.EndObject();
  EXPECT_EQ(out, "{\"k\\\\\\n\":\"a\\tb\\u0001\\u001f\xc3\xa9\"}");
  const nlohmann::json parsed = nlohmann::json::parse(out);
  EXPECT_EQ(parsed.at("k\\\n").get<std::string>(),
            std::string("a\tb\x01\x1f\xc3\xa9", 7));
}

TEST(JsonWriter, IntegersAreWrittenExactly) {
  std::string out;
  JsonWriter json(&out);
  json.BeginArray()
      .Int(std::numeric_limits<int64_t>::min())
      .Int(std::numeric_limits<int64_t>::max())
      .Int(0)
      .EndArray();
  EXPECT_EQ(out, "[-9223372036854775808,9223372036854775807,0]");
}

TEST(JsonWriterDeathTest, UnbalancedOrMisplacedCallsAreProgrammerErrors) {
  std::string out;
  EXPECT_DEATH(
      {
        JsonWriter json(&out);
        json.BeginObject().EndArray();
      },
      "unbalanced JSON");
  EXPECT_DEATH(
      {
        JsonWriter json(&out);
        json.BeginArray().Key("k");
      },
      "a JSON key outside an object");
  EXPECT_DEATH(
      {
        JsonWriter json(&out);
        json.Int(1).Int(2);
      },
      "a second top-level JSON value");
}

}  // namespace
}  // namespace symba::io_internal
