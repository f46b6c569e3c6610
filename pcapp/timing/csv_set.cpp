#include "csv_set.h"

#include <sys/stat.h>

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
const char* const kColumnNames[kColumnCount] = {"name",        "id",        "ext",  "dlc", "period_us",
                                                "deadline_us", "jitter_us", "c_us", "bits"};
constexpr int kRequiredColumns = kPeriod + 1;  // name .. period_us

struct Field {
  std::string text;  // trimmed
  size_t col;        // 1-based column of the field's first character
};

class Failure {
 public:
  explicit Failure(const std::string& source) : source_(source) {}
  Status at(size_t line, size_t col, const std::string& what) const {
    std::ostringstream s;
    s << source_ << ':' << line << ':' << col << ": " << what;
    return Status::failure(s.str());
  }

 private:
  const std::string& source_;
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

// A decimal number of µs ("1040", "1040.0", "1040.125") as µs x 10^decimals,
// when it has no significant digit beyond `decimals` and a whole part of at
// most `max_whole`.
bool parse_decimal(const std::string& text, unsigned decimals, uint64_t max_whole, uint64_t* scaled) {
  const size_t dot = text.find('.');
  uint64_t whole = 0;
  if (!parse_uint(text.substr(0, dot), false, max_whole, &whole)) return false;
  uint64_t frac = 0;
  unsigned digits = 0;
  if (dot != std::string::npos) {
    if (dot + 1 == text.size()) return false;
    for (size_t i = dot + 1; i < text.size(); ++i) {
      if (text[i] < '0' || text[i] > '9') return false;
      const unsigned d = static_cast<unsigned>(text[i] - '0');
      if (digits < decimals) {
        frac = frac * 10u + d;
        ++digits;
      } else if (d != 0) {
        return false;  // not exact at this resolution
      }
    }
  }
  uint64_t scale = 1;
  for (unsigned i = 0; i < decimals; ++i) scale *= 10u;
  for (; digits < decimals; ++digits) frac *= 10u;
  *scaled = whole * scale + frac;
  return true;
}

// Length of the UTF-8 sequence at text[i] (1..4), 0 when it is not one
// (overlong forms, surrogates and code points above U+10FFFF included).
size_t utf8_length(const std::string& text, size_t i) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  if (c < 0x80) return 1;
  size_t n = 0;
  unsigned cp = 0;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
    cp = c & 0x1Fu;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    cp = c & 0x0Fu;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    cp = c & 0x07u;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    const unsigned char t = static_cast<unsigned char>(text[i + k]);
    if ((t & 0xC0u) != 0x80u) return 0;
    cp = (cp << 6) | (t & 0x3Fu);
  }
  const unsigned min[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < min[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

/// 0 when `line` is UTF-8 without NUL, else the 1-based column of the first
/// offending byte; *what says which.
size_t bad_byte(const std::string& line, const char** what) {
  for (size_t i = 0; i < line.size();) {
    if (line[i] == '\0') {
      *what = "NUL byte (the file must be text)";
      return i + 1;
    }
    const size_t n = utf8_length(line, i);
    if (n == 0) {
      *what = "not valid UTF-8 (save the file as UTF-8)";
      return i + 1;
    }
    i += n;
  }
  return 0;
}

class Parser {
 public:
  explicit Parser(const std::string& source) : fail_(source) {}

  Status header(const std::vector<Field>& fields, size_t line) {
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
    return Status::ok();
  }

  Status row(const std::vector<Field>& fields, const std::string& text, size_t line,
             std::vector<MessageSpec>& out) {
    if (fields.size() != width_) {
      const size_t col = fields.size() > width_ ? fields[width_].col : text.size() + 1;
      return fail_.at(
          line, col,
          "expected " + std::to_string(width_) + " fields, found " + std::to_string(fields.size()));
    }
    line_ = line;
    fields_ = &fields;
    MessageSpec m{};
    uint64_t v = 0;
    Status s;

    const Field& name = cell(kName);
    if (name.text.empty()) return fail_.at(line, name.col, "empty name");
    if (name.text.size() >= timing::kNameCapacity) {
      return fail_.at(line, name.col,
                      "name longer than " + std::to_string(timing::kNameCapacity - 1) + " characters");
    }
    if (!names_.insert(name.text).second) {
      return fail_.at(line, name.col, "name \"" + name.text + "\" used twice");
    }
    timing::set_name(m, name.text.c_str());

    if (!(s = number(kExt, false, 1, "ext must be 0 or 1", &v))) return s;
    m.extended = v == 1;
    const uint64_t id_max = m.extended ? 0x1FFFFFFFu : 0x7FFu;
    if (!(s = number(kId, true, id_max,
                     m.extended ? "id must be 0..0x1FFFFFFF for ext=1"
                                : "id must be 0..0x7FF for ext=0 (use ext=1 for 29-bit ids)",
                     &v))) {
      return s;
    }
    m.id = static_cast<uint32_t>(v);
    if (!(s = number(kDlc, false, 8, "dlc must be 0..8", &v))) return s;
    m.dlc = static_cast<uint8_t>(v);
    if (!(s = positive(kPeriod, &m.period_us))) return s;
    m.deadline_us = m.period_us;
    if (present(kDeadline) && !(s = positive(kDeadline, &m.deadline_us))) return s;
    if (present(kJitter)) {
      if (!parse_decimal(cell(kJitter).text, 0, UINT32_MAX, &v)) {
        return fail_.at(line, cell(kJitter).col,
                        "jitter_us must be an integer 0..4294967295, got \"" + cell(kJitter).text + "\"");
      }
      m.jitter_us = static_cast<uint32_t>(v);
    }
    if (present(kCUs) && !(s = transmission_time(&m.c_ns))) return s;
    if (present(kBits)) {
      if (present(kCUs)) return fail_.at(line, cell(kBits).col, "give c_us or bits, not both");
      if (!(s = number(kBits, false, UINT16_MAX, "bits must be 1..65535", &v))) return s;
      if (v == 0) return fail_.at(line, cell(kBits).col, "bits must be 1..65535, got \"0\"");
      m.bits = static_cast<uint16_t>(v);
    }

    const uint32_t key = timing::arbitration_key(m.id, m.extended);
    const auto seen = ids_.emplace(key, line);
    if (!seen.second) {
      return fail_.at(line, cell(kId).col,
                      "id " + cell(kId).text + " already used on line " + std::to_string(seen.first->second) +
                          " (CAN ids must be unique)");
    }
    out.push_back(m);
    return Status::ok();
  }

 private:
  bool present(Column c) const {
    return index_[c] >= 0 && !(*fields_)[static_cast<size_t>(index_[c])].text.empty();
  }
  const Field& cell(Column c) const { return (*fields_)[static_cast<size_t>(index_[c])]; }

  Status number(Column c, bool hex, uint64_t max, const char* what, uint64_t* v) {
    const Field& f = cell(c);
    if (!parse_uint(f.text, hex, max, v)) {
      return fail_.at(line_, f.col, std::string(what) + ", got \"" + f.text + "\"");
    }
    return Status::ok();
  }

  Status positive(Column c, uint32_t* out) {
    uint64_t v = 0;
    const std::string what = std::string(kColumnNames[c]) + " must be a whole number of µs 1..4294967295";
    const Field& f = cell(c);
    if (!parse_decimal(f.text, 0, UINT32_MAX, &v)) {
      return fail_.at(line_, f.col, what + ", got \"" + f.text + "\"");
    }
    if (v == 0) return fail_.at(line_, f.col, what + ", got \"" + f.text + "\"");
    *out = static_cast<uint32_t>(v);
    return Status::ok();
  }

  // c_us: µs with up to three decimals, kept in ns.
  Status transmission_time(uint64_t* ns) {
    const Field& f = cell(kCUs);
    const std::string what = "c_us must be µs 0.001..4294967295 with at most 3 decimals";
    if (!parse_decimal(f.text, 3, UINT32_MAX, ns) || *ns == 0) {
      return fail_.at(line_, f.col, what + ", got \"" + f.text + "\"");
    }
    return Status::ok();
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

Status parse_message_csv(const std::string& text, const std::string& source,
                         std::vector<timing::MessageSpec>& out) {
  out.clear();
  Parser parser(source);
  const Failure fail(source);
  bool have_header = false;
  size_t line_no = 0;
  // A UTF-8 byte order mark (Windows editors write one) is no column name.
  const size_t bom = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  std::istringstream in(text.substr(bom));
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const char* what = "";
    const size_t bad = bad_byte(line, &what);
    if (bad != 0) return fail.at(line_no, bad, what);  // columns as an editor shows them (no BOM)
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const size_t quote = line.find('"');
    if (quote != std::string::npos) {
      return fail.at(line_no, quote + 1, "quoted fields are not supported");
    }
    const std::vector<Field> fields = split(line);
    Status s = have_header ? parser.row(fields, line, line_no, out) : parser.header(fields, line_no);
    if (!s) return s;
    have_header = true;
  }
  if (!have_header) return fail.at(line_no + 1, 1, "empty file: expected a header line");
  if (out.empty()) return fail.at(line_no + 1, 1, "no messages after the header");
  return Status::ok();
}

Status read_message_csv(const std::string& path, std::vector<timing::MessageSpec>& out) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    return Status::failure(path + ": cannot open: " + std::strerror(errno));
  }
  struct stat st;
  if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    return Status::failure(path + ": is a directory, not a CSV file");
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) {
    return Status::failure(path + ": cannot read: " + std::strerror(errno));
  }
  return parse_message_csv(text.str(), path, out);
}

}  // namespace timing_cli
}  // namespace mb2co
