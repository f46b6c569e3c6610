#include "report.h"

#include <cstdio>

namespace mb2co {
namespace timing_cli {

Cell Cell::str(const std::string& s) {
  return Cell{s, json_string(s)};
}

Cell Cell::integer(uint64_t v) {
  const std::string s = std::to_string(v);
  return Cell{s, s};
}

Cell Cell::boolean(bool v) {
  return Cell{v ? "yes" : "no", v ? "true" : "false"};
}

Cell Cell::null() {
  return Cell{"-", "null"};
}

Cell Cell::id(uint32_t id, bool extended) {
  char text[16];
  std::snprintf(text, sizeof text, extended ? "0x%08X" : "0x%03X", id);
  return Cell{text, std::to_string(id)};
}

Cell Cell::us(uint64_t ns) {
  const std::string s = format_us(ns);
  return Cell{s, s};
}

Cell Cell::real(double v, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return Cell{text, text};
}

Cell Cell::raw_json(const std::string& text, const std::string& json) {
  return Cell{text, json};
}

std::string format_us(uint64_t ns) {
  std::string s = std::to_string(ns / 1000u);
  uint64_t frac = ns % 1000u;
  if (frac == 0) return s;
  char digits[8];
  std::snprintf(digits, sizeof digits, ".%03u", static_cast<unsigned>(frac));
  std::string tail(digits);
  while (tail.back() == '0') tail.pop_back();
  return s + tail;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", static_cast<unsigned>(c));
      out += esc;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

namespace {

void print_table(const Report& r, std::ostream& out) {
  std::vector<size_t> width(r.columns.size());
  for (size_t c = 0; c < r.columns.size(); ++c) width[c] = r.columns[c].size();
  for (const auto& row : r.rows) {
    for (size_t c = 0; c < row.size() && c < width.size(); ++c) {
      if (row[c].text.size() > width[c]) width[c] = row[c].text.size();
    }
  }
  auto line = [&](auto text_of) {
    std::string s;
    for (size_t c = 0; c < width.size(); ++c) {
      const std::string t = text_of(c);
      const std::string pad(width[c] - t.size(), ' ');
      if (c == 0) {  // first column left, others right
        s += t;
        s += pad;
      } else {
        s += "  ";
        s += pad;
        s += t;
      }
    }
    while (!s.empty() && s.back() == ' ') s.pop_back();
    out << s << '\n';
  };
  if (!r.columns.empty()) {
    line([&](size_t c) { return r.columns[c]; });
    for (const auto& row : r.rows) line([&](size_t c) { return row[c].text; });
  }
  if (!r.totals.empty() && !r.columns.empty()) out << '\n';
  for (const auto& t : r.totals) out << t.first << ": " << t.second.text << '\n';
  for (const auto& n : r.notes) out << n << '\n';
}

void print_json(const Report& r, std::ostream& out) {
  out << "{\n";
  for (const auto& t : r.totals) out << "  " << json_string(t.first) << ": " << t.second.json << ",\n";
  out << "  " << json_string(r.rows_key) << ": [";
  for (size_t i = 0; i < r.rows.size(); ++i) {
    out << (i == 0 ? "\n    {" : ",\n    {");
    for (size_t c = 0; c < r.columns.size(); ++c) {
      out << (c == 0 ? "" : ", ") << json_string(r.columns[c]) << ": " << r.rows[i][c].json;
    }
    out << "}";
  }
  out << (r.rows.empty() ? "]\n}\n" : "\n  ]\n}\n");
}

void print_csv(const Report& r, std::ostream& out) {
  for (size_t c = 0; c < r.columns.size(); ++c) out << (c == 0 ? "" : ",") << r.columns[c];
  out << '\n';
  for (const auto& row : r.rows) {
    for (size_t c = 0; c < row.size(); ++c) {
      out << (c == 0 ? "" : ",") << (row[c].json == "null" ? "" : row[c].text);
    }
    out << '\n';
  }
}

}  // namespace

void print_report(const Report& report, Format format, std::ostream& out) {
  switch (format) {
    case Format::kTable:
      print_table(report, out);
      break;
    case Format::kJson:
      print_json(report, out);
      break;
    case Format::kCsv:
      print_csv(report, out);
      break;
  }
}

}  // namespace timing_cli
}  // namespace mb2co
