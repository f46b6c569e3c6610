#include "uno_board.h"

#include <avr_eeprom.h>
#include <avr_ioport.h>
#include <avr_spi.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_io.h>
#include <string.h>
#include <sys/stat.h>

#include <memory>

namespace mb2co {
namespace uno {
namespace {

// ATmega328P data-space addresses of the SPI unit (datasheet, register summary).
constexpr uint16_t kSpcr = 0x4C;
constexpr uint16_t kSpsr = 0x4D;
constexpr uint16_t kSpdr = 0x4E;
constexpr uint8_t kSpcrSpe = 0x40, kSpcrMstr = 0x10, kSpsrSpi2x = 0x01;
constexpr uint16_t kEecr = 0x3F;
constexpr uint8_t kEecrEepe = 0x02, kEecrEempe = 0x04;
// USART0 (datasheet, 20.11): every register that sets its character time.
constexpr uint16_t kUcsr0a = 0xC0, kUcsr0b = 0xC1, kUcsr0c = 0xC2, kUbrr0l = 0xC4, kUbrr0h = 0xC5;
constexpr uint8_t kUcsr0aU2x = 0x02, kUcsr0bUcsz2 = 0x04;
constexpr uint8_t kUcsr0cUpm1 = 0x20, kUcsr0cUsbs = 0x08, kUcsr0cUcszShift = 1;

/// Port letter and bit of an Arduino Uno pin (variants/standard).
struct PortBit {
  char port;
  uint8_t bit;
};
PortBit port_bit(uint8_t pin) {
  if (pin < 8) return PortBit{'D', pin};
  if (pin < 14) return PortBit{'B', static_cast<uint8_t>(pin - 8)};
  return PortBit{'C', static_cast<uint8_t>(pin - 14)};
}

/// simavr's messages: warnings and errors on stderr, the rest (UART set-up
/// traces and the like) dropped: stdout is the control channel. Off while
/// loading: our own check speaks for a bad file, in one line.
bool g_log_quiet = false;
void simavr_log(avr_t*, const int level, const char* format, va_list ap) {
  if (level > LOG_WARNING || g_log_quiet) return;
  fputs("mb2co-uno: simavr: ", stderr);
  vfprintf(stderr, format, ap);
}

/// The board paces time itself (main loop): a sleeping CPU just lets the
/// cycle count jump to the next event, it must not usleep() in here.
void no_sleep(avr_t*, avr_cycle_count_t) {}

/// True for a 32-bit little-endian ELF file for the AVR (e_machine 83).
bool is_avr_elf(const std::string& path) {
  unsigned char h[20] = {};
  FILE* f = fopen(path.c_str(), "rb");
  const bool read_all = f != nullptr && fread(h, 1, sizeof h, f) == sizeof h;
  if (f != nullptr) fclose(f);
  return read_all &&
         memcmp(h,
                "\x7f"
                "ELF",
                4) == 0 &&
         h[4] == 1 && h[5] == 1 && h[18] == 83 && h[19] == 0;
}

avr_uart_t* find_uart0(avr_t* avr) {
  for (avr_io_t* io = avr->io_port; io != nullptr; io = io->next) {
    if (io->kind != nullptr && strcmp(io->kind, "uart") == 0 &&
        reinterpret_cast<avr_uart_t*>(io)->name == '0')
      return reinterpret_cast<avr_uart_t*>(io);
  }
  return nullptr;
}

avr_spi_t* find_spi(avr_t* avr) {
  for (avr_io_t* io = avr->io_port; io != nullptr; io = io->next) {
    if (io->kind != nullptr && strcmp(io->kind, "spi") == 0) return reinterpret_cast<avr_spi_t*>(io);
  }
  return nullptr;
}

}  // namespace

UnoBoard::UnoBoard() = default;

UnoBoard::~UnoBoard() {
  if (avr_ != nullptr) avr_terminate(avr_);
}

Status UnoBoard::load(const std::string& elf_path, Wiring wiring) {
  struct stat st {};
  if (stat(elf_path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    return Status::failure("elf " + elf_path + ": no such file");
  }
  if (!is_avr_elf(elf_path)) {
    return Status::failure("elf " + elf_path + ": not an ELF file for the AVR");
  }
  avr_global_logger_set(&simavr_log);
  auto fw = std::make_unique<elf_firmware_t>();
  memset(fw.get(), 0, sizeof(elf_firmware_t));
  g_log_quiet = true;
  const int read_rc = elf_read_firmware(elf_path.c_str(), fw.get());
  g_log_quiet = false;
  if (read_rc != 0 || fw->flashsize == 0) {
    return Status::failure("elf " + elf_path + ": not an AVR image simavr can load");
  }
  if (fw->mmcu[0] != '\0' && strcmp(fw->mmcu, "atmega328p") != 0) {
    return Status::failure("elf " + elf_path + ": built for " + fw->mmcu + ", not the Uno's atmega328p");
  }
  if (fw->flashsize > 32768) {
    return Status::failure("elf " + elf_path + ": " + std::to_string(fw->flashsize) +
                           " B of flash, the ATmega328P has 32768");
  }
  avr_ = avr_make_mcu_by_name("atmega328p");
  if (avr_ == nullptr || avr_init(avr_) != 0) {
    return Status::failure("simavr has no atmega328p");
  }
  avr_->frequency = kCpuHz;
  avr_->sleep = &no_sleep;
  avr_->run_cycle_limit = kBurstCycles;  // simavr's default 1: a call per instruction
  avr_load_firmware(avr_, fw.get());
  avr_->frequency = kCpuHz;  // an .mmcu section may have set another one
  // .data starts at the first SRAM address (after the 256 register and I/O
  // addresses), .bss follows; the C runtime initialises only those, so the
  // paint above them survives until the stack writes over it.
  ramend_ = static_cast<uint16_t>(avr_->ramend);
  static_end_ = static_cast<uint16_t>(0x100u + fw->datasize + fw->bsssize);
  for (uint32_t a = static_end_; a <= ramend_; ++a) avr_->data[a] = kStackPaint;
  wiring_ = std::move(wiring);

  // USART0: no console echo, no polling usleep(); bytes out to the wiring.
  uint32_t flags = 0;
  avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  uart_input_ = avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), &on_uart_out,
                          this);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), &on_uart_xon,
                          this);
  avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), &on_uart_xoff,
                          this);

  // USART0's character time from every register that sets it (header
  // comment): simavr's handlers run first, ours recomputes after them.
  uart_ = find_uart0(avr_);
  if (uart_ == nullptr) return Status::failure("simavr's atmega328p has no USART0");
  static const uint16_t kUartTimingRegs[kUartTimingRegCount] = {kUcsr0a, kUcsr0b, kUcsr0c, kUbrr0l, kUbrr0h};
  for (int i = 0; i < kUartTimingRegCount; ++i) {
    auto& slot = avr_->io[AVR_DATA_TO_IO(kUartTimingRegs[i])];
    uart_reg_[i] = UartReg{this, slot.w.c, slot.w.param};
    slot.w.c = &on_uart_timing_write;
    slot.w.param = &uart_reg_[i];
  }
  set_uart_timing();

  // SPI: our SPDR write handler (header comment), CS on D10.
  // (The ATmega328P's SPI unit has no name in simavr 1.6: no GETIRQ('0').)
  spi_ = find_spi(avr_);
  spi_input_ = spi_ != nullptr && spi_->io.irq != nullptr ? spi_->io.irq + SPI_IRQ_INPUT : nullptr;
  if (spi_input_ == nullptr) {
    return Status::failure("simavr's atmega328p has no SPI unit");
  }
  avr_->io[AVR_DATA_TO_IO(kSpdr)].w.c = &on_spdr_write;
  avr_->io[AVR_DATA_TO_IO(kSpdr)].w.param = this;
  watch_pin(10);

  // EEPROM: simavr's own EECR write handler programs the byte, ours runs
  // around it and keeps EEPE set for the programming time (header comment).
  eecr_write_ = avr_->io[AVR_DATA_TO_IO(kEecr)].w.c;
  eecr_param_ = avr_->io[AVR_DATA_TO_IO(kEecr)].w.param;
  if (eecr_write_ == nullptr || avr_->io[AVR_DATA_TO_IO(kEecr)].r.c != nullptr) {
    return Status::failure("simavr's atmega328p EEPROM is not the one modelled (EECR)");
  }
  avr_->io[AVR_DATA_TO_IO(kEecr)].w.c = &on_eecr_write;
  avr_->io[AVR_DATA_TO_IO(kEecr)].w.param = this;
  avr_->io[AVR_DATA_TO_IO(kEecr)].r.c = &on_eecr_read;
  avr_->io[AVR_DATA_TO_IO(kEecr)].r.param = this;

  // Ports B, C, D take the levels driven from outside (header comment):
  // nothing driven yet.
  static const uint8_t kFirstPinOfPort[3] = {8, 14, 0};  // PB0 = D8, PC0 = A0, PD0 = D0
  for (const uint8_t first_pin_of_port : kFirstPinOfPort) {
    if (!set_external(first_pin_of_port, false, false)) {
      return Status::failure("simavr's atmega328p ports take no external levels (IOPORT_SET_EXTERNAL)");
    }
  }
  return Status::ok();
}

uint16_t UnoBoard::stack_used() const {
  uint32_t a = static_end_;
  while (a <= ramend_ && avr_->data[a] == kStackPaint) ++a;
  return static_cast<uint16_t>(ramend_ + 1u - a);
}

bool UnoBoard::run_until(uint64_t cycle) {
  // The burst ends at `cycle` (header comment): a timer of its own there.
  if (avr_->cycle < cycle) avr_cycle_timer_register(avr_, cycle - avr_->cycle, &on_run_end, this);
  while (avr_->cycle < cycle) {
    const int state = avr_run(avr_);
    if (state == cpu_Done || state == cpu_Crashed) {
      stop_reason_ = state == cpu_Crashed ? "the CPU crashed" : "the CPU stopped (cli; sleep)";
      char where[64];
      snprintf(where, sizeof where, " at pc 0x%04x, cycle %llu", static_cast<unsigned>(avr_->pc),
               static_cast<unsigned long long>(avr_->cycle));
      stop_reason_ += where;
      return false;
    }
  }
  avr_cycle_timer_cancel(avr_, &on_run_end, this);
  return true;
}

uint64_t UnoBoard::on_run_end(avr_t*, uint64_t, void*) {
  return 0;
}

uint64_t UnoBoard::cycle() const {
  return avr_->cycle;
}

avr_irq_t* UnoBoard::pin_irq(uint8_t pin) const {
  const PortBit pb = port_bit(pin);
  return avr_io_getirq(avr_, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(pb.port)), pb.bit);
}

void UnoBoard::watch_pin(uint8_t pin) {
  if (pin >= 20) return;
  watches_[pin] = Watch{this, pin};
  avr_irq_register_notify(pin_irq(pin), &on_pin, &watches_[pin]);
}

bool UnoBoard::set_external(uint8_t pin, bool driven, bool high) {
  const PortBit pb = port_bit(pin);
  const int port = pb.port - 'B';
  const uint8_t bit = static_cast<uint8_t>(1u << pb.bit);
  external_mask_[port] =
      static_cast<uint8_t>(driven ? external_mask_[port] | bit : external_mask_[port] & ~bit);
  external_high_[port] =
      static_cast<uint8_t>(driven && high ? external_high_[port] | bit : external_high_[port] & ~bit);
  avr_ioport_external_t external{};
  external.name = static_cast<unsigned long>(pb.port) & 0x7Fu;
  external.mask = external_mask_[port];
  external.value = external_high_[port];
  return avr_ioctl(avr_, static_cast<uint32_t>(AVR_IOCTL_IOPORT_SET_EXTERNAL(pb.port)), &external) == 0;
}

void UnoBoard::drive_pin(uint8_t pin, bool high) {
  if (pin >= 20) return;
  set_external(pin, true, high);
  avr_raise_irq(pin_irq(pin), high ? 1u : 0u);  // the level now; the port's writes keep it
}

void UnoBoard::switch_to_gnd(uint8_t pin, bool closed) {
  if (pin >= 20) return;
  set_external(pin, closed, false);
  // Open: high, as the pull-up pulls it (simavr raises it again at the next
  // port write if the image has set its pull-up).
  avr_raise_irq(pin_irq(pin), closed ? 0u : 1u);
}

void UnoBoard::on_pin(avr_irq_t*, uint32_t value, void* param) {
  const Watch* w = static_cast<const Watch*>(param);
  UnoBoard* self = w->board;
  if (w->pin == 10) {
    if (self->wiring_.spi_select) self->wiring_.spi_select(value == 0);
    return;
  }
  if (self->wiring_.pin_out) self->wiring_.pin_out(w->pin, value != 0);
}

// --- USART0 ----------------------------------------------------------------------

void UnoBoard::uart_receive(const uint8_t* data, size_t length) {
  uart_queue_.append(reinterpret_cast<const char*>(data), length);
  feed_uart();
}

void UnoBoard::feed_uart() {
  // simavr raises XOFF from inside the input IRQ when its FIFO fills: stop then.
  while (!uart_xoff_ && uart_queue_head_ < uart_queue_.size()) {
    avr_raise_irq(uart_input_, static_cast<uint8_t>(uart_queue_[uart_queue_head_++]));
  }
  if (uart_queue_head_ == uart_queue_.size()) {
    uart_queue_.clear();
    uart_queue_head_ = 0;
  }
}

void UnoBoard::on_uart_timing_write(avr_t* avr, uint16_t addr, uint8_t value, void* param) {
  const UartReg* reg = static_cast<const UartReg*>(param);
  if (reg->write != nullptr) {
    reg->write(avr, addr, value, reg->param);
  } else {
    avr_core_watch_write(avr, addr, value);  // what simavr does for a register without a handler
  }
  reg->board->set_uart_timing();
}

void UnoBoard::set_uart_timing() {
  const uint8_t* d = avr_->data;
  const uint32_t ubrr = static_cast<uint32_t>(d[kUbrr0l] | ((d[kUbrr0h] & 0x0Fu) << 8));
  // Datasheet, table 20-1: a bit is 16 (U2X0: 8) clocks of the rate UBRR0 + 1 divides.
  const uint32_t cycles_per_bit = (ubrr + 1u) * ((d[kUcsr0a] & kUcsr0aU2x) ? 8u : 16u);
  static const uint8_t kDataBits[8] = {5, 6, 7, 8, 8, 8, 8, 9};  // UCSZ0[2:0]; reserved codes as 8
  const uint8_t ucsz =
      static_cast<uint8_t>(((d[kUcsr0c] >> kUcsr0cUcszShift) & 3u) | ((d[kUcsr0b] & kUcsr0bUcsz2) ? 4u : 0u));
  const uint32_t bits = 1u /* start */ + kDataBits[ucsz] + ((d[kUcsr0c] & kUcsr0cUpm1) ? 1u : 0u) +
                        ((d[kUcsr0c] & kUcsr0cUsbs) ? 2u : 1u);
  uart_->cycles_per_byte = cycles_per_bit * bits;
}

uint64_t UnoBoard::uart_cycles_per_char() const {
  return uart_ != nullptr ? uart_->cycles_per_byte : 0;
}

void UnoBoard::on_uart_out(avr_irq_t*, uint32_t value, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  if (self->wiring_.uart_tx) self->wiring_.uart_tx(static_cast<uint8_t>(value));
}

void UnoBoard::on_uart_xon(avr_irq_t*, uint32_t, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  self->uart_xoff_ = false;
  self->feed_uart();
}

void UnoBoard::on_uart_xoff(avr_irq_t*, uint32_t value, void* param) {
  static_cast<UnoBoard*>(param)->uart_xoff_ = value != 0;
}

// --- SPI ---------------------------------------------------------------------------

void UnoBoard::on_spdr_write(avr_t* avr, uint16_t addr, uint8_t value, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  avr_clear_interrupt(avr, &self->spi_->spi);  // writing SPDR starts a byte: SPIF goes
  avr_core_watch_write(avr, addr, value);
  const uint8_t spcr = avr->data[kSpcr];
  if ((spcr & kSpcrSpe) == 0 || (spcr & kSpcrMstr) == 0) return;  // only the master is modelled
  static const uint8_t kDivider[4] = {4, 16, 64, 128};
  uint32_t divider = kDivider[spcr & 3u];
  if (avr->data[kSpsr] & kSpsrSpi2x) divider /= 2;
  avr_cycle_timer_register(avr, 8u * divider, &on_spi_done, self);
}

uint64_t UnoBoard::on_spi_done(avr_t* avr, uint64_t, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  const uint8_t mosi = avr->data[kSpdr];
  const uint8_t miso = self->wiring_.spi_byte ? self->wiring_.spi_byte(mosi) : 0xFF;
  avr_raise_irq(self->spi_input_, miso);  // the SPI unit stores it and raises SPIF
  return 0;
}

// --- timer, EEPROM ------------------------------------------------------------------

void UnoBoard::call_at(uint64_t at_cycle, std::function<void()> fn) {
  avr_cycle_timer_cancel(avr_, &on_timer, this);
  timer_fn_ = std::move(fn);
  if (!timer_fn_) return;
  const uint64_t now = avr_->cycle;
  avr_cycle_timer_register(avr_, at_cycle > now ? at_cycle - now : 1u, &on_timer, this);
}

uint64_t UnoBoard::on_timer(avr_t*, uint64_t, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  std::function<void()> fn = self->timer_fn_;  // fn may set the next one
  if (fn) fn();
  return 0;
}

void UnoBoard::on_eecr_write(avr_t* avr, uint16_t addr, uint8_t value, void* param) {
  UnoBoard* self = static_cast<UnoBoard*>(param);
  // EEPE written within 4 cycles of EEMPE: simavr programs the byte now.
  const bool program = (avr->data[kEecr] & kEecrEempe) != 0 && (value & kEecrEepe) != 0;
  self->eecr_write_(avr, addr, value, self->eecr_param_);
  if (program) {
    self->eeprom_ready_cycle_ = avr->cycle + cycles_from_us(kEepromByteUs);
    ++self->eeprom_bytes_programmed_;
  }
}

uint8_t UnoBoard::on_eecr_read(avr_t* avr, uint16_t addr, void* param) {
  const UnoBoard* self = static_cast<const UnoBoard*>(param);
  const bool busy = avr->cycle < self->eeprom_ready_cycle_;
  return static_cast<uint8_t>((avr->data[addr] & ~kEecrEepe) | (busy ? kEecrEepe : 0));
}

bool UnoBoard::set_eeprom(const uint8_t* data, size_t length) {
  if (length != kEepromBytes) return false;
  avr_eeprom_desc_t d{const_cast<uint8_t*>(data), 0, kEepromBytes};
  return avr_ioctl(avr_, AVR_IOCTL_EEPROM_SET, &d) == 0;
}

bool UnoBoard::get_eeprom(uint8_t* out, size_t length) const {
  if (length != kEepromBytes) return false;
  avr_eeprom_desc_t d{out, 0, kEepromBytes};
  if (avr_ioctl(avr_, AVR_IOCTL_EEPROM_GET, &d) != 0 || d.ee == nullptr) return false;
  if (d.ee != out) memcpy(out, d.ee, kEepromBytes);  // a pointer into the EEPROM came back
  return true;
}

}  // namespace uno
}  // namespace mb2co
