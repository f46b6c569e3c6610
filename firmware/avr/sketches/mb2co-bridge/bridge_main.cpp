// mb2co-bridge on the Uno: the smart bridge of seed 003 §3.2.8 between a
// serial CANopen segment on the UART (115200 8-N-1) and CAN at 500 kbit/s on
// the MCP2515 shield. The segment's settings are built in (kSegment below):
// the 8-bit connection set, serial nodes 1..3 polled by the bridge (window 4),
// CAN node id = serial node id + 0x20. The UART carries only the segment (no
// console): an RS-485 transceiver on D0/D1 must not echo (RE tied high while
// DE is driven), as the link must not hear itself.
#include <Arduino.h>

#include "mcp2515.h"
#include "pins.h"
#include "port/can_int.h"
#include "port/can_port.h"
#include "port/gpio.h"
#include "port/mcp2515_spi.h"
#include "port/uart.h"
#include "serialnet/bridge.h"

namespace {

using namespace mb2co;

constexpr uint32_t kBaud = 115200;
constexpr uint16_t kCanKbit = 500;

serialnet::BridgeConfig segment_config() {
  serialnet::BridgeConfig c = {};
  c.bus.set = serialnet::connection_set(serialnet::IdBits::k8);
  c.bus.baud = kBaud;
  c.bus.access = serialnet::Access::kPoller;
  c.bus.first_node = 1;
  c.bus.last_node = 4;
  c.bus.window_us = 20000;
  c.bus.guard_us = 5000;
  c.bridge_node = 4;
  c.node_offset = 0x20;
  return c;
}

mcp2515::Driver driver(avr::mcp2515_spi());
// The bridge sets no filters (it forwards by function code whatever the
// segment consumes): the chip stays open, no planner in the image.
avr::CanPort<false> can_port(driver);
serialnet::Bridge bridge(segment_config(), avr::uart_sink(),
                         CanSink{&avr::CanPort<false>::send_to, &can_port});

}  // namespace

void setup() {
  avr::gpio_input(pins::kCanInt, false);  // the MCP2515 drives INT push-pull
  avr::mcp2515_spi_begin();
  avr::uart_begin(kBaud, modbus::Parity::kNone);
  can_port.begin(kCanKbit, micros());  // poll() retries while the chip does not answer
}

void loop() {
  const uint32_t now_us = micros();
  avr::UartChar c;
  while (avr::uart_read(c)) bridge.on_byte(c.byte, c.stamp_us);
  can_port.poll(bridge.can_input(), avr::can_int_low(), now_us);
  bridge.process(now_us);
}
