// One result shape for every subcommand, printed three ways: an aligned table
// for the terminal, JSON (totals as top-level keys plus an array of rows) and
// CSV (the rows only).
#pragma once
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace mb2co {
namespace timing_cli {

/// A value with its terminal/CSV text and its JSON literal.
struct Cell {
  std::string text;
  std::string json;

  static Cell str(const std::string& s);
  static Cell integer(uint64_t v);
  static Cell boolean(bool v);                 ///< "yes"/"no", true/false
  static Cell null();                          ///< "-", null
  static Cell id(uint32_t id, bool extended);  ///< "0x181", 385
  /// A time given in ns, shown in µs with up to 3 decimals ("3500", "8.334").
  static Cell us(uint64_t ns);
  static Cell real(double v, int decimals);
  static Cell raw_json(const std::string& text, const std::string& json);
};

struct Report {
  std::string rows_key = "rows";  ///< JSON name of the rows array
  std::vector<std::string> columns;
  std::vector<std::vector<Cell>> rows;
  std::vector<std::pair<std::string, Cell>> totals;
  std::vector<std::string> notes;  ///< lines shown under the table only
};

enum class Format { kTable, kJson, kCsv };

void print_report(const Report& report, Format format, std::ostream& out);

/// `s` as a quoted, escaped JSON string.
std::string json_string(const std::string& s);

/// ns as µs text: whole µs, plus up to 3 decimals when not whole.
std::string format_us(uint64_t ns);

}  // namespace timing_cli
}  // namespace mb2co
