#include "cycle_log.h"

#include <cerrno>
#include <cstring>

namespace mb2co {
namespace pcapp {

namespace {
bool ends_with(const std::string& s, const char* tail) {
  const size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}
}  // namespace

void format_csv_header(const std::vector<const char*>& names, std::string& out) {
  for (size_t i = 0; i < names.size(); ++i) {
    if (i) out += ',';
    out += names[i];
  }
  out += '\n';
}

void format_row(LogFormat format, const std::vector<const char*>& names, const std::vector<LogValue>& values,
                std::string& out) {
  char number[24];
  if (format == LogFormat::kJsonl) out += '{';
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) out += ',';
    if (format == LogFormat::kJsonl) {
      out += '"';
      out += names[i];
      out += "\":";
    }
    const LogValue& v = values[i];
    if (v.text != nullptr) {
      if (format == LogFormat::kJsonl) out += '"';
      out += v.text;
      if (format == LogFormat::kJsonl) out += '"';
    } else {
      const int n = std::snprintf(number, sizeof number, "%lld", static_cast<long long>(v.number));
      out.append(number, static_cast<size_t>(n));
    }
  }
  if (format == LogFormat::kJsonl) out += '}';
  out += '\n';
}

Status CycleLog::open(const std::string& path, const std::vector<const char*>& names) {
  close();
  if (ends_with(path, ".csv")) {
    format_ = LogFormat::kCsv;
  } else if (ends_with(path, ".jsonl")) {
    format_ = LogFormat::kJsonl;
  } else {
    return Status::failure("--log " + path + ": want a name ending in .csv or .jsonl");
  }
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) {
    return Status::failure("--log " + path + ": " + std::strerror(errno));
  }
  names_ = names;
  if (format_ == LogFormat::kCsv) {
    line_.clear();
    format_csv_header(names_, line_);
    std::fwrite(line_.data(), 1, line_.size(), file_);
  }
  return Status::ok();
}

void CycleLog::write(const std::vector<LogValue>& values) {
  if (file_ == nullptr) return;
  line_.clear();
  format_row(format_, names_, values, line_);
  std::fwrite(line_.data(), 1, line_.size(), file_);
  // One row per cycle (50/s at most): flushed so that a reader (tail -f, the
  // live script's hardware mode) sees each cycle as it happens.
  std::fflush(file_);
}

void CycleLog::close() {
  if (file_ != nullptr) std::fclose(file_);
  file_ = nullptr;
}

}  // namespace pcapp
}  // namespace mb2co
