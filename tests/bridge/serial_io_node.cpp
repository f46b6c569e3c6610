// mb2co-serial-io-node: the I/O node of shared/ionode (the unchanged node
// core) on a serial CANopen segment (shared/serialnet), for the bridge's
// end-to-end test: the segment options of mb2co-bridge plus --node-id and
// --heartbeat-ms. It sets 1019h to the windows per cycle (a poll SYNC carries
// its counter) and 1017h, then runs like the bridge: one poll() loop.
#include <errno.h>
#include <poll.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "ionode/io_node.h"
#include "segment_line.h"
#include "segment_options.h"
#include "serialnet/serial_link.h"
#include "serialnet/serial_node.h"
#include "stop_signal.h"

namespace {

void to_link(void* ctx, uint8_t byte, uint32_t byte_us) {
  static_cast<mb2co::serialnet::SerialLink*>(ctx)->on_byte(byte, byte_us);
}

int usage_error(const std::string& what) {
  std::fprintf(stderr, "mb2co-serial-io-node: %s\n", what.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  bridge::SegmentOptions seg;
  long node_id = 0;
  long heartbeat_ms = 100;
  for (int i = 1; i < argc; ++i) {
    bool taken = false;
    const Status s = bridge::parse_segment_option(argc, argv, &i, &seg, &taken);
    if (!s) return usage_error(s.message());
    if (taken) continue;
    const std::string a = argv[i];
    if ((a == "--node-id" || a == "--heartbeat-ms") && i + 1 < argc) {
      long* target = a == "--node-id" ? &node_id : &heartbeat_ms;
      if (!bridge::parse_number(argv[++i], a == "--node-id" ? 1 : 0, a == "--node-id" ? 126 : 65535, target))
        return usage_error("bad " + a + " '" + argv[i] + "'");
      continue;
    }
    if (a == "--help") {
      std::printf("usage: mb2co-serial-io-node --node-id N --serial PATH|--pty LINK [options]\n%s",
                  bridge::segment_usage());
      return 0;
    }
    return usage_error("unknown option " + a);
  }
  if (node_id < seg.first || node_id > seg.last) return usage_error("--node-id must be one of --nodes");
  serialnet::BusConfig config = {};
  const Status checked = bridge::segment_bus_config(
      seg, seg.token ? serialnet::Access::kToken : serialnet::Access::kPolled, &config);
  if (!checked) return usage_error(checked.message());

  bridge::catch_stop_signals();

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

  while (!bridge::stop_requested()) {
    NextDeadline d(port::monotonic_us());
    io.node().next_deadline(d);
    link.next_deadline(d);
    pollfd fd = {line.fd(), POLLIN, 0};
    if (poll(&fd, 1, bridge::poll_timeout_ms(d)) < 0) {
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
