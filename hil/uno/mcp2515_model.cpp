#include "mcp2515_model.h"

#include <algorithm>

#include "mcp2515_regs.h"

namespace mb2co::mcp2515::model {
namespace {

bool bit_modifiable(uint8_t a) {
  return a == reg::kBfpCtrl || a == reg::kTxRtsCtrl || a == reg::kCanCtrl ||
         (a >= reg::kCnf3 && a <= reg::kEflg) || a == reg::tx_ctrl(0) || a == reg::tx_ctrl(1) ||
         a == reg::tx_ctrl(2) || a == reg::kRxB0Ctrl || a == reg::kRxB1Ctrl;
}

/// 29-bit value of a SIDH/SIDL/EID8/EID0 quadruple (SID in bits 28:18).
uint32_t id29(const uint8_t* r) {
  const uint32_t sid = (uint32_t{r[0]} << 3) | (r[1] >> 5);
  const uint32_t eid = (uint32_t{r[1] & 0x03u} << 16) | (uint32_t{r[2]} << 8) | r[3];
  return (sid << 18) | eid;
}

}  // namespace

Spi Mcp2515Model::spi() {
  return Spi{[](void* ctx, uint8_t out) { return static_cast<Mcp2515Model*>(ctx)->transfer(out); },
             [](void* ctx, bool active) { static_cast<Mcp2515Model*>(ctx)->select(active); }, this};
}

void Mcp2515Model::reset() {
  std::fill(std::begin(regs_), std::end(regs_), uint8_t{0});
  regs_[kCtrl] = 0x87;  // configuration mode, CLKOUT on, /8
  regs_[kStat] = 0x80;
  pending_mode_ = 0x80;
  mode_countdown_ = 0;
  tec_ = rec_ = 0;
  bus_off_ = false;
  recovery_bits_ = 0;
}

// --- SPI ------------------------------------------------------------------------

void Mcp2515Model::select(bool active) {
  if (active) {
    selected_ = true;
    byte_index_ = 0;
    read_rx_clear_ = 0;
    return;
  }
  if (selected_) {
    end_instruction();
    ++transactions_;
  }
  selected_ = false;
}

void Mcp2515Model::end_instruction() {
  // READ RX BUFFER frees the buffer when CS rises, however many bytes were read.
  if (read_rx_clear_ != 0) regs_[kIntF] = static_cast<uint8_t>(regs_[kIntF] & ~read_rx_clear_);
  read_rx_clear_ = 0;
}

uint8_t Mcp2515Model::transfer(uint8_t mosi) {
  if (absent_) return absent_miso_;
  if (!selected_) return 0xFF;  // SO is high impedance
  const int index = byte_index_++;
  if (index == 0) {
    instruction_ = mosi;
    if (mosi == reg::kReset) {
      reset();
    } else if ((mosi & 0xF8) == reg::kRts) {
      for (uint8_t n = 0; n < 3; ++n) {
        if (mosi & (1u << n)) regs_[reg::tx_ctrl(n)] |= reg::kTxCtrlTxReq;
      }
    } else if ((mosi & 0xF9) == reg::kReadRxBuffer) {
      const uint8_t nm = (mosi >> 1) & 0x03;
      address_ = static_cast<uint8_t>(((nm & 2) ? reg::kRxB1Ctrl : reg::kRxB0Ctrl) +
                                      ((nm & 1) ? reg::kOffD0 : reg::kOffSidh));
      read_rx_clear_ = (nm & 2) ? reg::kIntRx1 : reg::kIntRx0;
    } else if ((mosi & 0xF8) == reg::kLoadTxBuffer && (mosi & 0x07) <= 5) {
      const uint8_t abc = mosi & 0x07;
      address_ = static_cast<uint8_t>(reg::tx_ctrl(abc >> 1) + ((abc & 1) ? reg::kOffD0 : reg::kOffSidh));
    }
    return 0;
  }
  switch (instruction_) {
    case reg::kRead:
      if (index == 1) {
        address_ = mosi & 0x7F;
        return 0;
      }
      return read_reg(address_++);
    case reg::kWrite:
      if (index == 1) {
        address_ = mosi & 0x7F;
      } else {
        write_reg(address_++, mosi);
      }
      return 0;
    case reg::kBitModify:
      if (index == 1) address_ = mosi & 0x7F;
      if (index == 2) mask_ = mosi;
      if (index == 3) write_reg(address_, mosi, bit_modifiable(map(address_)) ? mask_ : 0xFF);
      return 0;
    case reg::kReadStatus: {
      const uint8_t f = regs_[kIntF];
      uint8_t s = f & (reg::kIntRx0 | reg::kIntRx1);
      for (uint8_t n = 0; n < 3; ++n) {
        if (regs_[reg::tx_ctrl(n)] & reg::kTxCtrlTxReq) s |= reg::status_txreq(n);
        if (f & (reg::kIntTx0 << n)) s |= static_cast<uint8_t>(0x08u << (2 * n));
      }
      return s;
    }
    case reg::kRxStatus: {
      const uint8_t f = regs_[kIntF];
      uint8_t s = static_cast<uint8_t>(((f & reg::kIntRx0) ? 0x40 : 0) | ((f & reg::kIntRx1) ? 0x80 : 0));
      const uint8_t base = (f & reg::kIntRx0) ? reg::kRxB0Ctrl : reg::kRxB1Ctrl;
      if (f & (reg::kIntRx0 | reg::kIntRx1)) {
        const bool ext = regs_[base + reg::kOffSidl] & reg::kSidlExide;
        const bool rtr =
            ext ? (regs_[base + reg::kOffDlc] & reg::kDlcRtr) : (regs_[base + reg::kOffSidl] & reg::kSidlSrr);
        s |= static_cast<uint8_t>((ext ? 0x10 : 0) | (rtr ? 0x08 : 0));
        const uint8_t hit =
            base == reg::kRxB0Ctrl ? (regs_[base] & reg::kRxB0FilHit) : (regs_[base] & reg::kRxB1FilHit);
        s |= static_cast<uint8_t>(base == reg::kRxB1Ctrl && hit < 2 ? 6 + hit : hit);
      }
      return s;
    }
    default:
      if ((instruction_ & 0xF9) == reg::kReadRxBuffer) return regs_[address_++ & 0x7F];
      if ((instruction_ & 0xF8) == reg::kLoadTxBuffer) write_reg(address_++, mosi);
      return 0;
  }
}

uint8_t Mcp2515Model::read_reg(uint8_t address) {
  const uint8_t a = map(address);
  if (a == kStat && mode_countdown_ > 0 && --mode_countdown_ == 0) {
    regs_[kStat] = static_cast<uint8_t>((regs_[kStat] & ~0xE0) | pending_mode_);
  }
  address_ &= 0x7F;
  return regs_[a];
}

void Mcp2515Model::write_reg(uint8_t address, uint8_t value, uint8_t mask) {
  address_ &= 0x7F;
  const uint8_t a = map(address);
  const bool config = (regs_[kStat] & 0xE0) == reg::kModeConfig;
  uint8_t writable = 0xFF;
  if (a == kStat || a == reg::kTec || a == reg::kRec) return;  // read-only
  if (a < 0x20 || (a >= reg::kRxM0Sidh && a <= reg::kCnf1)) {
    if (a != reg::kBfpCtrl && a != reg::kTxRtsCtrl && a != kCtrl && !config)
      return;  // filters, masks, CNF: config mode only
  }
  if (a == kEflg) writable = reg::kEflgRx0Ovr | reg::kEflgRx1Ovr;
  if ((a & 0x8F) == 0x00 && a >= reg::kTxB0Ctrl && a <= reg::tx_ctrl(2))
    writable = reg::kTxCtrlTxReq | reg::kTxCtrlTxp;
  if (a > reg::kTxB0Ctrl && a < reg::kRxB0Ctrl && (a & 0x0F) != 0) {
    if (regs_[a & 0xF0] & reg::kTxCtrlTxReq) return;  // buffer locked while its frame is pending
  }
  if (a == reg::kRxB0Ctrl) writable = reg::kRxCtrlRxmAny | reg::kRxCtrlBukt;
  if (a == reg::kRxB1Ctrl) writable = reg::kRxCtrlRxmAny;
  if (a > reg::kRxB0Ctrl && (a & 0x0F) != 0) return;  // receive buffers are read-only

  const uint8_t old = regs_[a];
  const uint8_t wanted = static_cast<uint8_t>((old & ~mask) | (value & mask));
  regs_[a] = static_cast<uint8_t>((old & ~writable) | (wanted & writable));
  if (a == reg::kRxB0Ctrl) {
    regs_[a] = static_cast<uint8_t>((regs_[a] & ~reg::kRxCtrlBukt1) |
                                    ((regs_[a] & reg::kRxCtrlBukt) ? reg::kRxCtrlBukt1 : 0));
  }
  if (a == kCtrl) {
    if ((regs_[kCtrl] & 0xE0) != (old & 0xE0) || (regs_[kStat] & 0xE0) != (regs_[kCtrl] & 0xE0))
      mode_requested();
    if (regs_[kCtrl] & reg::kCanCtrlAbat) {
      for (uint8_t n = 0; n < 3; ++n) {
        uint8_t& ctrl = regs_[reg::tx_ctrl(n)];
        if (ctrl & reg::kTxCtrlTxReq)
          ctrl = static_cast<uint8_t>((ctrl & ~reg::kTxCtrlTxReq) | reg::kTxCtrlAbtf);
      }
    }
  }
}

void Mcp2515Model::mode_requested() {
  pending_mode_ = regs_[kCtrl] & 0xE0;
  if (pending_mode_ > reg::kModeConfig) return;  // invalid request: ignored
  if (mode_delay_ == 0) {
    regs_[kStat] = static_cast<uint8_t>((regs_[kStat] & ~0xE0) | pending_mode_);
    mode_countdown_ = 0;
  } else {
    mode_countdown_ = mode_delay_;
  }
}

// --- bus --------------------------------------------------------------------------

int Mcp2515Model::next_buffer() const {
  const uint8_t mode = regs_[kStat] & 0xE0;
  if (bus_off_ || (mode != reg::kModeNormal && mode != reg::kModeLoopback)) return -1;
  int best = -1;
  for (int n = 2; n >= 0; --n) {  // equal TXP: the higher buffer number goes first
    const uint8_t ctrl = regs_[reg::tx_ctrl(static_cast<uint8_t>(n))];
    if ((ctrl & reg::kTxCtrlTxReq) == 0) continue;
    if (best < 0 || (ctrl & 3) > (regs_[reg::tx_ctrl(static_cast<uint8_t>(best))] & 3)) best = n;
  }
  return best;
}

CanFrame Mcp2515Model::buffer_frame(int n) const {
  const uint8_t* b = &regs_[reg::tx_ctrl(static_cast<uint8_t>(n))];
  CanFrame f{};
  const bool ext = b[reg::kOffSidl] & reg::kSidlExide;
  const uint32_t raw = id29(b + reg::kOffSidh);
  f.id = ext ? raw : raw >> 18;
  f.flags = static_cast<uint8_t>((ext ? CanFrame::kExtended : 0) |
                                 ((b[reg::kOffDlc] & reg::kDlcRtr) ? CanFrame::kRtr : 0));
  f.dlc = static_cast<uint8_t>(std::min(b[reg::kOffDlc] & reg::kDlcMask, 8));
  if (!f.rtr()) std::copy(b + reg::kOffD0, b + reg::kOffD0 + f.dlc, f.data);
  return f;
}

bool Mcp2515Model::next_transmit(CanFrame* out) const {
  const int n = next_buffer();
  if (n < 0) return false;
  *out = buffer_frame(n);
  return true;
}

int Mcp2515Model::transmit(int max_frames) {
  int sent = 0;
  while (sent < max_frames) {
    const int best = next_buffer();
    if (best < 0) break;
    const CanFrame f = buffer_frame(best);
    regs_[reg::tx_ctrl(static_cast<uint8_t>(best))] &= static_cast<uint8_t>(~reg::kTxCtrlTxReq);
    regs_[kIntF] |= static_cast<uint8_t>(reg::kIntTx0 << best);
    if ((regs_[kStat] & 0xE0) == reg::kModeLoopback) {
      accept(f);
    } else {
      bus.push_back(f);
      if (tec_ > 0) --tec_;
      update_error_flags();
    }
    ++sent;
  }
  return sent;
}

uint32_t Mcp2515Model::bitrate_bps(uint32_t oscillator_hz) const {
  // TQ = 2 (BRP + 1) / Fosc; a bit is SyncSeg + PropSeg + PS1 + PS2. PS2 comes
  // from CNF3 when CNF2.BTLMODE is set, else it is max(PS1, IPT = 2 TQ).
  const uint8_t c1 = regs_[reg::kCnf1], c2 = regs_[reg::kCnf2], c3 = regs_[reg::kCnf3];
  const uint32_t prop = (c2 & 0x07u) + 1u, ps1 = ((c2 >> 3) & 0x07u) + 1u;
  const uint32_t ps2 = (c2 & 0x80u) ? (c3 & 0x07u) + 1u : std::max<uint32_t>(ps1, 2u);
  const uint32_t tq_per_bit = 1u + prop + ps1 + ps2;
  return oscillator_hz / (2u * ((c1 & 0x3Fu) + 1u) * tq_per_bit);
}

int Mcp2515Model::receive_from_bus(const CanFrame& frame) {
  const uint8_t mode = regs_[kStat] & 0xE0;
  if (mode != reg::kModeNormal && mode != reg::kModeListenOnly) return -1;
  if (rec_ > 0 && rec_ < 128) --rec_;
  update_error_flags();
  return accept(frame);
}

bool Mcp2515Model::filter_matches(uint8_t filter, uint8_t mask, const CanFrame& frame) const {
  const uint8_t* f = &regs_[reg::rxf_sidh(filter)];
  const uint8_t* m = &regs_[mask ? reg::kRxM1Sidh : reg::kRxM0Sidh];
  if (static_cast<bool>(f[1] & reg::kSidlExide) != frame.extended()) return false;
  const uint32_t fv = id29(f);
  const uint32_t mv = id29(m);
  if (frame.extended()) return ((frame.id ^ fv) & mv & 0x1FFFFFFFu) == 0;
  // Standard frames: SID against bits 28:18; the EID8/EID0 bits of filter and
  // mask are compared with data bytes 0 and 1 (absent bytes read as 0).
  const uint32_t d0 = frame.dlc > 0 && !frame.rtr() ? frame.data[0] : 0;
  const uint32_t d1 = frame.dlc > 1 && !frame.rtr() ? frame.data[1] : 0;
  const uint32_t fv_std = (frame.id << 18) | (d0 << 8) | d1;
  return ((fv_std ^ fv) & mv & 0x1FFCFFFFu) == 0;  // EID17:16 play no part
}

void Mcp2515Model::store(uint8_t buffer, const CanFrame& frame, uint8_t filhit) {
  uint8_t* b = &regs_[buffer ? reg::kRxB1Ctrl : reg::kRxB0Ctrl];
  if (frame.extended()) {
    b[reg::kOffSidh] = static_cast<uint8_t>(frame.id >> 21);
    b[reg::kOffSidl] =
        static_cast<uint8_t>((((frame.id >> 18) & 7) << 5) | reg::kSidlExide | ((frame.id >> 16) & 3));
    b[reg::kOffEid8] = static_cast<uint8_t>(frame.id >> 8);
    b[reg::kOffEid0] = static_cast<uint8_t>(frame.id);
    b[reg::kOffDlc] = static_cast<uint8_t>(frame.dlc | (frame.rtr() ? reg::kDlcRtr : 0));
  } else {
    // Strict: a standard remote frame shows only in SIDL.SRR, as documented.
    b[reg::kOffSidh] = static_cast<uint8_t>(frame.id >> 3);
    b[reg::kOffSidl] = static_cast<uint8_t>(((frame.id & 7) << 5) | (frame.rtr() ? reg::kSidlSrr : 0));
    b[reg::kOffEid8] = 0;
    b[reg::kOffEid0] = 0;
    b[reg::kOffDlc] = frame.dlc;
  }
  if (!frame.rtr()) std::copy(frame.data, frame.data + std::min<int>(frame.dlc, 8), b + reg::kOffD0);
  const uint8_t rtr = frame.rtr() ? reg::kRxCtrlRxRtr : 0;
  if (buffer == 0) {
    b[0] = static_cast<uint8_t>((b[0] & ~(reg::kRxCtrlRxRtr | reg::kRxB0FilHit)) | rtr | (filhit & 1));
  } else {
    b[0] = static_cast<uint8_t>((b[0] & ~(reg::kRxCtrlRxRtr | reg::kRxB1FilHit)) | rtr | (filhit & 7));
  }
  regs_[kIntF] |= buffer ? reg::kIntRx1 : reg::kIntRx0;
}

int Mcp2515Model::accept(const CanFrame& frame) {
  const bool any0 = (regs_[reg::kRxB0Ctrl] & reg::kRxCtrlRxmAny) == reg::kRxCtrlRxmAny;
  const bool any1 = (regs_[reg::kRxB1Ctrl] & reg::kRxCtrlRxmAny) == reg::kRxCtrlRxmAny;
  int hit0 = any0 ? 0 : -1;
  for (uint8_t f = 0; f < 2 && hit0 < 0; ++f) {
    if (filter_matches(f, 0, frame)) hit0 = f;
  }
  int hit1 = any1 ? 2 : -1;
  for (uint8_t f = 2; f < 6 && hit1 < 0; ++f) {
    if (filter_matches(f, 1, frame)) hit1 = f;
  }
  const bool full0 = regs_[kIntF] & reg::kIntRx0;
  const bool full1 = regs_[kIntF] & reg::kIntRx1;
  if (hit0 >= 0) {
    if (!full0) {
      store(0, frame, static_cast<uint8_t>(hit0));
      return 0;
    }
    if (regs_[reg::kRxB0Ctrl] & reg::kRxCtrlBukt) {
      if (!full1) {
        store(1, frame, static_cast<uint8_t>(hit0));  // FILHIT 0/1: rolled over
        return 1;
      }
      set_eflg(reg::kEflgRx1Ovr, true);
      return -2;
    }
    set_eflg(reg::kEflgRx0Ovr, true);
    return -2;
  }
  if (hit1 >= 0) {
    if (!full1) {
      store(1, frame, static_cast<uint8_t>(hit1));
      return 1;
    }
    set_eflg(reg::kEflgRx1Ovr, true);
    return -2;
  }
  return -1;
}

// --- error confinement ---------------------------------------------------------------

void Mcp2515Model::set_eflg(uint8_t bits, bool on) {
  const uint8_t old = regs_[kEflg];
  regs_[kEflg] = static_cast<uint8_t>(on ? (old | bits) : (old & ~bits));
  if (regs_[kEflg] & ~old) regs_[kIntF] |= reg::kIntErr;  // ERRIF on every new error condition
}

void Mcp2515Model::update_error_flags() {
  regs_[reg::kTec] = static_cast<uint8_t>(std::min(tec_, 255));
  regs_[reg::kRec] = static_cast<uint8_t>(rec_);
  const uint8_t want = static_cast<uint8_t>(
      ((tec_ >= 96 || rec_ >= 96) ? reg::kEflgEwarn : 0) | (rec_ >= 96 ? reg::kEflgRxWar : 0) |
      (tec_ >= 96 ? reg::kEflgTxWar : 0) | (rec_ >= 128 ? reg::kEflgRxEp : 0) |
      (tec_ >= 128 ? reg::kEflgTxEp : 0) | (bus_off_ ? reg::kEflgTxBo : 0));
  const uint8_t old = regs_[kEflg] & 0x3F;
  regs_[kEflg] = static_cast<uint8_t>((regs_[kEflg] & 0xC0) | want);
  if (want & ~old) regs_[kIntF] |= reg::kIntErr;  // entering a state raises ERRIF; leaving it does not
}

void Mcp2515Model::transmit_errors(int count) {
  for (int i = 0; i < count && !bus_off_; ++i) {
    tec_ += 8;
    for (uint8_t n = 0; n < 3; ++n) {
      if (regs_[reg::tx_ctrl(n)] & reg::kTxCtrlTxReq) regs_[reg::tx_ctrl(n)] |= reg::kTxCtrlTxErr;
    }
    regs_[kIntF] |= reg::kIntMerr;
    if (tec_ > 255) {
      bus_off_ = true;
      recovery_bits_ = 0;
    }
  }
  update_error_flags();
}

void Mcp2515Model::receive_errors(int count) {
  rec_ = std::min(rec_ + count, 128);
  regs_[kIntF] |= reg::kIntMerr;
  update_error_flags();
}

void Mcp2515Model::idle_bits(uint32_t bits) {
  if (!bus_off_) return;
  recovery_bits_ += bits;
  if (recovery_bits_ >= 128u * 11u) {
    bus_off_ = false;
    tec_ = rec_ = 0;
    update_error_flags();
  }
}

}  // namespace mb2co::mcp2515::model
