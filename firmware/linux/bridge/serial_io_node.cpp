// mb2co-serial-io-node: the I/O node of shared/ionode (the unchanged node
// core) on a serial CANopen segment (shared/serialnet): what the bridge is
// tried and tested with (docs/serial-canopen.md, "Try it"; tests/bridge). The
// segment options of mb2co-bridge plus --node-id and --heartbeat-ms. It sets 1019h to the windows per cycle
// (a poll SYNC carries its counter) and 1017h, then runs like the bridge: one poll() loop.
#include <errno.h>
#include <poll.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "ionode/io_node.h"
#include "platform/stop_signal.h"
#include "segment_line.h"
#include "segment_options.h"
#include "serialnet/serial_link.h"
#include "serialnet/serial_node.h"

namespace {

void to_link(void* ctx, uint8_t byte, uint32_t byte_us) {
  static_cast<mb2co::serialnet::SerialLink*>(ctx)->on_byte(byte, byte_us);
}

int usage_error(const std::string& what) {
  std::fprintf(stderr, "mb2co-serial-io-node: %s\n", what.c_str());
  return mb2co::cli::kExitUsage;
}

mb2co::cli::Program make_program() {
  using namespace mb2co;
  cli::Program p;
  p.name = "mb2co-serial-io-node";
  p.description = "The CiA 401 I/O node on a serial CANopen segment (docs/serial-canopen.md).\n";
  cli::Command c;
  c.options = bridge::segment_options();
  c.options.push_back(cli::uint_range("--node-id", "N", 1, 126, "its node id, one of --nodes (required)"));
  c.options.push_back(cli::uint_range("--heartbeat-ms", "N", 0, 65535, "1017h (default 100)"));
  p.commands = {c};
  p.footer = "\nexit status: 0 on SIGINT/SIGTERM, 1 runtime error, 2 usage error\n";
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  static const cli::Program program = make_program();
  const cli::Parsed parsed = cli::parse(program, argc, argv);
  const int early = cli::finish_early(program, parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  bridge::SegmentOptions seg;
  const Status applied = bridge::apply_segment_options(parsed.args, &seg);
  if (!applied) return usage_error(applied.message());
  const long node_id = static_cast<long>(parsed.args.uint("--node-id", 0));
  const long heartbeat_ms = static_cast<long>(parsed.args.uint("--heartbeat-ms", 100));
  if (node_id < seg.first || node_id > seg.last) return usage_error("--node-id must be one of --nodes");
  serialnet::BusConfig config = {};
  const Status checked = bridge::segment_bus_config(
      seg, seg.token ? serialnet::Access::kToken : serialnet::Access::kPolled, &config);
  if (!checked) return usage_error(checked.message());

  port::catch_stop_signals();
  port::ignore_broken_pipes();

  bridge::SegmentLine line;
  const Status opened = line.open(seg);
  if (!opened) {
    std::fprintf(stderr, "mb2co-serial-io-node: %s\n", opened.message().c_str());
    return 1;
  }
  static serialnet::SerialLink link(config, static_cast<uint8_t>(node_id), line.sink());
  static ionode::IoNode io(link.can_sink());
  link.set_receiver(serialnet::node_receiver(io.node()));

  io.start(static_cast<uint8_t>(node_id), port::monotonic_us());
  const uint8_t windows = seg.bridge_node();
  const uint8_t hb[2] = {static_cast<uint8_t>(heartbeat_ms), static_cast<uint8_t>(heartbeat_ms >> 8)};
  if (io.od().write(0x1019, 0, &windows, 1) != canopen::kSdoOk ||
      io.od().write(0x1017, 0, hb, 2) != canopen::kSdoOk) {
    std::fprintf(stderr, "mb2co-serial-io-node: the OD refused 1019h or 1017h\n");
    return 1;
  }
  std::printf("ready node=%ld serial=%s\n", node_id, line.port().path().c_str());
  std::fflush(stdout);

  while (!port::stop_requested()) {
    NextDeadline d(port::monotonic_us());
    io.node().next_deadline(d);
    link.next_deadline(d);
    pollfd fd = {line.fd(), POLLIN, 0};
    if (poll(&fd, 1, port::poll_timeout_ms(d)) < 0) {
      if (errno == EINTR) continue;
      return 1;
    }
    if (fd.revents & (POLLIN | POLLERR | POLLHUP)) {
      const Status got = line.read(&to_link, &link);
      if (!got) {
        std::fprintf(stderr, "mb2co-serial-io-node: %s\n", got.message().c_str());
        return 1;
      }
    }
    const uint32_t now = port::monotonic_us();
    io.process(now);
    link.process(now);
  }
  return 0;
}
