#include "uno_rig.h"

#include "modbus/rtu_timing.h"

namespace mb2co {
namespace uno {
namespace {

// firmware/avr/pins.h; the buttons and LEDs are the image's (uno_image.cpp).
constexpr uint8_t kPinCanInt = 2;

/// USART0 rate of the gateway image (gateway_main.cpp, kBaud).
constexpr uint32_t kImageBaud = 115200;

}  // namespace

UnoRig::UnoRig(const UnoImage& image) : image_(image), wire_(UnoBoard::kCpuHz), panel_(image) {
  const modbus::RtuTiming t = modbus::rtu_timing(kImageBaud);
  char_us_ = t.char_us;
  t35_us_ = t.t35_us;
}

Status UnoRig::load(const std::string& elf_path) {
  UnoBoard::Wiring w;
  w.uart_tx = [this](uint8_t b) { serial_out_.push_back(static_cast<char>(b)); };
  w.pin_out = [this](uint8_t pin, bool high) { on_pin(pin, high); };
  w.spi_byte = [this](uint8_t mosi) { return wire_.chip().transfer(mosi); };
  w.spi_select = [this](bool selected) { on_select(selected); };
  Status loaded = board_.load(elf_path, std::move(w));
  if (!loaded) return loaded;
  for (uint8_t i = 0; i < image_.led_count; ++i) board_.watch_pin(image_.led_pins[i]);
  for (int b = 0; b < image_.buttons.count; ++b)
    board_.switch_to_gnd(image_.button_pins[b], false);  // released
  board_.drive_pin(kPinCanInt, true);
  return Status::ok();
}

bool UnoRig::run_until_us(uint64_t until_us) {
  return board_.run_until(UnoBoard::cycles_from_us(until_us));
}

// --- pins ----------------------------------------------------------------------------

void UnoRig::on_pin(uint8_t pin, bool high) {
  for (uint8_t i = 0; i < image_.led_count; ++i) {
    if (image_.led_pins[i] != pin) continue;
    panel_.set_led(i, high, board_.micros());
    led_changed_ = true;
    led_changed_us_ = board_.micros();
  }
}

bool UnoRig::take_led_change(uint64_t* changed_us) {
  if (!led_changed_) return false;
  led_changed_ = false;
  *changed_us = led_changed_us_;
  return true;
}

void UnoRig::apply_buttons() {
  const uint8_t want = panel_.buttons();
  for (int b = 0; b < image_.buttons.count; ++b) {
    const uint8_t bit = static_cast<uint8_t>(1u << b);
    if ((want ^ buttons_driven_) & bit) board_.switch_to_gnd(image_.button_pins[b], (want & bit) != 0);
  }
  buttons_driven_ = want;
}

// --- CAN -------------------------------------------------------------------------------

void UnoRig::on_select(bool selected) {
  wire_.chip().select(selected);
  if (selected) {
    ++chip_selects_;
    return;
  }
  CanFrame pending;
  if (on_transmit_request && wire_.chip().next_transmit(&pending))
    on_transmit_request(board_.cycle(), pending);
  // An instruction ended: it may have requested a transmission or cleared flags.
  wire_event();
}

void UnoRig::wire_event() {
  wire_.advance(board_.cycle());
  note_sent(wire_.take_sent());
  const bool int_high = !wire_.int_low();
  if (int_high != int_high_) {
    int_high_ = int_high;
    board_.drive_pin(kPinCanInt, int_high);
  }
  schedule_wire();
}

void UnoRig::schedule_wire() {
  const uint64_t at = wire_.next_event();
  if (at == CanWire::kIdle) {
    board_.call_at(0, nullptr);
  } else {
    board_.call_at(at, [this] { wire_event(); });
  }
}

void UnoRig::note_sent(const std::vector<CanWire::Sent>& sent) {
  for (const CanWire::Sent& s : sent) {
    const CanFrame& f = s.frame;
    // Boot-up: 700h + node id, one data byte 00 (CiA 301 NMT error control).
    if (booted_node_ == 0 && !f.extended() && !f.rtr() && f.id > 0x700 && f.id <= 0x77F && f.dlc == 1 &&
        f.data[0] == 0) {
      booted_node_ = static_cast<uint8_t>(f.id - 0x700);
      booted_us_ = s.end_cycle / (UnoBoard::kCpuHz / 1000000u);
    }
    can_out_.push_back(s);
  }
}

void UnoRig::can_in(const CanFrame& frame, uint64_t arrival_us) {
  wire_.frame_from_bus(frame, board_.cycle(), UnoBoard::cycles_from_us(arrival_us));
  wire_event();
}

std::vector<CanWire::Sent> UnoRig::take_can_out() {
  std::vector<CanWire::Sent> out;
  out.swap(can_out_);
  return out;
}

// --- serial ------------------------------------------------------------------------------

void UnoRig::serial_in(const uint8_t* data, size_t length) {
  // The UART takes them back to back from now (or from the end of the ones
  // still queued): the line is busy until the last one is through.
  const uint64_t from = line_busy_until_us_ > now_us() ? line_busy_until_us_ : now_us();
  line_busy_until_us_ = from + static_cast<uint64_t>(length) * char_us_;
  board_.uart_receive(data, length);
}

std::string UnoRig::take_serial_out() {
  std::string out;
  out.swap(serial_out_);
  return out;
}

bool UnoRig::modbus_ready() const {
  if (booted_node_ == 0) return false;
  const uint64_t quiet_from = line_busy_until_us_ > booted_us_ ? line_busy_until_us_ : booted_us_;
  return board_.uart_backlog() == 0 && now_us() >= quiet_from + t35_us_;
}

}  // namespace uno
}  // namespace mb2co
