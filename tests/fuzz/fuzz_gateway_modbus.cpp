// libFuzzer target: the station's Modbus/RTU serial line. The input is a
// stream of records (time gap, byte) handed to a whole Gateway (OD, register
// bank, Modbus slave, line application) at address 1, with the gateway's
// loop run between them:
//   byte 0: gap before the character: bits 0..6 × (bit 7 ? 1000 µs : 10 µs)
//   byte 1: the character
// Invariants (violations abort): every response is a whole ADU for address 1
// with a right CRC; a response only follows a frame (never unprompted);
// afterwards the const entries of the OD are unchanged and a well-formed FC 03
// of holding register 0 is answered correctly.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vector>

#include "fuzz_support.h"
#include "gateway/gateway.h"

namespace {

using namespace mb2co;

struct Line {
  std::vector<std::vector<uint8_t>> responses;
  static bool write(void* ctx, const uint8_t* data, uint16_t len) {
    Line& l = *static_cast<Line*>(ctx);
    fuzz::require(len >= 4, "a response shorter than an exception");
    fuzz::require(data[0] == 1, "a response for another address");
    fuzz::require(fuzz::crc16_modbus(data, len) == 0, "a response with a wrong CRC");
    l.responses.emplace_back(data, data + len);
    return true;
  }
};

bool drop_frame(void*, const CanFrame&) {
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Line line;
  gateway::GatewayPorts ports{CanSink{&drop_frame, nullptr}, modbus::ByteSink{&Line::write, &line}, nullptr,
                              115200};
  gateway::Gateway gw(ports);
  gateway::Gateway* g = &gw;
  uint32_t now = 0xFFFFFFFFu - 3000000u;  // 3 s before the wrap
  g->start(now);
  const std::vector<uint8_t> consts = fuzz::const_values(g->od());
  for (size_t i = 0; i + 1 < size; i += 2) {
    const uint32_t gap = static_cast<uint32_t>(data[i] & 0x7Fu) * ((data[i] & 0x80u) ? 1000u : 10u);
    g->process(now += gap, 0);  // a loop pass at the end of the gap (timers fire late, as on a busy Uno)
    const size_t before = line.responses.size();
    g->on_serial_byte(data[i + 1], now);
    g->process(now, 0);
    fuzz::require(line.responses.size() == before, "a response while a frame is still arriving");
  }
  for (int k = 0; k < 10; ++k) g->process(now += 1000u, 0);  // t3.5 and more: the last frame ends
  fuzz::require(fuzz::const_values(g->od()) == consts, "a const entry changed");

  // A well-formed request still gets its answer.
  const uint8_t request[] = {1, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A};
  now += 5000u;
  g->process(now, 0);
  line.responses.clear();
  for (uint8_t b : request) g->on_serial_byte(b, now += 90u);
  for (int k = 0; k < 10; ++k) g->process(now += 1000u, 0);
  fuzz::require(line.responses.size() == 1 && line.responses[0].size() == 7 && line.responses[0][1] == 0x03,
                "no answer to FC 03 after the input");
  const uint16_t row = g->od().find(0x2100, 1);
  fuzz::require(line.responses[0][4] == static_cast<uint8_t>(g->od().get(row)),
                "FC 03 answered a wrong value");
  return 0;
}
