// One Uno gateway as its image's main() drives it
// (firmware/avr/sketches/mb2co-gateway/gateway_main.cpp), on the host: the
// gateway of this build's profile, its CAN port as the image picks it
// (avr::CanPortFor the gateway's widest acceptance range), the MCP2515
// driver on the register-level chip model, INT read from the model; a
// Modbus master on the serial side, byte by byte at 115200 baud. Virtual
// time: a loop pass every kPassUs.
#pragma once
#include <gtest/gtest.h>
#include <stdint.h>

#include <functional>
#include <vector>

#include "gateway/gateway.h"
#include "mcp2515.h"
#include "mcp2515_model.h"
#include "port/can_port.h"

namespace mb2co {
namespace test {

class UnoCanRig {
 public:
  using Port = avr::CanPortFor<gateway::Gateway::kWidestRange>;
  static constexpr uint32_t kPassUs = 500;
  static constexpr uint32_t kCharUs = 96;  // 11 bits at 115200 baud, rounded up

  mcp2515::model::Mcp2515Model chip;
  mcp2515::Driver driver{chip.spi()};
  Port port{driver};
  std::vector<uint8_t> serial_out;
  gateway::Gateway gw{gateway::GatewayPorts{CanSink{&Port::send_to, &port},
                                            modbus::ByteSink{&UnoCanRig::serial_write, this}, nullptr, 115200,
                                            &Port::kControl}};
  uint32_t now_us = 0;
  /// Called after every pass (a remote node answering what the chip sent).
  std::function<void()> each_pass;

  /// Power-on as setup() does it: the gateway's reset starts the chip at
  /// its bit rate (CanControl::set_bitrate), then a few passes.
  void power_on(uint8_t node_id) {
    gw.start(now_us, node_id);
    run_us(20000);
  }
  /// One pass of loop(): the port hands what the chip received to the
  /// gateway, the gateway runs, the chip puts what was queued on the bus.
  void pass() {
    now_us += kPassUs;
    port.poll(gw.can_input(), chip.int_low(), now_us);
    gw.process(now_us, 0);
    chip.transmit();
    if (each_pass) each_pass();
  }
  void run_us(uint32_t us) {
    for (uint32_t t = 0; t < us; t += kPassUs) pass();
  }
  /// A Modbus request (ADU), then passes until an answer is complete or
  /// `timeout_us` passed; the answer's bytes (empty: none).
  std::vector<uint8_t> modbus(const uint8_t* adu, uint16_t length, uint32_t timeout_us) {
    serial_out.clear();
    for (uint16_t k = 0; k < length; ++k) {
      now_us += kCharUs;
      gw.on_serial_byte(adu[k], now_us);
    }
    for (uint32_t t = 0; t < timeout_us && serial_out.empty(); t += kPassUs) pass();
    return serial_out;
  }

 private:
  static bool serial_write(void* ctx, const uint8_t* data, uint16_t n) {
    std::vector<uint8_t>& out = static_cast<UnoCanRig*>(ctx)->serial_out;
    out.insert(out.end(), data, data + n);
    return true;
  }
};

inline CanFrame can_frame(uint16_t id, std::vector<uint8_t> data) {
  CanFrame f{};
  f.id = id;
  f.dlc = static_cast<uint8_t>(data.size());
  for (size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

}  // namespace test
}  // namespace mb2co
