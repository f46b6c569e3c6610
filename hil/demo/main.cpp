// mb2co-demo: a CANopen master (scripted) and the CiA 401 I/O test node (the
// real portable core) on an in-process bus, every frame printed raw and
// decoded. The frame exchange of seed 004 §2.11 first, then segmented SDO,
// an SDO abort, EMCY, SYNC-driven TPDOs, NMT stop and reset.
#include <cstdio>
#include <initializer_list>
#include <iostream>
#include <string>

#include "canopen_text.h"
#include "host/cli.h"
#include "ionode/io_node.h"

namespace {

using mb2co::CanFrame;

uint32_t g_now_us = 0;

void print(const char* who, const CanFrame& f) {
  std::printf("%9.3f  %-7s %-32s %s\n", g_now_us / 1000.0, who, mb2co::hil::frame_bytes(f).c_str(),
              mb2co::hil::describe(f).c_str());
}

bool node_sends(void*, const CanFrame& f) {
  print("node ->", f);
  return true;
}

CanFrame frame(uint32_t id, std::initializer_list<uint8_t> bytes) {
  CanFrame f = {};
  f.id = id;
  for (uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

void say(const char* text) {
  std::printf("\n-- %s\n", text);
}

// No options: the table gives --help, --version and the usage errors of
// docs/cli.md.
mb2co::cli::Program make_program() {
  mb2co::cli::Program p;
  p.name = "mb2co-demo";
  p.description =
      "Runs a scripted CANopen master against the I/O test node (id 3, the portable core)\n"
      "on an in-process bus and prints every frame, raw and decoded.\n";
  p.commands = {mb2co::cli::Command{}};
  p.footer = "\nexit status: 0 done, 2 usage error\n";
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  const mb2co::cli::Program program = make_program();
  const mb2co::cli::Parsed parsed = mb2co::cli::parse(program, argc, argv);
  const int early = mb2co::cli::finish_early(program, parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  mb2co::ionode::IoNode node(mb2co::CanSink{&node_sends, nullptr}, 0x00030191u);
  auto master = [&](std::initializer_list<uint8_t> bytes, uint32_t id) {
    const CanFrame f = frame(id, bytes);
    print("master>", f);
    node.receive(f, g_now_us);
    node.process(g_now_us);
  };
  auto run_ms = [&](uint32_t ms) {
    for (uint32_t i = 0; i < ms; ++i) node.process(g_now_us += 1000);
  };

  std::printf("mb2co demo: CANopen master and I/O node 3 (device type 00030191h)\n");
  std::printf("%9s  %-7s %-32s %s\n", "t/ms", "from", "frame", "meaning");
  say("power on: boot-up, then pre-operational (seed 004 section 2.11 from here)");
  node.start(3, g_now_us);
  run_ms(1);
  master({0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}, 0x603);
  run_ms(1);
  master({0x22, 0x17, 0x10, 0x00, 0xF4, 0x01, 0x00, 0x00}, 0x603);
  run_ms(500);
  master({0x01, 0x03}, 0x000);
  run_ms(499);
  node.set_input(0, 0x02);
  node.set_input(1, 0x81);
  run_ms(1);
  master({0x00, 0x01}, 0x203);
  std::printf("           outputs now 6200h/1 = %02Xh, 6200h/2 = %02Xh\n", node.output(0), node.output(1));

  say("segmented SDO upload of the device name 1008h");
  master({0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 0x603);
  master({0x60, 0, 0, 0, 0, 0, 0, 0}, 0x603);
  master({0x70, 0, 0, 0, 0, 0, 0, 0}, 0x603);

  say("writing a read-only object is refused with a CiA 301 abort code");
  master({0x23, 0x18, 0x10, 0x01, 0x01, 0x00, 0x00, 0x00}, 0x603);

  say("an RPDO one byte short: not applied, EMCY 8210h; the next good one clears it");
  master({0x05}, 0x203);
  run_ms(1);
  master({0x00, 0x00}, 0x203);
  run_ms(1);

  say("remap TPDO2 by the CiA 301 procedure to send the error register at every SYNC");
  master({0x23, 0x01, 0x18, 0x01, 0x83, 0x02, 0x00, 0x80}, 0x603);  // disable (bit 31)
  master({0x2F, 0x01, 0x1A, 0x00, 0x00, 0, 0, 0}, 0x603);           // sub 0 = 0
  master({0x23, 0x01, 0x1A, 0x01, 0x08, 0x00, 0x01, 0x10}, 0x603);  // 1001h/00, 8 bits
  master({0x2F, 0x01, 0x1A, 0x00, 0x01, 0, 0, 0}, 0x603);           // sub 0 = 1
  master({0x2F, 0x01, 0x18, 0x02, 0x01, 0, 0, 0}, 0x603);           // every SYNC
  master({0x23, 0x01, 0x18, 0x01, 0x83, 0x02, 0x00, 0x00}, 0x603);  // enable
  run_ms(10);
  master({}, 0x080);
  run_ms(10);
  master({}, 0x080);

  say("NMT stop: no SDO answer, heartbeat reports stopped; then reset communication");
  master({0x02, 0x03}, 0x000);
  master({0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}, 0x603);
  run_ms(500);
  master({0x82, 0x03}, 0x000);
  run_ms(1);
  master({0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0}, 0x603);
  std::printf("\nDone: every node frame above came from the portable core in shared/canopen.\n");
  return 0;
}
