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

Status message_set_option(const Options& o, std::vector<timing::MessageSpec>& set, uint32_t* bitrate_bps) {
  if (o.has("--line")) {
    if (!o.positional.empty()) {
      return Status::failure("give FILE.csv or --line N, not both");
    }
    timing::LineCanConfig cfg;
    Status s = line_config_option(o, &cfg);
    if (!s) return s;
    set.resize(timing::line_message_count(cfg));
    size_t count = 0;
    const timing::LineStatus status = timing::build_line_messages(cfg, set.data(), set.size(), &count);
    if (status != timing::LineStatus::kOk) {
      return Status::failure(line_status_text(status));
    }
    set.resize(count);
    *bitrate_bps = cfg.bitrate_bps;
    return Status::ok();
  }
  for (const char* name : kLineOptions) {
    if (o.has(name)) {
      return Status::failure(std::string("option ") + name + " describes a line: add --line N");
    }
  }
  if (o.positional.size() != 1) {
    return Status::failure(o.positional.empty() ? "missing FILE.csv (or --line N)"
                                                : "unexpected argument \"" + o.positional[1] + "\"");
  }
  if (!o.has("--bitrate")) {
    return Status::failure("missing --bitrate B (bit/s) for " + o.positional[0]);
  }
  uint64_t bitrate = 0;
  Status s = uint_option(o, "--bitrate", 1, timing::kMaxBitrateBps, 0, true, &bitrate);
  if (!s) return s;
  if (!(s = read_message_csv(o.positional[0], set))) return s;
  timing::sort_by_priority(set.data(), set.size());
  *bitrate_bps = static_cast<uint32_t>(bitrate);
  return Status::ok();
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
  bool deadline_missed = false;
  Status status = parse_options(argc, argv, options);
  if (status) {
    switch (options.command) {
      case kFrame:
        status = frame_command(options, out);
        break;
      case kLoad:
        status = load_command(options, out);
        break;
      case kRta:
        status = rta_command(options, out, &deadline_missed);
        break;
      case kLatency:
        status = latency_command(options, out);
        break;
    }
  }
  if (!status) {
    err << program << ": " << status.message() << '\n';
    return 1;
  }
  return deadline_missed ? 3 : 0;
}

}  // namespace timing_cli
}  // namespace mb2co
