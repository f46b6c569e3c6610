#include "node_setup.h"

#include <cstdio>

#include "platform/stop_signal.h"
#include "program_data.h"

namespace mb2co {
namespace node {

namespace {

bool serial_write(void* ctx, const uint8_t* data, uint16_t n) {
  return static_cast<port::SerialPort*>(ctx)->write(data, n).is_ok();
}

bool can_discard(void*, const CanFrame&) {
  return true;
}

}  // namespace

NodeWiring::NodeWiring(const NodeOptions& opt)
    : eeprom(opt.eeprom, opt.eeprom_write_us),
      storage(eeprom.storage()),
      with_serial(opt.serial != kNoSerial),
      traced_can(can, trace),
      with_can(opt.can != "none") {}

Status NodeWiring::open(const NodeOptions& opt) {
  if (!opt.eeprom.empty()) {
    Status usable = eeprom.usable();
    if (!usable) return usable;
  }
  // The trace is created here, empty when nothing crossed the bus; with
  // --can none nothing does.
  if (!opt.trace_can.empty()) {
    const Status created = trace.open(opt.trace_can, opt.can);
    if (!created) return Status::failure("--trace-can " + created.message());
  }
  Status opened = !with_serial          ? Status::ok()
                  : !opt.serial.empty() ? serial.open_tty(opt.serial, opt.baud, opt.parity)
                                        : serial.create_pty(opt.pty_link);
  if (!opened) return opened;
  if (!with_can) return Status::ok();
  Status bound = can.open(opt.can.c_str());
  if (bound) bound = can.accept_all();
  return bound;
}

gateway::GatewayPorts NodeWiring::gateway_ports(const NodeOptions& opt) {
  // Queued: a pass's frames (a block upload's sub-block) leave together at
  // its end (the loop's can.flush()), kBatch per system call.
  const CanSink can_sink = !with_can         ? CanSink{&can_discard, nullptr}
                           : trace.is_open() ? traced_can.sink()
                                             : can.queue_sink();
  gateway::GatewayPorts ports{can_sink, modbus::ByteSink{&serial_write, &serial},
                              opt.eeprom.empty() ? nullptr : &storage, opt.baud};
  // Kernel filters from the gateway's acceptance ranges (a flood of other
  // frames never reaches the loop): the core sets them at every reset.
  if (with_can)
    ports.can_control = trace.is_open() ? &TracedCan::kControl : &linux_port::SocketCanPort::kControl;
  return ports;
}

std::string NodeWiring::serial_text(const NodeOptions& opt) const {
  return with_serial ? serial.path() : opt.serial;
}

void serve_program_data(gateway::Gateway& gw) {
  static ProgramData program_data;
  static const canopen::SdoDomain program_data_table = program_data.table();
  gw.node().sdo_server().set_domain(&program_data_table);
  gw.node().sdo_server().set_block_transfer(true);
}

Status start_gateway(gateway::Gateway& gw, const NodeOptions& opt) {
  gw.start(port::monotonic_us(), opt.node_id);
  if (gw.node().storage_damage_count() != 0) {
    std::fprintf(
        stderr, "mb2co-node: warning: %s: %s\n", opt.eeprom.c_str(),
        gw.node().params_loaded()
            ? "a damaged parameter slot was found, the newest valid set is in force (it may be the older one)"
            : "the saved parameters are damaged, defaults are in force");
  }
  canopen::ObjectDictionary& od = gw.od();
  bool reconfigured = false;
  auto set = [&](uint8_t sub, uint32_t v, uint16_t size) {
    uint8_t b[4];
    canopen::put_le32(b, v);
    if (od.write(0x2000, sub, b, size) != canopen::kSdoOk) return false;
    reconfigured = true;
    return true;
  };
  if (opt.bitrate_kbit && !set(2, opt.bitrate_kbit, 2)) return Status::failure("bit rate refused");
  if (opt.topology >= 0 && !set(3, static_cast<uint32_t>(opt.topology), 1))
    return Status::failure("topology refused");
  if (opt.stations && !set(4, opt.stations, 1)) return Status::failure("station count refused");
  if (reconfigured) gw.node().request_reset(canopen::kResetCommunication);
  return Status::ok();
}

}  // namespace node
}  // namespace mb2co
