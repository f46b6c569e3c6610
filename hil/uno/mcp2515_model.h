// Register-level model of the MCP2515 for host tests: the SPI instruction set
// on a 128-byte register file, transmit buffers onto a fake bus, acceptance
// filtering with RXB0 rollover, CANINTF/EFLG flags, error counters, bus-off
// and its recovery. Behaviour follows the datasheet (DS20001801); where the
// datasheet is silent the model is strict (see the notes at each member), so
// a driver passing against it does not rely on luck.
// Used by the driver's unit tests (tests/mcp2515) and as the CAN controller
// of the simulated Uno (hil/uno, mb2co-uno).
#pragma once
#include <cstdint>
#include <vector>

#include "canopen/can_frame.h"
#include "mcp2515.h"

namespace mb2co::mcp2515::model {

class Mcp2515Model {
 public:
  Mcp2515Model() { reset(); }

  /// The driver's SPI interface, wired to this model.
  Spi spi();

  // --- SPI side (what the pins see) ---
  void select(bool active);
  uint8_t transfer(uint8_t mosi);

  // --- bus side ---
  /// Frames the chip put on the bus, in order.
  std::vector<CanFrame> bus;
  /// Sends pending TX buffers (highest TXP first, equal TXP: higher buffer
  /// number first) until none is left or `max_frames` went out. In loopback
  /// mode frames are received by the chip itself instead of going on the bus.
  /// Nothing is sent in configuration mode or bus-off. Returns frames sent.
  int transmit(int max_frames = 1000);
  /// The frame transmit() would send next, without sending it; false when it
  /// would send nothing (no TXREQ, configuration/listen-only mode, bus-off).
  bool next_transmit(CanFrame* out) const;
  /// Nominal bit rate the CNF1..CNF3 registers give with `oscillator_hz`
  /// (the SparkFun shield: 16 MHz); > 0 for every register content.
  uint32_t bitrate_bps(uint32_t oscillator_hz) const;
  /// A frame from another node arrives (normal/listen-only/loopback ignore
  /// it as the chip does in loopback; configuration mode ignores it too).
  /// Returns 0 (accepted into RXB0), 1 (RXB1), -1 (filtered out), -2 (lost: overflow).
  int receive_from_bus(const CanFrame& frame);
  /// `count` transmit errors (TEC += 8 each); past 255 the chip goes bus-off.
  void transmit_errors(int count);
  /// `count` receive errors (REC += 1 each, stops at 128 as in the standard).
  void receive_errors(int count);
  /// `bits` recessive bit times pass on the bus; in bus-off, 128 x 11 of them
  /// bring the chip back (TEC = REC = 0). Recovery sets no CANINTF flag.
  void idle_bits(uint32_t bits);
  /// Every mode request takes this many CANSTAT reads before it shows.
  void set_mode_delay(int reads) { mode_delay_ = reads; }
  /// Chip absent: MISO reads this constant and nothing is stored.
  void set_absent(bool absent, uint8_t miso = 0xFF) {
    absent_ = absent;
    absent_miso_ = miso;
  }

  // --- inspection ---
  uint8_t reg(uint8_t address) const { return regs_[map(address)]; }
  bool int_low() const { return (regs_[kIntE] & regs_[kIntF]) != 0; }
  uint8_t mode() const { return regs_[kStat] & 0xE0; }
  int spi_transactions() const { return transactions_; }

 private:
  static constexpr uint8_t kStat = 0x0E, kCtrl = 0x0F, kIntE = 0x2B, kIntF = 0x2C, kEflg = 0x2D;

  static uint8_t map(uint8_t address) {
    address &= 0x7F;
    if ((address & 0x0F) == 0x0E) return kStat;
    if ((address & 0x0F) == 0x0F) return kCtrl;
    return address;
  }
  void reset();
  int next_buffer() const;  ///< TX buffer transmit() would send next, -1 none
  CanFrame buffer_frame(int n) const;
  void write_reg(uint8_t address, uint8_t value, uint8_t mask = 0xFF);
  uint8_t read_reg(uint8_t address);
  void end_instruction();
  bool filter_matches(uint8_t filter, uint8_t mask, const CanFrame& frame) const;
  void store(uint8_t buffer, const CanFrame& frame, uint8_t filhit);
  int accept(const CanFrame& frame);
  void set_eflg(uint8_t bits, bool on);
  void update_error_flags();
  void mode_requested();

  uint8_t regs_[128] = {};
  // SPI instruction decoding.
  bool selected_ = false;
  int byte_index_ = 0;
  uint8_t instruction_ = 0;
  uint8_t address_ = 0;
  uint8_t mask_ = 0;
  uint8_t read_rx_clear_ = 0;  ///< RXnIF to clear when CS rises after READ RX BUFFER
  int transactions_ = 0;
  // Mode change latency.
  uint8_t pending_mode_ = 0x80;
  int mode_delay_ = 0;
  int mode_countdown_ = 0;
  // Error confinement.
  int tec_ = 0, rec_ = 0;
  bool bus_off_ = false;
  uint32_t recovery_bits_ = 0;
  bool absent_ = false;
  uint8_t absent_miso_ = 0xFF;
};

}  // namespace mb2co::mcp2515::model
