// --log FILE.csv | FILE.jsonl: every cycle's I/O, one row per cycle. The
// format follows the file name's extension; columns are fixed for a run
// (common ones first, then the mode's).
#pragma once
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cycle_mode.h"
#include "host/status.h"

namespace mb2co {
namespace pcapp {

enum class LogFormat { kCsv, kJsonl };

/// Appends one row (with '\n') to `out`. CSV: values joined by ','; texts
/// are plain words (no quoting needed). JSONL: {"name":value,...}.
void format_csv_header(const std::vector<const char*>& names, std::string& out);
void format_row(LogFormat format, const std::vector<const char*>& names, const std::vector<LogValue>& values,
                std::string& out);

/// Owns the file; rows are buffered by stdio and flushed on close/destruction.
class CycleLog {
 public:
  /// Opens `path` for writing; fails for an unknown extension or a file that
  /// cannot be created.
  Status open(const std::string& path, const std::vector<const char*>& names);
  void write(const std::vector<LogValue>& values);
  void close();
  bool is_open() const { return file_ != nullptr; }
  ~CycleLog() { close(); }

 private:
  std::FILE* file_ = nullptr;
  LogFormat format_ = LogFormat::kCsv;
  std::vector<const char*> names_;
  std::string line_;
};

}  // namespace pcapp
}  // namespace mb2co
