// `mb2co-timing latency`: the button-to-LED bound of seed 000 §11 for both
// paths, with the CAN hops taken from the analysis of the line.
#include <cstring>

#include "command_parts.h"
#include "timing/line_latency.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

Status serial_options(const Options& o, timing::LatencyParams& p) {
  uint64_t v = 0;
  Status s = uint_option(o, "--baud", 1, 10000000, p.serial.baud, &v);
  if (!s) return s;
  p.serial.baud = static_cast<uint32_t>(v);
  if (!(s = uint_option(o, "--stop-bits", 1, 2, p.serial.stop_bits, &v))) return s;
  p.serial.stop_bits = static_cast<uint8_t>(v);
  p.serial.parity = o.args.parity("--parity", p.serial.parity);
  p.slave_waits_t35 = !o.has("--no-t35");
  return Status::ok();
}

Status time_options(const Options& o, timing::LatencyParams& p) {
  struct {
    const char* name;
    uint32_t* field;
  } const fields[] = {{"--debounce-us", &p.debounce_us},
                      {"--fw-loop-us", &p.fw_loop_us},
                      {"--pc-cycle-us", &p.pc_cycle_us},
                      {"--pc-compute-us", &p.pc_compute_us},
                      {"--master-end-us", &p.master_end_us}};
  for (const auto& f : fields) {
    uint64_t v = 0;
    Status s = uint_option(o, f.name, 0, 100000000, *f.field, &v);
    if (!s) return s;
    *f.field = static_cast<uint32_t>(v);
  }
  return Status::ok();
}

const timing::LatencyTerm* find_term(const timing::LatencyBound& b, const char* name) {
  for (size_t i = 0; i < b.count; ++i) {
    if (std::strcmp(b.terms[i].name, name) == 0) return &b.terms[i];
  }
  return nullptr;
}

}  // namespace

Status latency_command(const Options& o, std::ostream& out) {
  timing::WorstCase convention = timing::WorstCase::kDavis;
  Format format = Format::kTable;
  timing::LineCanConfig line;
  timing::LatencyParams p;
  uint64_t button_node = 0;
  uint64_t pc_node = 0;
  Status s = frame_bits_option(o, &convention);
  if (s) s = format_option(o, &format);
  if (s) s = line_config_option(o, &line);
  if (s) s = serial_options(o, p);
  if (s) s = time_options(o, p);
  if (s) s = uint_option(o, "--button-node", 1, timing::kMaxStations, kDefaultButtonNode, &button_node);
  if (s) s = uint_option(o, "--pc-node", 1, timing::kMaxStations, kDefaultPcNode, &pc_node);
  if (!s) return s;
  p.inhibit_us = uint32_t{line.tpdo1_inhibit_100us} * 100u;

  const size_t capacity = timing::line_message_count(line);
  std::vector<timing::MessageSpec> specs(capacity);
  std::vector<timing::RtaMessage> rta(capacity);
  std::vector<timing::RtaResult> results(capacity);
  const timing::LineScratch scratch{specs.data(), rta.data(), results.data(), capacity};
  timing::LineStatus line_status = timing::LineStatus::kOk;
  switch (timing::fill_can_hops(line, convention, static_cast<uint8_t>(button_node),
                                static_cast<uint8_t>(pc_node), scratch, &p, &line_status)) {
    case timing::HopStatus::kOk:
      break;
    case timing::HopStatus::kLine:
      return Status::failure(line_status_text(line_status));
    case timing::HopStatus::kNoTpdo1:
      return Status::failure("the latency path needs TPDO1 (drop --no-tpdo1)");
    case timing::HopStatus::kNode:
      return Status::failure("--button-node and --pc-node must be different nodes within 1..--line");
    case timing::HopStatus::kUnbounded:
      return Status::failure("a TPDO1 of the path has no bounded response time on this line");
  }

  const timing::LatencyBound modbus = timing::modbus_only_latency(p);
  const timing::LatencyBound canopen = timing::modbus_canopen_latency(p);
  const timing::PollCycle cycle = timing::poll_cycle(p);

  Report r;
  r.rows_key = "terms";
  r.columns = {"term", "modbus_best_us", "modbus_worst_us", "canopen_best_us", "canopen_worst_us"};
  auto cells = [](const timing::LatencyTerm* t) {
    return t == nullptr ? std::vector<Cell>{Cell::null(), Cell::null()}
                        : std::vector<Cell>{Cell::us(t->best_ns), Cell::us(t->worst_ns)};
  };
  for (size_t i = 0; i < canopen.count; ++i) {
    const char* name = canopen.terms[i].name;
    std::vector<Cell> row{Cell::str(name)};
    for (const Cell& c : cells(find_term(modbus, name))) row.push_back(c);
    for (const Cell& c : cells(&canopen.terms[i])) row.push_back(c);
    r.rows.push_back(row);
  }
  r.rows.push_back({Cell::str("total"), Cell::us(modbus.best_ns), Cell::us(modbus.worst_ns),
                    Cell::us(canopen.best_ns), Cell::us(canopen.worst_ns)});
  r.totals = {{"modbus_best_us", Cell::us(modbus.best_ns)},
              {"modbus_worst_us", Cell::us(modbus.worst_ns)},
              {"canopen_best_us", Cell::us(canopen.best_ns)},
              {"canopen_worst_us", Cell::us(canopen.worst_ns)},
              {"baud", Cell::integer(p.serial.baud)},
              {"char_bits", Cell::integer(timing::char_bits(p.serial))},
              {"t35_us", Cell::us(timing::t35_ns(p.serial))},
              {"read_request_us", Cell::us(cycle.read.request_ns)},
              {"read_response_us", Cell::us(cycle.read.response_ns)},
              {"write_request_us", Cell::us(cycle.write.request_ns)},
              {"write_response_us", Cell::us(cycle.write.response_ns)},
              {"poll_busy_best_us", Cell::us(cycle.busy_best_ns)},
              {"poll_busy_worst_us", Cell::us(cycle.busy_worst_ns)},
              {"poll_period_us", Cell::us(cycle.period_ns)},
              {"can_bitrate", Cell::integer(line.bitrate_bps)},
              {"frame_bits", Cell::str(frame_bits_name(convention))},
              {"can_up_worst_us", Cell::us(p.can_up_worst_ns)},
              {"can_down_worst_us", Cell::us(p.can_down_worst_ns)}};
  print_report(r, format, out);
  return Status::ok();
}

}  // namespace timing_cli
}  // namespace mb2co
