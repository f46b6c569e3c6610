#include "csv_set.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace mb2co {
namespace timing_cli {
namespace {

using timing::MessageSpec;

enum Column { kName, kId, kExt, kDlc, kPeriod, kDeadline, kJitter, kCUs, kBits, kColumnCount };
const char* const kColumnNames[kColumnCount] = {"name",        "id",        "ext",
                                                "dlc",         "period_us", "deadline_us",
                                                "jitter_us",   "c_us",      "bits"};
constexpr int kRequiredColumns = kPeriod + 1;  // name .. period_us

struct Field {
  std::string text;  // trimmed
  size_t col;        // 1-based column of the field's first character
};

class Failure {
 public:
  Failure(const std::string& source, std::string& error) : source_(source), error_(error) {}
  bool at(size_t line, size_t col, const std::string& what) {
    std::ostringstream s;
    s << source_ << ':' << line << ':' << col << ": " << what;
    error_ = s.str();
    return false;
  }

 private:
  const std::string& source_;
  std::string& error_;
};

std::vector<Field> split(const std::string& line) {
  std::vector<Field> fields;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    const size_t end = comma == std::string::npos ? line.size() : comma;
    size_t a = start;
    size_t b = end;
    while (a < b && (line[a] == ' ' || line[a] == '\t')) ++a;
    while (b > a && (line[b - 1] == ' ' || line[b - 1] == '\t')) --b;
    fields.push_back(Field{line.substr(a, b - a), a + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

// Unsigned integer, decimal or (if allowed) 0x-hex, at most `max`.
bool parse_uint(const std::string& text, bool allow_hex, uint64_t max, uint64_t* value) {
  size_t i = 0;
  int base = 10;
  if (allow_hex && text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    base = 16;
    i = 2;
  }
  if (i == text.size()) return false;
  uint64_t v = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (base == 16 && c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (base == 16 && c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    if (digit < 0) return false;
    const uint64_t d = static_cast<uint64_t>(digit);
    if (d > max || v > (max - d) / static_cast<uint64_t>(base)) return false;
    v = v * static_cast<uint64_t>(base) + static_cast<uint64_t>(digit);
  }
  *value = v;
  return true;
}

class Parser {
 public:
  Parser(const std::string& source, std::string& error) : fail_(source, error) {}

  bool header(const std::vector<Field>& fields, size_t line) {
    index_.assign(kColumnCount, -1);
    for (size_t f = 0; f < fields.size(); ++f) {
      int column = -1;
      for (int c = 0; c < kColumnCount; ++c) {
        if (fields[f].text == kColumnNames[c]) column = c;
      }
      if (column < 0) {
        return fail_.at(line, fields[f].col,
                        "unknown column \"" + fields[f].text +
                            "\" (expected name,id,ext,dlc,period_us and optionally "
                            "deadline_us,jitter_us,c_us,bits)");
      }
      if (index_[static_cast<size_t>(column)] >= 0) {
        return fail_.at(line, fields[f].col, "column \"" + fields[f].text + "\" given twice");
      }
      index_[static_cast<size_t>(column)] = static_cast<int>(f);
    }
    for (int c = 0; c < kRequiredColumns; ++c) {
      if (index_[static_cast<size_t>(c)] < 0) {
        return fail_.at(line, 1, std::string("missing column \"") + kColumnNames[c] + "\"");
      }
    }
    width_ = fields.size();
    return true;
  }

  bool row(const std::vector<Field>& fields, const std::string& text, size_t line,
           std::vector<MessageSpec>& out) {
    if (fields.size() != width_) {
      const size_t col = fields.size() > width_ ? fields[width_].col : text.size() + 1;
      return fail_.at(line, col,
                      "expected " + std::to_string(width_) + " fields, found " +
                          std::to_string(fields.size()));
    }
    line_ = line;
    fields_ = &fields;
    MessageSpec m{};
    uint64_t v = 0;

    const Field& name = cell(kName);
    if (name.text.empty()) return fail_.at(line, name.col, "empty name");
    if (name.text.size() >= timing::kNameCapacity) {
      return fail_.at(line, name.col,
                      "name longer than " + std::to_string(timing::kNameCapacity - 1) +
                          " characters");
    }
    if (!names_.insert(name.text).second) {
      return fail_.at(line, name.col, "name \"" + name.text + "\" used twice");
    }
    timing::set_name(m, name.text.c_str());

    if (!number(kExt, false, 1, "ext must be 0 or 1", &v)) return false;
    m.extended = v == 1;
    const uint64_t id_max = m.extended ? 0x1FFFFFFFu : 0x7FFu;
    if (!number(kId, true, id_max,
                m.extended ? "id must be 0..0x1FFFFFFF for ext=1"
                           : "id must be 0..0x7FF for ext=0 (use ext=1 for 29-bit ids)",
                &v)) {
      return false;
    }
    m.id = static_cast<uint32_t>(v);
    if (!number(kDlc, false, 8, "dlc must be 0..8", &v)) return false;
    m.dlc = static_cast<uint8_t>(v);
    if (!positive(kPeriod, &m.period_us)) return false;
    m.deadline_us = m.period_us;
    if (present(kDeadline) && !positive(kDeadline, &m.deadline_us)) return false;
    if (present(kJitter)) {
      if (!number(kJitter, false, UINT32_MAX, "jitter_us must be an integer 0..4294967295", &v)) {
        return false;
      }
      m.jitter_us = static_cast<uint32_t>(v);
    }
    if (present(kCUs) && !positive(kCUs, &m.c_us)) return false;
    if (present(kBits)) {
      if (present(kCUs)) return fail_.at(line, cell(kBits).col, "give c_us or bits, not both");
      if (!number(kBits, false, UINT16_MAX, "bits must be 1..65535", &v)) return false;
      if (v == 0) return fail_.at(line, cell(kBits).col, "bits must be 1..65535, got \"0\"");
      m.bits = static_cast<uint16_t>(v);
    }

    const uint32_t key = timing::arbitration_key(m.id, m.extended);
    const auto seen = ids_.emplace(key, line);
    if (!seen.second) {
      return fail_.at(line, cell(kId).col,
                      "id " + cell(kId).text + " already used on line " +
                          std::to_string(seen.first->second) + " (CAN ids must be unique)");
    }
    out.push_back(m);
    return true;
  }

 private:
  bool present(Column c) const {
    return index_[c] >= 0 && !(*fields_)[static_cast<size_t>(index_[c])].text.empty();
  }
  const Field& cell(Column c) const { return (*fields_)[static_cast<size_t>(index_[c])]; }

  bool number(Column c, bool hex, uint64_t max, const char* what, uint64_t* v) {
    const Field& f = cell(c);
    if (!parse_uint(f.text, hex, max, v)) {
      return fail_.at(line_, f.col, std::string(what) + ", got \"" + f.text + "\"");
    }
    return true;
  }

  bool positive(Column c, uint32_t* out) {
    uint64_t v = 0;
    const std::string what =
        std::string(kColumnNames[c]) + " must be a whole number of µs 1..4294967295";
    if (!number(c, false, UINT32_MAX, what.c_str(), &v)) return false;
    if (v == 0) return fail_.at(line_, cell(c).col, what + ", got \"0\"");
    *out = static_cast<uint32_t>(v);
    return true;
  }

  Failure fail_;
  std::vector<int> index_;
  size_t width_ = 0;
  size_t line_ = 0;
  const std::vector<Field>* fields_ = nullptr;
  std::set<std::string> names_;
  std::map<uint32_t, size_t> ids_;
};

}  // namespace

bool parse_message_csv(const std::string& text, const std::string& source,
                       std::vector<timing::MessageSpec>& out, std::string& error) {
  out.clear();
  Parser parser(source, error);
  Failure fail(source, error);
  bool have_header = false;
  size_t line_no = 0;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const size_t quote = line.find('"');
    if (quote != std::string::npos) {
      return fail.at(line_no, quote + 1, "quoted fields are not supported");
    }
    const std::vector<Field> fields = split(line);
    if (!have_header) {
      if (!parser.header(fields, line_no)) return false;
      have_header = true;
    } else if (!parser.row(fields, line, line_no, out)) {
      return false;
    }
  }
  if (!have_header) return fail.at(line_no + 1, 1, "empty file: expected a header line");
  if (out.empty()) return fail.at(line_no + 1, 1, "no messages after the header");
  return true;
}

bool read_message_csv(const std::string& path, std::vector<timing::MessageSpec>& out,
                      std::string& error) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  std::ostringstream text;
  text << file.rdbuf();
  return parse_message_csv(text.str(), path, out, error);
}

}  // namespace timing_cli
}  // namespace mb2co
