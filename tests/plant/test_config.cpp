// Config file parsing: the documented example, every kind of bad input with
// its line and column, and the cross-checks that keep the station safe.
#include <gtest/gtest.h>
#include <string.h>

#include <fstream>
#include <sstream>
#include <string>

#include "plant/config_parser.h"
#include "plant/plant_config.h"

namespace mb2co {
namespace plant {
namespace {

std::string read_file(const char* path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool parse(const std::string& text, PlantConfig& out, ConfigError& error) {
  return parse_plant_config(text.data(), text.size(), out, error);
}

// Parses text that must fail; returns the error.
ConfigError parse_error(const std::string& text) {
  PlantConfig out;
  ConfigError error{};
  EXPECT_FALSE(parse(text, out, error)) << text;
  return error;
}

bool same(const PlantConfig& a, const PlantConfig& b) {
  for (size_t i = 0; i < kConfigKeyCount; ++i) {
    if (a.*config_key(i).field != b.*config_key(i).field) return false;
  }
  return true;
}

TEST(PlantConfig, DefaultsPassTheChecks) {
  ConfigError error{};
  uint16_t involved = 0;
  EXPECT_TRUE(check_plant_config(PlantConfig(), error, involved));
}

TEST(PlantConfig, DerivedQuantitiesOfTheDefaults) {
  const PlantConfig c;
  EXPECT_EQ(travel_um_per_step(c), 1000u);  // 100 mm/s * 10 ms
  EXPECT_EQ(flow_ul_per_step(c), 1000u);    // 100 mL/s * 10 ms
  EXPECT_EQ(approach_steps(c), 10u);        // half the 20 mm window at 1 mm/step
  EXPECT_EQ(nominal_fill_steps(c), 500u);   // 500 mL at 1 mL/step
  EXPECT_EQ(fill_timeout_steps(c), 1000u);
}

TEST(PlantConfig, ExampleFileHoldsExactlyTheDefaults) {
  const std::string text = read_file(MB2CO_PLANT_EXAMPLE_CONF);
  ASSERT_FALSE(text.empty()) << MB2CO_PLANT_EXAMPLE_CONF;
  PlantConfig out;
  out.step_ms = 7;  // must be overwritten
  ConfigError error{};
  ASSERT_TRUE(parse(text, out, error)) << error.line << ":" << error.column << ": " << error.message;
  EXPECT_TRUE(same(out, PlantConfig()));
  for (size_t i = 0; i < kConfigKeyCount; ++i) {  // and it mentions every key
    EXPECT_NE(text.find(std::string(config_key(i).name) + " "), std::string::npos) << config_key(i).name;
  }
}

TEST(PlantConfig, DocTableStatesEveryKeyWithDefaultAndRange) {
  const std::string doc = read_file(MB2CO_PLANT_DOC);
  ASSERT_FALSE(doc.empty());
  const PlantConfig defaults;
  for (size_t i = 0; i < kConfigKeyCount; ++i) {
    const ConfigKey& k = config_key(i);
    const std::string row = "| `" + std::string(k.name) + "` | " + std::to_string(defaults.*k.field) + " | " +
                            std::to_string(k.min) + ".." + std::to_string(k.max) + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "docs/plant.md lacks the row " << row;
  }
}

TEST(PlantConfigParser, EmptyTextGivesDefaults) {
  PlantConfig out;
  out.fill_flow_ml_s = 1;
  ConfigError error{};
  ASSERT_TRUE(parse("", out, error));
  EXPECT_TRUE(same(out, PlantConfig()));
}

TEST(PlantConfigParser, CommentsBlanksTabsCrlfAndMissingFinalNewline) {
  PlantConfig out;
  ConfigError error{};
  ASSERT_TRUE(
      parse("# header\r\n\r\n\t  \n  step_ms\t=\t5   # half the step\r\nfill_level_ml=480", out, error))
      << error.message;
  EXPECT_EQ(out.step_ms, 5u);
  EXPECT_EQ(out.fill_level_ml, 480u);
  EXPECT_EQ(out.conveyor_speed_mm_s, PlantConfig().conveyor_speed_mm_s);
}

TEST(PlantConfigParser, EveryKeyIsSettable) {
  // A value other than the default that keeps all cross-checks happy.
  const uint32_t values[kConfigKeyCount] = {5, 120, 1200, 250, 600, 30, 30, 400, 420, 450, 150, 9000};
  std::string text;
  for (size_t i = 0; i < kConfigKeyCount; ++i) {
    text += std::string(config_key(i).name) + " = " + std::to_string(values[i]) + "\n";
  }
  PlantConfig out;
  ConfigError error{};
  ASSERT_TRUE(parse(text, out, error)) << error.line << ": " << error.message;
  for (size_t i = 0; i < kConfigKeyCount; ++i) EXPECT_EQ(out.*config_key(i).field, values[i]) << i;
}

// Syntax errors: where they are reported and what is said.
TEST(PlantConfigParser, SyntaxErrorsNameLineAndColumn) {
  const struct {
    const char* text;
    uint32_t line;
    uint32_t column;
    const char* message;
  } cases[] = {
      {"step_ms = 10\n  belt_speed = 3\n", 2, 3, "unknown key 'belt_speed'"},
      {"st\x1b[2Jep = 1\n", 1, 1, "unknown key 'st?[2Jep'"},  // no control codes echoed
      {"\nstep_ms 10\n", 2, 9, "expected '=' after 'step_ms'"},
      {" = 10\n", 1, 2, "missing key before '='"},
      {"step_ms =   # nothing\n", 1, 13, "step_ms: missing value"},
      {"step_ms = 10 ms\n", 1, 14, "step_ms: unexpected text after the value"},
      {"step_ms = 10\n\nstep_ms = 10\n", 3, 1, "step_ms: duplicate key (first set on line 1)"},
  };
  for (const auto& c : cases) {
    const ConfigError e = parse_error(c.text);
    EXPECT_EQ(e.line, c.line) << c.text;
    EXPECT_EQ(e.column, c.column) << c.text;
    EXPECT_STREQ(e.message, c.message);
  }
}

TEST(PlantConfigParser, BadNumbers) {
  for (const char* value : {"-5", "1.5", "0x10", "ten", "12ms", "+3"}) {
    const ConfigError e = parse_error(std::string("step_ms = ") + value + "\n");
    EXPECT_EQ(e.line, 1u);
    EXPECT_EQ(e.column, 11u);
    EXPECT_EQ(std::string(e.message),
              std::string("step_ms: bad number '") + value + "' (want a decimal integer up to 1000)");
  }
}

TEST(PlantConfigParser, NumberBeyondUint32IsBadNotWrapped) {
  const ConfigError e = parse_error("fill_timeout_ms = 4294967296\n");  // 2^32 would wrap to 0
  EXPECT_EQ(e.column, 19u);
  EXPECT_NE(std::string(e.message).find("bad number '4294967296'"), std::string::npos) << e.message;
  // 2^32 - 1 itself is a number, just out of range.
  const ConfigError range = parse_error("fill_timeout_ms = 4294967295\n");
  EXPECT_STREQ(range.message, "fill_timeout_ms: value 4294967295 out of range 1..3600000");
}

TEST(PlantConfigParser, OutOfRangeBothEndsOfEveryKey) {
  for (size_t i = 0; i < kConfigKeyCount; ++i) {
    const ConfigKey& k = config_key(i);
    const std::string prefix = std::string(k.name) + " = ";
    const ConfigError high = parse_error("# x\n" + prefix + std::to_string(k.max + 1u) + "\n");
    EXPECT_EQ(high.line, 2u);
    EXPECT_EQ(high.column, prefix.size() + 1u);
    EXPECT_EQ(std::string(high.message), std::string(k.name) + ": value " + std::to_string(k.max + 1u) +
                                             " out of range " + std::to_string(k.min) + ".." +
                                             std::to_string(k.max));
    if (k.min > 0u) {
      const ConfigError low = parse_error(prefix + std::to_string(k.min - 1u));
      EXPECT_NE(std::string(low.message).find("out of range"), std::string::npos) << k.name;
    }
  }
}

TEST(PlantConfigParser, FailureLeavesOutputUntouched) {
  PlantConfig out;
  out.step_ms = 7;
  out.fill_level_ml = 123;
  ConfigError error{};
  EXPECT_FALSE(parse("fill_level_ml = 400\nstep_ms = 2000\n", out, error));
  EXPECT_EQ(out.step_ms, 7u);
  EXPECT_EQ(out.fill_level_ml, 123u);
}

TEST(PlantConfigParser, CrossCheckNamesTheLineOfTheKeyToChange) {
  // 1100 mL/s at 10 ms pours 11 mL per step: from 499 mL (not yet full) the
  // level could reach 510+ mL, past overfill_ml.
  const ConfigError e = parse_error("# flow\n\nfill_flow_ml_s   = 1100\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_EQ(e.column, 20u);
  EXPECT_STREQ(e.message,
               "one step of flow (fill_flow_ml_s x step_ms = 11000 uL) is more than "
               "overfill_ml - fill_level_ml: bottles could overfill");
}

TEST(PlantConfigParser, CrossCheckPointsAtTheInvolvedKeySetLast) {
  // 400 mL at 0.1 mL per step take 4000 steps: the default timeout (1000
  // steps) no longer fits. Both keys are involved; line 3 set the later one.
  const ConfigError e = parse_error("fill_level_ml = 400\nstep_ms = 10\nfill_flow_ml_s = 10\n");
  EXPECT_EQ(e.line, 3u);
  EXPECT_EQ(e.column, 18u);
  EXPECT_STREQ(e.message, "fill_timeout_ms must be longer than the nominal fill time (40000 ms)");
}

// Each cross-check rejects the configuration it exists for, blaming line 1.
TEST(PlantConfigChecks, EachRuleRejectsItsCase) {
  const struct {
    const char* text;
    const char* message_start;
  } cases[] = {
      {"overfill_ml = 500\n", "need fill_level_ml < overfill_ml"},               // not above the fill level
      {"bottle_capacity_ml = 505\n", "need fill_level_ml < overfill_ml"},        // overfill above capacity
      {"fill_flow_ml_s = 1001\n", "one step of flow"},                           // 10.01 mL > 10 mL margin
      {"conveyor_speed_mm_s = 1001\n", "the conveyor moves 10010 um per step"},  // > half the window
      {"bottle_spacing_mm = 20\n", "bottle_spacing_mm must exceed"},             // two bottles in one window
      {"valve_position_mm = 20\n", "valve_position_mm must exceed"},          // sensor window at the infeed
      {"valve_position_mm = 980\n", "valve_position_mm + sensor_window_mm"},  // window reaches the hand-off
      {"bottle_spacing_mm = 60\n", "more than 16 bottles"},                   // 17 bottles on a 1 m belt
      {"fill_timeout_ms = 5000\n", "fill_timeout_ms must be longer"},         // not longer than 500 steps
  };
  for (const auto& c : cases) {
    PlantConfig out;
    ConfigError error{};
    ASSERT_FALSE(parse(c.text, out, error)) << c.text;
    EXPECT_EQ(std::string(error.message).rfind(c.message_start, 0), 0u) << c.text << " -> " << error.message;
    EXPECT_EQ(error.line, 1u) << c.text;
  }
}

uint16_t bit(const char* key) {
  return static_cast<uint16_t>(1u << find_config_key(key, strlen(key)));
}

TEST(PlantConfigChecks, FlowMarginBoundaryIsExact) {
  PlantConfig c;
  ConfigError error{};
  uint16_t involved = 0;
  c.fill_flow_ml_s = 1000;  // exactly 10 mL per step = the margin: level stays <= 510
  EXPECT_TRUE(check_plant_config(c, error, involved)) << error.message;
  c.fill_flow_ml_s = 1001;
  EXPECT_FALSE(check_plant_config(c, error, involved));
  EXPECT_EQ(involved, bit("fill_flow_ml_s") | bit("step_ms") | bit("fill_level_ml") | bit("overfill_ml"));
}

TEST(PlantConfigChecks, TravelBoundaryIsExact) {
  PlantConfig c;
  ConfigError error{};
  uint16_t involved = 0;
  c.conveyor_speed_mm_s = 1000;  // 10 mm per step = half the 20 mm window
  EXPECT_TRUE(check_plant_config(c, error, involved)) << error.message;
  c.conveyor_speed_mm_s = 1001;
  EXPECT_FALSE(check_plant_config(c, error, involved));
  EXPECT_EQ(involved, bit("conveyor_speed_mm_s") | bit("step_ms") | bit("sensor_window_mm"));
}

TEST(PlantConfigChecks, RangesAreCheckedForConfigsBuiltInCode) {
  PlantConfig c;
  c.step_ms = 0;
  ConfigError error{};
  uint16_t involved = 0;
  EXPECT_FALSE(check_plant_config(c, error, involved));
  EXPECT_EQ(involved, bit("step_ms"));
  EXPECT_STREQ(error.message, "step_ms: value 0 out of range 1..1000");
}

TEST(PlantConfigKeys, LookupByName) {
  EXPECT_EQ(find_config_key("step_ms", 7), 0u);
  EXPECT_EQ(find_config_key("step_msX", 7), 0u);  // length-delimited
  EXPECT_EQ(find_config_key("step_m", 6), kConfigKeyCount);
  EXPECT_EQ(find_config_key("", 0), kConfigKeyCount);
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
