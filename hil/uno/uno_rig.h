// The simulated station: the Uno board running the image, the MCP2515 on its
// SPI bus with the CAN wire behind it, the operator panel on its pins. Knows
// nothing of file descriptors: main.cpp moves bytes and frames in and out.
//
// Pins (firmware/avr/pins.h): the image's buttons (low = pressed) and LEDs
// (high = on) as UnoImage names them (the gateway: buttons D9 START, D3 STOP,
// D4 STOP2; LEDs D5 RUN-self, D6 RUN-prev, D14 RUN-next, D7 lab, D8 CAN not
// usable); MCP2515 CS D10 (SPI mode 0), INT D2 (active low).
#pragma once
#include <stdint.h>

#include <functional>
#include <string>
#include <vector>

#include "can_wire.h"
#include "panel_channel.h"
#include "uno_board.h"

namespace mb2co {
namespace uno {

class UnoRig {
 public:
  /// A board wired for `image`'s buttons and LEDs (a static table).
  explicit UnoRig(const UnoImage& image = gateway_image());
  /// Loads the image and wires it up (see UnoBoard::load).
  Status load(const std::string& elf_path);

  UnoBoard& board() { return board_; }
  PanelChannel& panel() { return panel_; }
  uint64_t now_us() const { return board_.micros(); }

  /// Runs the image up to simulated time `until_us`. False when the CPU stopped.
  bool run_until_us(uint64_t until_us);

  /// Bytes from the Modbus master, arriving now.
  void serial_in(const uint8_t* data, size_t length);
  /// Bytes the image sent since the last call.
  std::string take_serial_out();
  /// A frame from the CAN bus that reached the bus at simulated time
  /// `arrival_us` (now, if that has passed): the chip receives it then.
  void can_in(const CanFrame& frame, uint64_t arrival_us = 0);
  /// Frames the chip put on the bus since the last call.
  std::vector<CanWire::Sent> take_can_out();
  /// The wire's counters (frames carried, dropped, busy time).
  const CanWire& wire() const { return wire_; }
  /// Cycle at which the frame on the wire ends (a frame from can_in() is
  /// received then) or a frame from can_in() arrives; CanWire::kIdle when
  /// nothing is to happen.
  uint64_t wire_busy_until() const { return wire_.next_event(); }
  /// Measurements (mb2co-lab sync-processing): called at the end of every
  /// SPI instruction after which the chip holds a frame to send (TXREQ set),
  /// with the cycle and that frame, before the wire may take it.
  std::function<void(uint64_t cycle, const CanFrame& frame)> on_transmit_request;
  /// Drives the button pins from the panel's levels (call after commands).
  void apply_buttons();
  /// MCP2515 instructions the image has begun since load (CS falling edges).
  uint64_t chip_selects() const { return chip_selects_; }

  /// True when a LED changed since the last call; `changed_us` then holds
  /// the simulated time of the last change.
  bool take_led_change(uint64_t* changed_us);

  /// Node id of the boot-up message seen (0: none yet) and when it ended.
  uint8_t booted_node() const { return booted_node_; }
  /// True once the boot-up went out and the Modbus line has since been idle
  /// for t3.5: the image's RTU slave then takes requests (serial line spec:
  /// after power-on it waits for t3.5 of silence first).
  bool modbus_ready() const;

 private:
  void on_pin(uint8_t pin, bool high);
  void on_select(bool selected);
  void wire_event();
  void schedule_wire();
  void note_sent(const std::vector<CanWire::Sent>& sent);

  const UnoImage& image_;
  UnoBoard board_;
  CanWire wire_;
  PanelChannel panel_;
  std::string serial_out_;
  std::vector<CanWire::Sent> can_out_;
  bool int_high_ = true;
  uint64_t chip_selects_ = 0;
  uint8_t buttons_driven_ = 0;
  bool led_changed_ = false;
  uint64_t led_changed_us_ = 0;
  uint8_t booted_node_ = 0;
  uint64_t booted_us_ = 0;
  uint64_t line_busy_until_us_ = 0;  ///< end of the last byte the master sent
  uint32_t char_us_;
  uint32_t t35_us_;
};

}  // namespace uno
}  // namespace mb2co
