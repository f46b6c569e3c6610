#include "commands.h"

#include <string>

#include "command_parts.h"
#include "csv_set.h"
#include "host/cli_messages.h"
#include "serial_command.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

const char* const kLineOptions[] = {"--no-tpdo1",      "--tpdo-dlc",         "--tpdo-inhibit-100us",
                                    "--tpdo-event-ms", "--tpdo-deadline-us", "--heartbeat-ms",
                                    "--sync-us",       "--sync-tpdos",       "--sync-dlc",
                                    "--sync-type",     "--jitter-us"};

}  // namespace

Status message_set_option(const Options& o, std::vector<timing::MessageSpec>& set, uint32_t* bitrate_bps,
                          bool* runtime_failure) {
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
      return Status::failure(std::string(name) + " describes a line: add --line N");
    }
  }
  if (o.positional.size() != 1) {
    const std::string command = o.args.command != nullptr ? o.args.command->name : "";
    return Status::failure(o.positional.empty()
                               ? cli::missing_operand(program().name, command, "FILE.csv (or --line N)")
                               : "unexpected argument \"" + o.positional[1] + "\"");
  }
  if (!o.has("--bitrate")) {
    return Status::failure("missing --bitrate B (bit/s) for " + o.positional[0]);
  }
  Status s = read_message_csv(o.positional[0], set);
  if (!s) {
    *runtime_failure = true;
    return s;
  }
  timing::sort_by_priority(set.data(), set.size());
  *bitrate_bps = o.args.bitrate_bps("--bitrate", 0);
  return Status::ok();
}

int run(int argc, char** argv, std::ostream& out, std::ostream& err) {
  const cli::Parsed parsed = cli::parse(program(), argc, argv);
  const int early = cli::finish_early(program(), parsed, out, err);
  if (early >= 0) return early;
  if (parsed.args.command->name == "serial") return serial_run(parsed.args, out, err);
  const Options options = options_of(parsed.args);
  bool deadline_missed = false;
  bool runtime_failure = false;
  Status status;
  switch (options.command) {
    case kFrame:
      status = frame_command(options, out);
      break;
    case kLoad:
      status = load_command(options, out, &runtime_failure);
      break;
    case kRta:
      status = rta_command(options, out, &deadline_missed, &runtime_failure);
      break;
    case kLatency:
      status = latency_command(options, out);
      break;
  }
  if (!status) {
    err << program().name << ": " << status.message() << '\n';
    return runtime_failure ? cli::kExitRuntime : cli::kExitUsage;
  }
  return deadline_missed ? 3 : cli::kExitDone;
}

}  // namespace timing_cli
}  // namespace mb2co
