// Tests of vcmm/errormodel/json_input.h and of the readers that run it (issue 12): a nesting
// bomb, repeated keys and numbers beyond the double range are refused with the line and the
// key path, never a crash.
#include "vcmm/errormodel/json_input.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/errors.h"

namespace vcmm::errormodel {
namespace {

using Problem = JsonInputCheck::Problem;

TEST(JsonInput, CleanDocumentsPassAndIdsAreRecorded) {
  const auto c = check_json_input(R"({"a": [1, 2.5e3, {"id": "x-1"}], "b": {"c": null}})");
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.ids.at("a[2]"), "x-1");
}

TEST(JsonInput, ANestingBombIsRefusedWithoutRecursion) {
  const std::string bomb(100000, '[');
  const auto c = check_json_input(bomb);
  EXPECT_EQ(c.problem, Problem::too_deep);
  EXPECT_EQ(c.line, 1u);
  // Just within the limit is fine.
  std::string ok(max_json_depth, '[');
  ok += std::string(max_json_depth, ']');
  EXPECT_TRUE(check_json_input(ok).ok());
  std::string over(max_json_depth + 1, '[');
  over += std::string(max_json_depth + 1, ']');
  EXPECT_EQ(check_json_input(over).problem, Problem::too_deep);
}

TEST(JsonInput, RepeatedKeysNameTheObject) {
  const auto c = check_json_input("{\n \"a\": {\"x\": 1,\n \"x\": 2}}");
  EXPECT_EQ(c.problem, Problem::duplicate_key);
  EXPECT_EQ(c.path, "a");
  EXPECT_EQ(c.message, "x");
}

TEST(JsonInput, NumbersBeyondDoubleAndSyntaxErrorsGiveTheLine) {
  const auto big = check_json_input("{\n \"a\": 1,\n \"b\": 1e999\n}");
  EXPECT_EQ(big.problem, Problem::syntax);
  EXPECT_EQ(big.line, 3u);
  EXPECT_NE(big.message.find("1e999"), std::string::npos) << big.message;
  const auto bad = check_json_input("{\"a\": tru}");
  EXPECT_EQ(bad.problem, Problem::syntax);
  EXPECT_EQ(bad.line, 1u);
}

// The model reader (and through it every command that reads a model) runs the guard.
TEST(JsonInput, TheModelReaderRefusesAllThreeWithItsOwnError) {
  auto message = [](const std::string& text) {
    try {
      parse_digital_model(text, "m.json");
    } catch (const InvalidParameter& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message(std::string(100000, '[')).find("nesting deeper than 64"), std::string::npos);
  EXPECT_NE(message(R"({"schema": "vcmm.digital_model", "schema": "x"})").find("appears twice"),
            std::string::npos);
  const std::string big = message("{\"schema_version\": 1e999}");
  EXPECT_NE(big.find("m.json:1: not valid JSON"), std::string::npos) << big;
}

}  // namespace
}  // namespace vcmm::errormodel
