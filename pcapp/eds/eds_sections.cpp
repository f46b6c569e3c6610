#include "eds_sections.h"

#include <strings.h>

#include <cstdio>
#include <map>

namespace mb2co {
namespace eds {
namespace detail {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

bool fail(LineError* error, int line, std::string what) {
  error->line = line;
  error->what = std::move(what);
  return false;
}

}  // namespace

const Entry* Section::find(const std::string& key) const {
  for (const Entry& e : entries) {
    if (strcasecmp(e.key.c_str(), key.c_str()) == 0) return &e;
  }
  return nullptr;
}

KeyValues Section::key_values() const {
  KeyValues kv;
  for (const Entry& e : entries) kv.emplace_back(e.key, e.value);
  return kv;
}

bool split_sections(std::string_view text, std::vector<Section>* sections, LineError* error, int* last_line) {
  std::map<std::string, int> section_lines;  // lower-case name -> header line
  std::map<std::string, int> key_lines;      // keys of the current section
  int line_no = 0;
  *last_line = 1;
  for (size_t pos = 0; pos < text.size();) {  // pos grows by at least 1 per pass
    size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    *last_line = line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    for (const char c : line) {
      const auto u = static_cast<unsigned char>(c);
      if ((u < 0x20 && u != '\t') || u == 0x7F) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "a control character (byte 0x%02X)", u);
        return fail(error, line_no, buf);
      }
    }
    line = trim(line);
    if (line.empty() || line.front() == ';') continue;
    if (line.front() == '[') {
      if (line.back() != ']') return fail(error, line_no, "a section header without ']'");
      const std::string_view name = trim(line.substr(1, line.size() - 2));
      if (name.empty()) return fail(error, line_no, "an empty section name");
      const auto seen = section_lines.emplace(lower(name), line_no);
      if (!seen.second) {
        return fail(error, line_no,
                    "section [" + std::string(name) + "] appears twice (first at line " +
                        std::to_string(seen.first->second) + ")");
      }
      sections->push_back(Section{std::string(name), line_no, {}});
      key_lines.clear();
      continue;
    }
    if (sections->empty()) return fail(error, line_no, "a line before the first [section]");
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos) return fail(error, line_no, "expected key=value");
    const std::string_view key = trim(line.substr(0, eq));
    if (key.empty()) return fail(error, line_no, "an empty key");
    const auto seen = key_lines.emplace(lower(key), line_no);
    if (!seen.second) {
      return fail(error, line_no,
                  "key '" + std::string(key) + "' appears twice in [" + sections->back().name +
                      "] (first at line " + std::to_string(seen.first->second) + ")");
    }
    sections->back().entries.push_back(
        Entry{std::string(key), std::string(trim(line.substr(eq + 1))), line_no});
  }
  return true;
}

}  // namespace detail
}  // namespace eds
}  // namespace mb2co
