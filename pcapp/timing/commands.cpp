#include "commands.h"

#include <string>

#include "command_parts.h"
#include "csv_set.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

const char* const kLineOptions[] = {"--no-tpdo1",      "--tpdo-dlc",         "--tpdo-inhibit-100us",
                                    "--tpdo-event-ms", "--tpdo-deadline-us", "--heartbeat-ms",
                                    "--sync-us",       "--sync-tpdos",       "--sync-dlc",
                                    "--sync-type",     "--jitter-us"};

}  // namespace

bool message_set_option(const Options& o, std::vector<timing::MessageSpec>& set, uint32_t* bitrate_bps,
                        std::string& error) {
  if (o.has("--line")) {
    if (!o.positional.empty()) {
      error = "give FILE.csv or --line N, not both";
      return false;
    }
    timing::LineCanConfig cfg;
    if (!line_config_option(o, &cfg, error)) return false;
    set.resize(timing::line_message_count(cfg));
    size_t count = 0;
    const timing::LineStatus status = timing::build_line_messages(cfg, set.data(), set.size(), &count);
    if (status != timing::LineStatus::kOk) {
      error = line_status_text(status);
      return false;
    }
    set.resize(count);
    *bitrate_bps = cfg.bitrate_bps;
    return true;
  }
  for (const char* name : kLineOptions) {
    if (o.has(name)) {
      error = std::string("option ") + name + " describes a line: add --line N";
      return false;
    }
  }
  if (o.positional.size() != 1) {
    error = o.positional.empty() ? "missing FILE.csv (or --line N)"
                                 : "unexpected argument \"" + o.positional[1] + "\"";
    return false;
  }
  if (!o.has("--bitrate")) {
    error = "missing --bitrate B (bit/s) for " + o.positional[0];
    return false;
  }
  uint64_t bitrate = 0;
  if (!uint_option(o, "--bitrate", 1, timing::kMaxBitrateBps, 0, true, &bitrate, error)) {
    return false;
  }
  if (!read_message_csv(o.positional[0], set, error)) return false;
  timing::sort_by_priority(set.data(), set.size());
  *bitrate_bps = static_cast<uint32_t>(bitrate);
  return true;
}

int run(int argc, char** argv, std::ostream& out, std::ostream& err) {
  const std::string program = "mb2co-timing";
  if (argc < 2) {
    err << program << ": missing command (frame, load, rta, latency); see --help\n";
    return 1;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || first == "help") {
    out << usage_text();
    return 0;
  }
  if (first == "--version") {
    out << program << " 0.1.0\n";
    return 0;
  }
  Options options;
  std::string error;
  int status = 1;
  if (parse_options(argc, argv, options, error)) {
    switch (options.command) {
      case kFrame:
        status = frame_command(options, out, error);
        break;
      case kLoad:
        status = load_command(options, out, error);
        break;
      case kRta:
        status = rta_command(options, out, error);
        break;
      case kLatency:
        status = latency_command(options, out, error);
        break;
    }
  }
  if (status == 1) err << program << ": " << error << '\n';
  return status;
}

}  // namespace timing_cli
}  // namespace mb2co
