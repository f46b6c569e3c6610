#include "plant/config_parser.h"

#include <stdint.h>

#include "plant/text_buffer.h"

namespace mb2co {
namespace plant {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}
bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool ends_token(char c) {
  return is_space(c) || c == '=' || c == '#';
}

// One line being parsed: `length` bytes at `begin` (no newline), 1-based number.
struct Line {
  const char* begin;
  size_t length;
  uint32_t number;

  size_t skip_spaces(size_t pos) const {
    while (pos < length && is_space(begin[pos])) ++pos;
    return pos;
  }
  size_t token_end(size_t pos) const {
    while (pos < length && !ends_token(begin[pos])) ++pos;
    return pos;
  }
  bool at_end(size_t pos) const { return pos >= length || begin[pos] == '#'; }
};

TextBuffer fail(ConfigError& error, const Line& line, size_t pos) {
  error.line = line.number;
  error.column = static_cast<uint32_t>(pos + 1u);
  return TextBuffer(error.message, sizeof error.message);
}

// Where a key's value was set; line 0 = not in the file (default).
struct Seen {
  uint32_t line;
  uint32_t column;
};

// Parses one line into `config`, noting in `seen` where each key was set.
bool parse_line(const Line& line, PlantConfig& config, Seen* seen, ConfigError& error) {
  const size_t key_begin = line.skip_spaces(0);
  if (line.at_end(key_begin)) return true;  // blank or comment
  const size_t key_end = line.token_end(key_begin);
  const size_t eq = line.skip_spaces(key_end);
  if (key_end == key_begin) {
    fail(error, line, key_begin).add("missing key before '='");
    return false;
  }
  if (eq >= line.length || line.begin[eq] != '=') {
    fail(error, line, eq).add("expected '=' after ").add_quoted(line.begin + key_begin, key_end - key_begin);
    return false;
  }
  const size_t key = find_config_key(line.begin + key_begin, key_end - key_begin);
  if (key == kConfigKeyCount) {
    fail(error, line, key_begin).add("unknown key ").add_quoted(line.begin + key_begin, key_end - key_begin);
    return false;
  }
  const ConfigKey& spec = config_key(key);
  if (seen[key].line != 0u) {
    fail(error, line, key_begin)
        .add(spec.name)
        .add(": duplicate key (first set on line ")
        .add_u32(seen[key].line)
        .add(")");
    return false;
  }
  const size_t value_begin = line.skip_spaces(eq + 1u);
  if (line.at_end(value_begin)) {
    fail(error, line, value_begin).add(spec.name).add(": missing value");
    return false;
  }
  const size_t value_end = line.token_end(value_begin);
  uint32_t value = 0;
  for (size_t i = value_begin; i < value_end; ++i) {
    const char c = line.begin[i];
    const uint32_t digit = static_cast<uint32_t>(c - '0');
    if (!is_digit(c) || value > (UINT32_MAX - digit) / 10u) {
      fail(error, line, value_begin)
          .add(spec.name)
          .add(": bad number ")
          .add_quoted(line.begin + value_begin, value_end - value_begin)
          .add(" (want a decimal integer up to ")
          .add_u32(spec.max)
          .add(")");
      return false;
    }
    value = value * 10u + digit;
  }
  const size_t rest = line.skip_spaces(value_end);
  if (!line.at_end(rest)) {
    fail(error, line, rest).add(spec.name).add(": unexpected text after the value");
    return false;
  }
  if (value < spec.min || value > spec.max) {
    fail(error, line, value_begin)
        .add(spec.name)
        .add(": value ")
        .add_u32(value)
        .add(" out of range ")
        .add_u32(spec.min)
        .add("..")
        .add_u32(spec.max);
    return false;
  }
  config.*spec.field = value;
  seen[key].line = line.number;
  seen[key].column = static_cast<uint32_t>(value_begin + 1u);
  return true;
}

}  // namespace

bool parse_plant_config(const char* text, size_t length, PlantConfig& out, ConfigError& error) {
  PlantConfig config;  // defaults; `out` changes only when all is well
  Seen seen[kConfigKeyCount] = {};

  uint32_t number = 1;
  size_t pos = 0;
  while (pos < length) {
    size_t end = pos;
    while (end < length && text[end] != '\n') ++end;
    const Line line{text + pos, end - pos, number};
    if (!parse_line(line, config, seen, error)) return false;
    pos = end + 1u;
    ++number;
  }

  uint16_t involved = 0;
  if (!check_plant_config(config, error, involved)) {
    // Point at the involved key set last in the file: the likely mistake.
    // (Some key of a failed rule is always in the file, since the defaults
    // pass; line 0 is kept only as a defined answer.)
    error.line = 0;
    error.column = 0;
    for (size_t k = 0; k < kConfigKeyCount; ++k) {
      if ((involved >> k & 1u) != 0u && seen[k].line > error.line) {
        error.line = seen[k].line;
        error.column = seen[k].column;
      }
    }
    return false;
  }
  out = config;
  return true;
}

}  // namespace plant
}  // namespace mb2co
