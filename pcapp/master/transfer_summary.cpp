#include "transfer_summary.h"

#include <cstdio>
#include <sstream>

namespace mb2co {
namespace master {

namespace {

double seconds_of(const Transfer& t) {
  return static_cast<double>(t.elapsed_us()) / 1e6;
}

}  // namespace

std::string transfer_summary(const Transfer& t) {
  const double s = seconds_of(t);
  char line[200];
  std::snprintf(line, sizeof line, "%s %u bytes %s node %u %04Xh/%u in %.3f s (%.1f KiB/s, %s)",
                t.upload ? "uploaded" : "downloaded", static_cast<unsigned>(t.bytes),
                t.upload ? "from" : "to", t.node, t.index, t.sub, s,
                s > 0 ? static_cast<double>(t.bytes) / 1024.0 / s : 0.0,
                t.mode == canopen::kSdoBlock ? (t.crc ? "block with CRC" : "block") : "expedited/segmented");
  return line;
}

std::string transfer_json(const Transfer& t, const std::string& path) {
  std::ostringstream out;
  out << "{\"node\":" << unsigned(t.node) << ",\"file\":\"" << path << "\",\"bytes\":" << t.bytes
      << ",\"seconds\":" << seconds_of(t)
      << ",\"block\":" << (t.mode == canopen::kSdoBlock ? "true" : "false")
      << ",\"crc\":" << (t.crc ? "true" : "false") << "}";
  return out.str();
}

}  // namespace master
}  // namespace mb2co
