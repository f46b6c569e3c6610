#include "mcp2515.h"

#include <stddef.h>
#include <string.h>

#include "mcp2515_regs.h"

namespace mb2co {
namespace mcp2515 {

constexpr uint8_t Driver::kNoPriority;

namespace {

/// CANSTAT polls before a mode change counts as failed. Each poll is a 3-byte
/// READ (~6 us on the AVR at 8 MHz SPI): ~6 ms, far above the chip's worst
/// case (it finishes a frame in progress first: < 160 bits = 1.3 ms at 125k).
constexpr uint16_t kModePolls = 1000;

constexpr uint32_t kMaxExtendedId = 0x1FFFFFFFu;
static_assert(reg::kModeNormal == 0, "Driver's constructor starts in normal mode");

uint8_t reqop(Mode mode) {
  return mode == Mode::kLoopback     ? reg::kModeLoopback
         : mode == Mode::kListenOnly ? reg::kModeListenOnly
                                     : reg::kModeNormal;
}

/// SIDH, SIDL, EID8, EID0 of an 11-bit mask or filter for standard frames
/// (EXIDE = 0; the EID bits stay 0 so data bytes are never compared).
void encode_standard(uint16_t id, uint8_t* out) {
  out[0] = static_cast<uint8_t>(id >> 3);
  out[1] = static_cast<uint8_t>((id & 0x07u) << 5);
  out[2] = 0;
  out[3] = 0;
}

/// True when (key_a, seq_a) goes on the bus before (key_b, seq_b); sequence
/// numbers are compared wrap-safe (at most 3 frames are ever compared).
bool before(uint32_t key_a, uint8_t seq_a, uint32_t key_b, uint8_t seq_b) {
  if (key_a != key_b) return key_a < key_b;
  return static_cast<int8_t>(static_cast<uint8_t>(seq_a - seq_b)) < 0;
}

}  // namespace

namespace {

/// SIDH, SIDL, EID8, EID0, DLC of `frame` as the TX buffer wants them.
void encode_header(const CanFrame& frame, uint8_t* out) {
  // Byte-wise: shifts by multiples of 8 are free on the AVR, others are loops.
  const uint8_t b0 = static_cast<uint8_t>(frame.id);
  const uint8_t b1 = static_cast<uint8_t>(frame.id >> 8);
  if (frame.extended()) {
    const uint8_t b2 = static_cast<uint8_t>(frame.id >> 16);
    const uint8_t b3 = static_cast<uint8_t>(frame.id >> 24);
    out[0] = static_cast<uint8_t>((b3 << 3) | (b2 >> 5));                               // SID10:3
    out[1] = static_cast<uint8_t>(((b2 << 3) & 0xE0) | reg::kSidlExide | (b2 & 0x03));  // SID2:0, EID17:16
    out[2] = b1;
    out[3] = b0;
  } else {
    out[0] = static_cast<uint8_t>((b1 << 5) | (b0 >> 3));
    out[1] = static_cast<uint8_t>(b0 << 5);
    out[2] = 0;
    out[3] = 0;
  }
  out[4] = static_cast<uint8_t>(frame.dlc | (frame.rtr() ? reg::kDlcRtr : 0u));
}

uint32_t header_key(const uint8_t* header) {
  // SID, then RTR (standard) or SRR = 1, IDE = 1 (extended), then EID.
  const bool ext = header[1] & reg::kSidlExide;
  const uint8_t bits = ext ? 0x18 : (header[4] & reg::kDlcRtr) ? 0x10 : 0x00;
  const uint8_t b2 = static_cast<uint8_t>((header[1] & 0xE0u) | bits | (header[1] & 0x03u));
  return (static_cast<uint32_t>(header[0]) << 24) | (static_cast<uint32_t>(b2) << 16) |
         (static_cast<uint16_t>(header[2] << 8) | header[3]);
}

}  // namespace

uint32_t arbitration_key(const CanFrame& frame) {
  uint8_t header[5];
  encode_header(frame, header);
  return header_key(header);
}

// --- SPI instructions -----------------------------------------------------
// Every instruction is built in a byte buffer and shifted in place: one loop
// with the interface's function pointers instead of a call site per byte
// (which costs flash on the AVR).

void Driver::xfer(uint8_t* bytes, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i) bytes[i] = spi_.transfer(spi_.ctx, bytes[i]);
}

void Driver::transact(uint8_t* bytes, uint8_t count) {
  spi_.select(spi_.ctx, true);
  xfer(bytes, count);
  spi_.select(spi_.ctx, false);
}

uint8_t Driver::read(uint8_t address) {
  uint8_t bytes[3] = {reg::kRead, address, 0};
  transact(bytes, 3);
  return bytes[2];
}

void Driver::write(uint8_t address, const uint8_t* values, uint8_t count) {
  uint8_t bytes[2 + 12];  // longest write: three filters
  bytes[0] = reg::kWrite;
  bytes[1] = address;
  memcpy(bytes + 2, values, count);
  transact(bytes, static_cast<uint8_t>(2u + count));
}

void Driver::bit_modify(uint8_t address, uint8_t mask, uint8_t value) {
  uint8_t bytes[4] = {reg::kBitModify, address, mask, value};
  transact(bytes, 4);
}

void Driver::command(uint8_t instruction) {
  transact(&instruction, 1);
}

uint8_t Driver::command_read(uint8_t instruction) {
  uint8_t bytes[2] = {instruction, 0};
  transact(bytes, 2);
  return bytes[1];
}

// --- configuration --------------------------------------------------------

bool Driver::request_mode(uint8_t opmode) {
  // Whole CANCTRL: ABAT = 0, one-shot off, CLKOUT off (unused on the shield).
  write1(reg::kCanCtrl, opmode);
  for (uint16_t i = 0; i < kModePolls; ++i) {
    if ((read(reg::kCanStat) & reg::kModeMask) == opmode) return true;
  }
  return false;
}

bool Driver::begin(Bitrate rate, Mode mode) {
  command(reg::kReset);
  // After RESET the chip is in configuration mode once its oscillator runs.
  bool in_config = false;
  for (uint16_t i = 0; i < kModePolls && !in_config; ++i) {
    in_config = (read(reg::kCanStat) & reg::kModeMask) == reg::kModeConfig;
  }
  if (!in_config) return false;

  // CNF3, CNF2, CNF1 as one constant per rate (a switch: the timing tables
  // would otherwise be copied into RAM on the AVR).
  constexpr uint32_t kCnf1000k = cnf_bytes(kTiming1000k);
  constexpr uint32_t kCnf500k = cnf_bytes(kTiming500k);
  constexpr uint32_t kCnf250k = cnf_bytes(kTiming250k);
  constexpr uint32_t kCnf125k = cnf_bytes(kTiming125k);
  const uint32_t cnf = rate == Bitrate::k1000k  ? kCnf1000k
                       : rate == Bitrate::k500k ? kCnf500k
                       : rate == Bitrate::k250k ? kCnf250k
                                                : kCnf125k;
  // CNF3, CNF2, CNF1, CANINTE are consecutive (0x28..0x2B).
  const uint8_t config[4] = {static_cast<uint8_t>(cnf), static_cast<uint8_t>(cnf >> 8),
                             static_cast<uint8_t>(cnf >> 16),
                             static_cast<uint8_t>(reg::kIntRx0 | reg::kIntRx1 | reg::kIntErr)};
  write(reg::kCnf3, config, 4);
  // Read back: a missing chip answers a constant (MISO floating or pulled).
  for (uint8_t i = 0; i < 4; ++i) {
    if (read(static_cast<uint8_t>(reg::kCnf3 + i)) != config[i]) return false;
  }
  const uint8_t clear[2] = {0, 0};  // CANINTF, EFLG
  write(reg::kCanIntF, clear, 2);

  mode_ = reqop(mode);
  state_ = ErrorState::kActive;
  stage_next_ = stage_count_ = 0;
  for (uint8_t n = 0; n < 3; ++n) tx_prio_[n] = kNoPriority;
  return configure_filters(nullptr);
}

bool Driver::set_mode(Mode mode) {
  mode_ = reqop(mode);
  return request_mode(mode_);
}

bool Driver::configure_filters(const FilterPlan* plan) {
  if (!request_mode(reg::kModeConfig)) return false;  // masks/filters are writable only here
  if (plan != nullptr) {
    // Three writes of consecutive registers: RXF0-2, RXF3-5, then RXM0-1
    // (the masks are the two words before the filters in FilterPlan).
    static_assert(reg::rxf_sidh(3) == reg::rxf_sidh(0) + 0x10 && reg::kRxM0Sidh == reg::rxf_sidh(0) + 0x20 &&
                      reg::kRxM1Sidh == reg::kRxM0Sidh + 4,
                  "filter and mask blocks 10h apart");
    static_assert(offsetof(FilterPlan, filter) == offsetof(FilterPlan, mask) + 2 * sizeof(uint16_t),
                  "masks right before the filters");
    const uint16_t* words = plan->filter;
    for (uint8_t block = 0; block < 3; ++block) {
      const uint8_t count = block < 2 ? 3 : 2;
      uint8_t bytes[12];
      for (uint8_t k = 0; k < count; ++k) encode_standard(words[k], bytes + 4 * k);
      write(static_cast<uint8_t>(reg::rxf_sidh(0) + 0x10 * block), bytes, static_cast<uint8_t>(4 * count));
      words = block == 0 ? words + 3 : plan->mask;
    }
  }
  // RXB0 rolls over into RXB1, so RXB0's ids get two buffers of depth.
  const uint8_t rxm = plan != nullptr ? 0 : reg::kRxCtrlRxmAny;
  write1(reg::kRxB0Ctrl, static_cast<uint8_t>(rxm | reg::kRxCtrlBukt));
  write1(reg::kRxB1Ctrl, rxm);
  return request_mode(mode_);
}

bool Driver::set_filters(const uint16_t* ids, uint8_t count, FilterPlan* plan_out) {
  FilterPlan plan;
  if (!plan_filters(ids, count, plan)) return false;
  if (plan_out != nullptr) *plan_out = plan;
  return configure_filters(&plan);
}

bool Driver::accept_all() {
  return configure_filters(nullptr);
}

uint8_t Driver::tec() {
  return read(reg::kTec);
}
uint8_t Driver::rec() {
  return read(reg::kRec);
}

// --- transmit ---------------------------------------------------------------

bool Driver::sink_send(void* ctx, const CanFrame& frame) {
  return static_cast<Driver*>(ctx)->send(frame);
}

bool Driver::send(const CanFrame& frame) {
  if (frame.dlc > 8 || frame.id > (frame.extended() ? kMaxExtendedId : 0x7FFu)) {
    ++counters_.tx_invalid;
    return false;
  }
  const uint8_t status = command_read(reg::kReadStatus);
  uint8_t pending = 0;  // bit n: TXBn still waits to be sent
  uint8_t buffer = 3;
  uint8_t buffer_bit = 0;  // 1 << buffer
  // Masks walk by shifting bytes: a shift by a variable count is a loop on
  // the AVR.
  static_assert(
      reg::status_txreq(1) == reg::status_txreq(0) << 2 && reg::status_txreq(2) == reg::status_txreq(0) << 4,
      "TXREQ bits of READ STATUS: every second bit");
  uint8_t txreq = status;  // TXREQ of buffer n at status_txreq(0) after n steps
  for (uint8_t n = 0, bit = 1; n < 3;
       ++n, bit = static_cast<uint8_t>(bit << 1), txreq = static_cast<uint8_t>(txreq >> 2)) {
    if (txreq & reg::status_txreq(0)) {
      pending = static_cast<uint8_t>(pending | bit);
    } else if (buffer == 3) {
      buffer = n;
      buffer_bit = bit;
    }
  }
  if (buffer == 3) {
    ++counters_.tx_full;
    return false;
  }

  uint8_t bytes[6 + 8];
  bytes[0] = static_cast<uint8_t>(reg::kLoadTxBuffer | reg::load_tx_sidh(buffer));
  encode_header(frame, bytes + 1);
  const uint8_t data_bytes = frame.rtr() ? 0 : frame.dlc;
  memcpy(bytes + 6, frame.data, data_bytes);
  tx_key_[buffer] = header_key(bytes + 1);  // before transact() overwrites bytes with MISO
  transact(bytes, static_cast<uint8_t>(6u + data_bytes));

  tx_seq_[buffer] = seq_++;
  tx_prio_[buffer] = kNoPriority;  // idle: its TXP is whatever was left there
  rank_transmit_buffers(static_cast<uint8_t>(pending | buffer_bit));
  command(static_cast<uint8_t>(reg::kRts | buffer_bit));
  ++counters_.tx_frames;
  return true;
}

void Driver::rank_transmit_buffers(uint8_t queued) {
  // rank[n]: how many queued frames go before buffer n's. Target TXP: 3 for
  // the frame that wins arbitration first, then 2, 1.
  // Not queued: rank 3, which no pass below handles. Masks walk by shifting
  // a byte (a shift by a variable count is a loop on the AVR).
  uint8_t rank[3];
  for (uint8_t n = 0, bit_n = 1; n < 3; ++n, bit_n = static_cast<uint8_t>(bit_n << 1)) {
    rank[n] = 3;
    if (!(queued & bit_n)) continue;
    rank[n] = 0;
    for (uint8_t m = 0, bit_m = 1; m < 3; ++m, bit_m = static_cast<uint8_t>(bit_m << 1)) {
      if (m != n && (queued & bit_m) && before(tx_key_[m], tx_seq_[m], tx_key_[n], tx_seq_[n])) {
        ++rank[n];
      }
    }
  }
  // Pending buffers already hold strictly decreasing TXP in send order. The
  // chip may start one at any moment, so keep that true at every step: first
  // lower priorities from the back (last-sent first), then raise them from
  // the front.
  for (uint8_t pass = 0; pass < 6; ++pass) {
    const bool lowering = pass < 3;
    const uint8_t r = lowering ? static_cast<uint8_t>(2u - pass) : static_cast<uint8_t>(pass - 3u);
    for (uint8_t n = 0; n < 3; ++n) {
      if (rank[n] != r) continue;
      const uint8_t target = static_cast<uint8_t>(3u - r);
      const bool known = tx_prio_[n] != kNoPriority;
      if (lowering ? (known && target < tx_prio_[n]) : (tx_prio_[n] != target)) {
        bit_modify(reg::tx_ctrl(n), reg::kTxCtrlTxp, target);
        tx_prio_[n] = target;
      }
    }
  }
}

// --- receive and flags --------------------------------------------------------

void Driver::read_rx_buffer(uint8_t start, CanFrame& frame) {
  uint8_t head[6] = {static_cast<uint8_t>(reg::kReadRxBuffer | start), 0, 0, 0, 0, 0};
  spi_.select(spi_.ctx, true);
  xfer(head, 6);  // SIDH, SIDL, EID8, EID0, DLC follow the instruction
  const uint8_t sidl = head[2];
  const uint8_t dlc = head[5];
  frame.dlc = static_cast<uint8_t>(dlc & reg::kDlcMask);
  if (frame.dlc > 8) frame.dlc = 8;  // DLC 9..15 still carries 8 bytes
  const uint8_t sidh = head[1];
  if (sidl & reg::kSidlExide) {
    // Byte-wise assembly: shifts by multiples of 8 cost nothing on the AVR.
    const uint8_t b3 = static_cast<uint8_t>(sidh >> 3);
    const uint8_t b2 = static_cast<uint8_t>((sidh << 5) | ((sidl >> 3) & 0x1C) | (sidl & 0x03));
    frame.id = (static_cast<uint32_t>(b3) << 24) | (static_cast<uint32_t>(b2) << 16) |
               static_cast<uint16_t>((head[3] << 8) | head[4]);
    frame.flags = static_cast<uint8_t>(CanFrame::kExtended | ((dlc & reg::kDlcRtr) ? CanFrame::kRtr : 0));
  } else {
    frame.id = static_cast<uint16_t>((sidh << 3) | (sidl >> 5));
    frame.flags = (sidl & reg::kSidlSrr) ? CanFrame::kRtr : 0;
  }
  // Data bytes shift in while whatever frame.data held shifts out (MOSI is
  // don't-care during a read).
  xfer(frame.data, frame.rtr() ? 0 : frame.dlc);
  spi_.select(spi_.ctx, false);  // CS rising clears RXnIF: the buffer is free again
}

void Driver::fetch_received() {
  if (stage_count_ != 0) return;  // the caller drains the stage first
  stage_next_ = 0;
  uint8_t rx = command_read(reg::kRxStatus);
  if (rx & reg::kRxStatusRxB0) {
    read_rx_buffer(reg::kReadRxB0Sidh, stage_[stage_count_++]);
    // Look at RXB1 again right away. A frame rolls over into RXB1 only while
    // RXB0 is full, so what RXB1 holds now arrived before the frame just read
    // was released, or came through RXB1's own filters (other ids). A newer
    // rollover would need RXB0 refilled first: a whole frame (>= 47 us), far
    // longer than these few SPI bytes. So RXB0 then RXB1 is arrival order.
    rx = command_read(reg::kRxStatus);
  }
  if (rx & reg::kRxStatusRxB1) read_rx_buffer(reg::kReadRxB1Sidh, stage_[stage_count_++]);
}

bool Driver::receive(CanFrame& frame) {
  if (stage_next_ >= stage_count_) {
    stage_next_ = stage_count_ = 0;
    return false;
  }
  frame = stage_[stage_next_++];
  if (stage_next_ == stage_count_) stage_next_ = stage_count_ = 0;
  ++counters_.rx_frames;
  return true;
}

uint8_t Driver::service() {
  uint8_t events = 0;
  const uint8_t intf = read(reg::kCanIntF);
  if (intf & (reg::kIntRx0 | reg::kIntRx1)) fetch_received();

  // Bus-off recovery raises no interrupt: keep looking while not error-active.
  if ((intf & reg::kIntErr) == 0 && state_ == ErrorState::kActive) return events;
  // Clear ERRIF before reading EFLG: a change after the read raises it again.
  if (intf & reg::kIntErr) bit_modify(reg::kCanIntF, reg::kIntErr, 0);
  const uint8_t eflg = read(reg::kEflg);
  const uint8_t overflow = static_cast<uint8_t>(eflg & (reg::kEflgRx0Ovr | reg::kEflgRx1Ovr));
  if (overflow != 0) {
    bit_modify(reg::kEflg, overflow, 0);
    counters_.rx_overflows =
        static_cast<uint16_t>(counters_.rx_overflows + ((overflow & reg::kEflgRx0Ovr) ? 1u : 0u) +
                              ((overflow & reg::kEflgRx1Ovr) ? 1u : 0u));
    events |= kEventRxOverflow;
  }
  const ErrorState state = (eflg & reg::kEflgTxBo)                      ? ErrorState::kBusOff
                           : (eflg & (reg::kEflgTxEp | reg::kEflgRxEp)) ? ErrorState::kPassive
                           : (eflg & reg::kEflgEwarn)                   ? ErrorState::kWarning
                                                                        : ErrorState::kActive;
  if (state != state_) {
    events |= kEventStateChanged;
    if (state == ErrorState::kBusOff) {
      ++counters_.bus_offs;
      events |= kEventBusOff;
    } else if (state_ == ErrorState::kBusOff) {
      events |= kEventBusOffRecovered;
    }
    state_ = state;
  }
  return events;
}

}  // namespace mcp2515
}  // namespace mb2co
