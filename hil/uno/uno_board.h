// An Arduino Uno as libsimavr runs it: an ATmega328P at 16 MHz executing an
// ELF image, with the board's outside world reduced to callbacks and levels:
// USART0 bytes out, bytes in (with simavr's flow control), digital pins
// watched and driven by Arduino pin number, the SPI master's bytes handed to
// one device, the 1 KiB EEPROM loaded and read back.
//
// SPI timing: simavr 1.6 completes every SPI byte a fixed 100 µs after SPDR
// is written (1,600 CPU cycles; a real Uno at F_CPU/2 needs 16). The board
// takes over the SPDR write handler of the simulated SPI unit (the io[] table
// of simavr's public avr_t) and completes each byte after 8 SCK periods as
// SPCR/SPSR set them (F_CPU/2 -> 1 µs), exactly what the hardware does. The
// byte received comes in through the SPI unit's own input IRQ, so SPDR reads
// and the SPIF flag stay simavr's.
//
// EEPROM timing: simavr 1.6 programs an EEPROM byte at once and clears EEPE
// in the same write, where the ATmega328P keeps EEPE set for 3.3 ms
// (datasheet, 26.4: 3.3 ms typical at 5 V) and avr-libc's eeprom_write_*
// wait for it. The board wraps simavr's EECR write handler (io[] table, as
// for SPDR) to note when a byte was programmed and reads EEPE as set until
// kEepromByteUs later, so a save takes the board's time and the firmware
// sees the same busy bit (canopen::ParamSave polls it, avr::eeprom_storage).
//
// USART0 timing: simavr 1.6 works out the character time only when UBRR0L
// is written, from the U2X0 bit as it stands then, and always counts a
// parity bit (11 bits for 8N1). The image (firmware/avr/port/uart.cpp)
// writes UBRR0 first and sets U2X0 after it, as the datasheet allows (the
// rate follows U2X0 at once on the chip): simavr then ran the UART at half
// the speed, 187 us a character instead of 85 us at 115200 8N1 (117.6 kbaud
// from UBRR0 16 with U2X0), and every Modbus answer took twice its wire time.
// The board wraps simavr's write handlers of UCSR0A..C and UBRR0L/H (io[]
// table, as for SPDR) and sets the character time after every write from
// all of them: UBRR0, U2X0, data bits, parity (UPM01), stop bits.
//
// Pins driven from outside: simavr 1.6 drives every input pin whose PORT bit
// is set (the image's pull-up) back high at every write of that PORT or DDR
// register, and writes are frequent: D10 (PB2, the MCP2515's chip select) at
// every SPI instruction, the LEDs on ports B, C and D. A level raised on the
// pin's IRQ alone (a pressed button) is undone by the next such write,
// where on the Uno a switch to GND holds the pin low against the 20-50 kOhm
// pull-up. The board therefore gives simavr each driven pin as an external
// level of its port (AVR_IOCTL_IOPORT_SET_EXTERNAL: the pull_mask/pull_value
// that avr_ioport_update_irqs() takes for an input pin before the PORT bit),
// so the pin keeps what drives it across every write.
//
// Instruction bursts: simavr 1.6 runs one instruction per avr_run() and
// then looks at its cycle timers, unless avr_t::run_cycle_limit (default 1)
// lets avr_run_one() go on: it then runs instructions back to back until the
// next cycle timer is due, an interrupt is pending or the limit is reached,
// and registering or cancelling a timer shortens the burst (simavr keeps
// run_cycle_count up to date). The board sets the limit to kBurstCycles and
// puts a timer of its own at the end of each run_until(), so every event
// still happens at its exact cycle: the same traces, cycle for cycle, at
// about twice the speed (the per-instruction calls were a third of the CPU).
//
// Time is the simulated CPU cycle count (cycle(), 62.5 ns each). Not
// thread-safe; every callback runs inside run_until().
#pragma once
#include <stdint.h>

#include <functional>
#include <string>

#include "host/status.h"

struct avr_t;
struct avr_irq_t;
struct avr_spi_t;
struct avr_uart_t;

namespace mb2co {
namespace uno {

class UnoBoard {
 public:
  static constexpr uint32_t kCpuHz = 16000000;
  static constexpr uint16_t kEepromBytes = 1024;
  /// Most cycles simavr runs without looking at its timers (header comment;
  /// a timer is due every 16,384 cycles anyway: timer 0 overflows for micros()).
  static constexpr uint32_t kBurstCycles = 16000;

  /// What the board does with the outside world. Unset callbacks ignore the event.
  struct Wiring {
    std::function<void(uint8_t byte)> uart_tx;            ///< the image sent a byte on USART0
    std::function<void(uint8_t pin, bool high)> pin_out;  ///< a watched pin's output level changed
    std::function<uint8_t(uint8_t mosi)> spi_byte;        ///< one SPI byte: returns MISO
    std::function<void(bool selected)> spi_select;        ///< chip select (D10 = PB2) edge: low = selected
  };

  UnoBoard();
  ~UnoBoard();
  UnoBoard(const UnoBoard&) = delete;
  UnoBoard& operator=(const UnoBoard&) = delete;

  /// Reads `elf_path` and makes an ATmega328P at 16 MHz running it from
  /// reset. Fails for a missing or invalid file or an image built for
  /// another MCU.
  Status load(const std::string& elf_path, Wiring wiring);

  /// Runs until the cycle count reaches `cycle` (it may pass it by one
  /// instruction, as without bursts). False when the CPU stopped (crashed
  /// or `done`); the reason is in stop_reason().
  bool run_until(uint64_t cycle);
  uint64_t cycle() const;
  const std::string& stop_reason() const { return stop_reason_; }

  /// Microseconds since reset (the image's micros() counts the same time).
  uint64_t micros() const { return cycle() / (kCpuHz / 1000000u); }
  static uint64_t cycles_from_us(uint64_t us) { return us * (kCpuHz / 1000000u); }

  /// Watches Arduino pin `pin` (0..19): Wiring::pin_out on every change of
  /// the level its PORT bit drives. Call after load().
  void watch_pin(uint8_t pin);
  /// Drives input pin `pin` from outside with a push-pull output (the
  /// MCP2515's INT): the pin has this level whatever the image writes to
  /// its port, until the next call.
  void drive_pin(uint8_t pin, bool high);
  /// A switch from input pin `pin` to GND (a button, a joystick direction):
  /// closed, the pin is low whatever the image writes to its port; open,
  /// nothing drives it and it reads high, as through the image's pull-up
  /// (INPUT_PULLUP; an image without one would read a floating pin).
  void switch_to_gnd(uint8_t pin, bool closed);

  /// Queues bytes for USART0's receiver; simavr spaces them at the UART's
  /// character time as they are taken. Bytes wait while its FIFO is full.
  void uart_receive(const uint8_t* data, size_t length);
  /// USART0's character time in CPU cycles (start, data, parity, stop
  /// bits at the rate UBRR0 and U2X0 set), as the board keeps it.
  uint64_t uart_cycles_per_char() const;
  /// Bytes queued but not yet taken by the UART.
  size_t uart_backlog() const { return uart_queue_.size() - uart_queue_head_; }

  /// Calls `fn` when the cycle count reaches `at_cycle` (one timer: a later
  /// call replaces an earlier one). Runs inside run_until().
  void call_at(uint64_t at_cycle, std::function<void()> fn);

  /// Stack high-water mark: the RAM above .data + .bss (up to RAMEND) is
  /// painted with kStackPaint at load; the deepest byte no longer holding it
  /// is how far the stack has grown since reset. Exact unless the deepest
  /// bytes pushed happened to equal kStackPaint (then a few bytes low).
  /// The images use no heap (it would grow into the same region).
  static constexpr uint8_t kStackPaint = 0xA5;
  /// Bytes of RAM the stack may use: RAMEND + 1 - end of .data + .bss.
  uint16_t stack_room() const { return static_cast<uint16_t>(ramend_ + 1u - static_end_); }
  /// Most bytes the stack has held since reset.
  uint16_t stack_used() const;

  /// Programming time of one EEPROM byte (EEPE set meanwhile).
  static constexpr uint32_t kEepromByteUs = 3300;
  /// EEPROM bytes the image has programmed since load (each kEepromByteUs).
  uint64_t eeprom_bytes_programmed() const { return eeprom_bytes_programmed_; }

  /// Replaces the EEPROM content (exactly kEepromBytes).
  bool set_eeprom(const uint8_t* data, size_t length);
  /// Reads the EEPROM content (kEepromBytes into `out`).
  bool get_eeprom(uint8_t* out, size_t length) const;

 private:
  avr_irq_t* pin_irq(uint8_t pin) const;
  /// Hands the externally driven levels of `pin`'s port to simavr; false
  /// when simavr's port does not take them.
  bool set_external(uint8_t pin, bool driven, bool high);
  void feed_uart();
  static void on_uart_out(avr_irq_t* irq, uint32_t value, void* param);
  static void on_uart_xon(avr_irq_t* irq, uint32_t value, void* param);
  static void on_uart_xoff(avr_irq_t* irq, uint32_t value, void* param);
  static void on_pin(avr_irq_t* irq, uint32_t value, void* param);
  static void on_uart_timing_write(avr_t* avr, uint16_t addr, uint8_t value, void* param);
  /// Sets simavr's USART0 character time from UCSR0A..C and UBRR0.
  void set_uart_timing();
  static void on_spdr_write(avr_t* avr, uint16_t addr, uint8_t value, void* param);
  static uint64_t on_spi_done(avr_t* avr, uint64_t when, void* param);
  static uint64_t on_timer(avr_t* avr, uint64_t when, void* param);
  static uint64_t on_run_end(avr_t* avr, uint64_t when, void* param);
  static void on_eecr_write(avr_t* avr, uint16_t addr, uint8_t value, void* param);
  static uint8_t on_eecr_read(avr_t* avr, uint16_t addr, void* param);

  avr_t* avr_ = nullptr;
  Wiring wiring_;
  avr_spi_t* spi_ = nullptr;
  avr_irq_t* spi_input_ = nullptr;
  avr_irq_t* uart_input_ = nullptr;
  avr_uart_t* uart_ = nullptr;
  /// simavr's write handler of one USART0 timing register, which ours wraps.
  struct UartReg {
    UnoBoard* board;
    void (*write)(avr_t*, uint16_t, uint8_t, void*);
    void* param;
  };
  static constexpr int kUartTimingRegCount = 5;
  UartReg uart_reg_[kUartTimingRegCount] = {};
  bool uart_xoff_ = false;
  std::string uart_queue_;
  size_t uart_queue_head_ = 0;
  std::function<void()> timer_fn_;
  struct Watch {
    UnoBoard* board;
    uint8_t pin;
  };
  Watch watches_[20] = {};
  /// Pins driven from outside, per port B, C, D (bit = port bit), and their levels.
  uint8_t external_mask_[3] = {};
  uint8_t external_high_[3] = {};
  std::string stop_reason_;
  uint16_t static_end_ = 0;  ///< first RAM address above .data + .bss
  uint16_t ramend_ = 0;
  void (*eecr_write_)(avr_t*, uint16_t, uint8_t, void*) = nullptr;  ///< simavr's EEPROM unit
  void* eecr_param_ = nullptr;
  uint64_t eeprom_ready_cycle_ = 0;  ///< EEPE reads set before this cycle
  uint64_t eeprom_bytes_programmed_ = 0;
};

}  // namespace uno
}  // namespace mb2co
