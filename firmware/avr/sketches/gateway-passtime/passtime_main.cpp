// Pass times of the gateway core on the ATmega328P (run under simavr by
// firmware/avr/measure-pass-time.sh, or on a real Uno: 115200 8N1 on USB).
// No Arduino core: its timer interrupt would be counted into every pass.
// The gateway runs as node 2 of a 4-station ring, operational (self-start),
// CAN frames and serial bytes going into sinks that accept everything.
// Each line is "<what> <µs>"; a Modbus request prints
// "<what> <µs> <µs again> <response bytes> <function code>": handed in byte
// by byte (stamped 96 µs apart, as at 115200 baud), the pass that answers it
// after t3.5 is timed, the first time and the second (the register bank
// then knows the OD rows of the map entries it touched).
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <avr/sleep.h>
#include <stdint.h>

#include "canopen/pdo_map.h"
#include "crc/crc16.h"
#include "filter_plan.h"
#include "gateway/gateway.h"
#include "modbus/master_codec.h"

namespace {

using namespace mb2co;

uint8_t response[96];
uint16_t response_len = 0;

bool can_sink(void*, const CanFrame&) {
  return true;
}
bool serial_sink(void*, const uint8_t* data, uint16_t n) {
  response_len = n;
  for (uint16_t i = 0; i < n && i < sizeof response; ++i) response[i] = data[i];
  return true;
}

// Saved parameters in the EEPROM with the part's timing as a pass sees it:
// a byte programmed keeps the storage busy (EEPE) until the next timed pass,
// 3.3 ms being longer than any pass (plain simavr programs at once).
bool eeprom_busy = false;
bool eeprom_read(void*, uint16_t at, uint8_t* data, uint16_t n) {
  eeprom_read_block(data, reinterpret_cast<const void*>(at), n);
  return true;
}
bool eeprom_write(void*, uint16_t at, const uint8_t* data, uint16_t n) {
  eeprom_update_block(data, reinterpret_cast<void*>(at), n);
  eeprom_busy = true;
  return true;
}
bool eeprom_ready(void*) {
  return !eeprom_busy;
}
const canopen::ParamStorage storage{&eeprom_read, &eeprom_write, nullptr, nullptr, &eeprom_ready};

void put(char c) {
  while (!(UCSR0A & _BV(UDRE0))) {
  }
  UCSR0A |= _BV(TXC0);  // cleared by writing 1: set again when this one is out
  UDR0 = static_cast<uint8_t>(c);
}
// `s` is in flash (PSTR): the names would otherwise take RAM the gateway needs.
void put_P(const char* s) {
  for (char c = static_cast<char>(pgm_read_byte(s)); c != 0; c = static_cast<char>(pgm_read_byte(++s)))
    put(c);
}
void put_number(uint32_t v) {
  char digits[10];
  uint8_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0);
  while (n != 0) put(digits[--n]);
}

// Timer1 at clk/64: 4 µs per tick, 262 ms before it wraps.
void timer_start() {
  TCNT1 = 0;
}
uint32_t timer_us() {
  return static_cast<uint32_t>(TCNT1) * 4u;
}

gateway::Gateway* gw = nullptr;
uint32_t now_us = 0;

void line(const char* what, uint32_t us) {
  put_P(what);
  put(' ');
  put_number(us);
  put('\n');
}

// One request, answered by the pass after it; µs of that pass.
uint32_t answer(const uint8_t* adu, uint16_t n) {
  now_us += 5000;
  gw->process(now_us, 0);
  for (uint16_t i = 0; i < n; ++i) {
    now_us += 96;
    gw->on_serial_byte(adu[i], now_us);
  }
  now_us += 2000;  // past t3.5
  response_len = 0;
  timer_start();
  gw->process(now_us, 0);
  return timer_us();
}

void request(const char* what, const uint8_t* adu, uint16_t n) {
  const uint32_t first_us = answer(adu, n);
  const uint32_t again_us = answer(adu, n);
  put_P(what);
  put(' ');
  put_number(first_us);
  put(' ');
  put_number(again_us);
  put(' ');
  put_number(response_len);
  put(' ');
  put_number(response_len > 1 ? response[1] : 0);
  put('\n');
}

void read_request(const char* what, uint8_t function, uint16_t start, uint16_t count) {
  uint8_t adu[8];
  request(what, adu, modbus::build_read_request(adu, sizeof adu, 1, function, start, count));
}

void frame(const char* what, uint16_t id, uint8_t dlc, uint8_t byte0) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  f.data[0] = byte0;
  now_us += 1000;
  timer_start();
  gw->on_can_frame(f, now_us);
  gw->process(now_us, 0);
  line(what, timer_us());
}

// Building blocks (no pass): the OD's lookup and value access, a TPDO build.
void blocks(gateway::Gateway& g) {
  canopen::ObjectDictionary& od = g.od();
  volatile uint32_t sink = 0;
  timer_start();
  for (uint8_t i = 0; i < 100; ++i) sink = od.find(0x2100, 3);
  line(PSTR("od_find_x100"), timer_us());
  const uint16_t row = od.find(0x2100, 3);
  timer_start();
  for (uint8_t i = 0; i < 100; ++i) sink = od.get(row);
  line(PSTR("od_get_x100"), timer_us());
  uint8_t payload[8];
  timer_start();
  canopen::pdo_build(od, od.find(0x1A00, 0), payload);
  line(PSTR("tpdo1_build"), timer_us());
  (void)sink;
}

// MCP2515 acceptance-filter planning (shared/mcp2515/filter_plan.h) for
// the ids a gateway consumes: node 2 of a 4-station ring (NMT, SYNC, SDO,
// guarding RTR, RPDO1-3, the neighbours' heartbeats: 9 ids), its first 6,
// and 12 (the planner's limit: 3 more heartbeat consumers).
// "filter_plan_ids_<n> <µs> <accepted ids>": the whole plan in one go
// (plan_filters), Timer1 at clk/256 (16 µs ticks, 1 s before it wraps).
// "filter_plan_step_ids_<n> <µs> <steps>": the longest FilterPlanner step,
// i.e. what planning adds to a loop pass (CanPort plans a step per pass),
// the last step included (it also builds the plan), Timer1 at clk/64.
void filter_plans() {
  static const uint16_t kIds[12] = {0x000, 0x080, 0x181, 0x183, 0x281, 0x602,
                                    0x701, 0x702, 0x703, 0x704, 0x705, 0x706};
  static const uint8_t kCounts[3] = {6, 9, 12};
  for (uint8_t k = 0; k < 3; ++k) {
    mcp2515::FilterPlan plan;
    TCCR1B = _BV(CS12);
    TCNT1 = 0;
    const bool ok = mcp2515::plan_filters(kIds, kCounts[k], plan);
    const uint32_t us = static_cast<uint32_t>(TCNT1) * 16u;
    put_P(PSTR("filter_plan_ids_"));
    put_number(kCounts[k]);
    put(' ');
    put_number(us);
    put(' ');
    put_number(ok ? plan.accepted_ids : 0);
    put('\n');

    TCCR1B = _BV(CS11) | _BV(CS10);
    mcp2515::FilterPlanner planner{};
    planner.start(kIds, kCounts[k]);
    uint32_t longest_us = 0;
    uint16_t steps = 0;
    bool last = false;
    while (!last) {
      timer_start();
      last = planner.step();
      if (last) planner.plan(plan);
      const uint32_t step_us = timer_us();
      if (step_us > longest_us) longest_us = step_us;
      ++steps;
    }
    put_P(PSTR("filter_plan_step_ids_"));
    put_number(kCounts[k]);
    put(' ');
    put_number(longest_us);
    put(' ');
    put_number(steps);
    put('\n');
  }
}

}  // namespace

int main() {
  UBRR0H = 0;
  UBRR0L = 8;  // 115200 baud at 16 MHz (U2X0 off): close enough for a log
  UCSR0B = _BV(TXEN0);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  TCCR1A = 0;
  TCCR1B = _BV(CS11) | _BV(CS10);

  // The AVR's own CRC code (crc/crc16.cpp) against a known frame: the
  // answers below are only worth timing when they are right.
  static const uint8_t kKnown[6] = {0x01, 0x04, 0x00, 0x00, 0x00, 0x0B};  // CRC B1 CD
  line(PSTR("crc_ok"), crc16(kKnown, 6) == 0xCDB1u ? 1 : 0);

  static const gateway::GatewayPorts ports{CanSink{&can_sink, nullptr},
                                           modbus::ByteSink{&serial_sink, nullptr}, &storage, 115200};
  static gateway::Gateway g(ports);
  gw = &g;
  timer_start();
  g.start(0, 2);
  line(PSTR("start"), timer_us());
  for (uint8_t i = 0; i < 5; ++i) {
    now_us += 1000;
    g.process(now_us, 0);  // self-start: operational
  }

  uint32_t sum = 0;
  uint32_t worst = 0;
  for (uint8_t i = 0; i < 16; ++i) {
    now_us += 1000;
    timer_start();
    g.process(now_us, 0);
    const uint32_t us = timer_us();
    sum += us;
    if (us > worst) worst = us;
  }
  line(PSTR("idle_mean"), sum / 16);
  line(PSTR("idle_max"), worst);
  // A pass in which TPDO1's event timer (100 ms) runs out: built and sent.
  now_us += 100000;
  timer_start();
  g.process(now_us, 0);
  line(PSTR("idle_tpdo_event_timer"), timer_us());
  {
    // The characters of a request as the loop hands them in (not answered here).
    uint8_t adu[8];
    const uint16_t n = modbus::build_read_request(adu, sizeof adu, 1, 0x04, 0, 1);
    timer_start();
    for (uint16_t i = 0; i < n; ++i) g.on_serial_byte(adu[i], now_us + 96u * static_cast<uint32_t>(i + 1u));
    line(PSTR("serial_8_chars"), timer_us());
    now_us += 10000;
    g.process(now_us, 0);  // answers it (not timed)
  }
  blocks(g);

  read_request(PSTR("fc02_di0"), 0x02, 0, 1);
  read_request(PSTR("fc02_di0-6"), 0x02, 0, 7);
  read_request(PSTR("fc04_ir0"), 0x04, 0, 1);
  read_request(PSTR("fc04_ir18"), 0x04, 18, 1);
  read_request(PSTR("fc04_ir0-3"), 0x04, 0, 4);
  read_request(PSTR("fc04_ir0-10"), 0x04, 0, 11);
  read_request(PSTR("fc04_ir0-22"), 0x04, 0, 23);
  read_request(PSTR("fc03_hr0-12"), 0x03, 0, 13);
  uint8_t adu[16];
  request(PSTR("fc05_coil1"), adu, modbus::build_write_single_coil(adu, sizeof adu, 1, 1, true));
  request(PSTR("fc06_hr0"), adu, modbus::build_write_single_register(adu, sizeof adu, 1, 0, 1));
  const uint16_t regs[2] = {1, 1};
  request(PSTR("fc10_hr0-1"), adu, modbus::build_write_registers(adu, sizeof adu, 1, 0, 2, regs));

  now_us += 1000;
  timer_start();
  g.process(now_us, 0);
  line(PSTR("idle_lab_led_on"), timer_us());
  frame(PSTR("heartbeat_frame"), 0x701, 1, 5);
  frame(PSTR("rpdo3_frame"), 0x281, 1, 1);
  frame(PSTR("rpdo1_frame"), 0x181, 3, 1);

  filter_plans();

  // A first save (FC 10h, HR 11-12 = "save"): the pass that answers it, then
  // the passes that write it, one EEPROM byte each, 3.3 ms apart.
  const uint16_t save_regs[2] = {0x6576, 0x6173};
  line(PSTR("fc10_save_answer"),
       answer(adu, modbus::build_write_registers(adu, sizeof adu, 1, 11, 2, save_regs)));
  uint32_t save_passes = 0;
  sum = 0;
  worst = 0;
  while (g.node().saving()) {
    eeprom_busy = false;
    now_us += 3300;
    timer_start();
    g.process(now_us, 0);
    const uint32_t us = timer_us();
    ++save_passes;
    sum += us;
    if (us > worst) worst = us;
  }
  line(PSTR("save_passes"), save_passes);
  line(PSTR("save_pass_mean"), sum / save_passes);
  line(PSTR("save_pass_max"), worst);

  put_P(PSTR("end\n"));
  while (!(UCSR0A & _BV(TXC0))) {
  }
  cli();  // simavr ends the run on sleep with interrupts off
  sleep_mode();
  return 0;
}
