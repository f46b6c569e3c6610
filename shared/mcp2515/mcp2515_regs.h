// MCP2515 register map, bit names and SPI instructions (Microchip DS20001801),
// shared by the driver and the register-level test model so both speak the
// same chip.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace mcp2515 {
namespace reg {

// SPI instructions (first byte after CS falls).
constexpr uint8_t kReset = 0xC0;
constexpr uint8_t kRead = 0x03;          ///< addr, then data out; address auto-increments
constexpr uint8_t kWrite = 0x02;         ///< addr, then data in; address auto-increments
constexpr uint8_t kBitModify = 0x05;     ///< addr, mask, data (only some registers)
constexpr uint8_t kReadStatus = 0xA0;    ///< -> kStatus* bits
constexpr uint8_t kRxStatus = 0xB0;      ///< -> kRxStatus* bits
constexpr uint8_t kReadRxBuffer = 0x90;  ///< | kReadRxB*; CS rising clears that RXnIF
constexpr uint8_t kLoadTxBuffer = 0x40;  ///< | kLoadTxB*
constexpr uint8_t kRts = 0x80;           ///< | (1 << buffer): request-to-send

// Start addresses of READ RX BUFFER / LOAD TX BUFFER.
constexpr uint8_t kReadRxB0Sidh = 0x00;
constexpr uint8_t kReadRxB0D0 = 0x02;
constexpr uint8_t kReadRxB1Sidh = 0x04;
constexpr uint8_t kReadRxB1D0 = 0x06;
/// LOAD TX BUFFER start at TXBnSIDH for buffer n (0..2); +1 would start at D0.
constexpr uint8_t load_tx_sidh(uint8_t n) {
  return static_cast<uint8_t>(n * 2u);
}

// READ STATUS bits.
constexpr uint8_t kStatusRx0If = 0x01;
constexpr uint8_t kStatusRx1If = 0x02;
/// TXREQ of buffer n (0..2) in the READ STATUS byte.
constexpr uint8_t status_txreq(uint8_t n) {
  return static_cast<uint8_t>(0x04u << (2u * n));
}

// RX STATUS bits 7:6: which receive buffers hold a message.
constexpr uint8_t kRxStatusRxB0 = 0x40;
constexpr uint8_t kRxStatusRxB1 = 0x80;

// Registers. CANSTAT/CANCTRL are mirrored at every xEh/xFh.
constexpr uint8_t kRxF0Sidh = 0x00;  ///< RXF0..RXF2 at 0x00, 0x04, 0x08
constexpr uint8_t kRxF3Sidh = 0x10;  ///< RXF3..RXF5 at 0x10, 0x14, 0x18
constexpr uint8_t kBfpCtrl = 0x0C;
constexpr uint8_t kTxRtsCtrl = 0x0D;
constexpr uint8_t kCanStat = 0x0E;
constexpr uint8_t kCanCtrl = 0x0F;
constexpr uint8_t kTec = 0x1C;
constexpr uint8_t kRec = 0x1D;
constexpr uint8_t kRxM0Sidh = 0x20;
constexpr uint8_t kRxM1Sidh = 0x24;
constexpr uint8_t kCnf3 = 0x28;
constexpr uint8_t kCnf2 = 0x29;
constexpr uint8_t kCnf1 = 0x2A;
constexpr uint8_t kCanIntE = 0x2B;
constexpr uint8_t kCanIntF = 0x2C;
constexpr uint8_t kEflg = 0x2D;
constexpr uint8_t kTxB0Ctrl =
    0x30;  ///< TXBn block at 0x30 + 0x10 * n: CTRL, SIDH, SIDL, EID8, EID0, DLC, D0..D7
constexpr uint8_t kRxB0Ctrl = 0x60;  ///< RXB0 block; RXB1 at 0x70, same layout as TX
constexpr uint8_t kRxB1Ctrl = 0x70;
constexpr uint8_t tx_ctrl(uint8_t n) {
  return static_cast<uint8_t>(kTxB0Ctrl + 0x10u * n);
}
/// Filter n (0..5) SIDH address.
constexpr uint8_t rxf_sidh(uint8_t n) {
  return static_cast<uint8_t>(n < 3u ? kRxF0Sidh + 4u * n : kRxF3Sidh + 4u * (n - 3u));
}

// Offsets inside a TX/RX buffer block and inside a 4-byte filter/mask.
constexpr uint8_t kOffSidh = 1, kOffSidl = 2, kOffEid8 = 3, kOffEid0 = 4, kOffDlc = 5, kOffD0 = 6;

// CANCTRL / CANSTAT.
constexpr uint8_t kModeMask = 0xE0;  ///< REQOP (CANCTRL) and OPMOD (CANSTAT) bits 7:5
constexpr uint8_t kModeNormal = 0x00;
constexpr uint8_t kModeSleep = 0x20;
constexpr uint8_t kModeLoopback = 0x40;
constexpr uint8_t kModeListenOnly = 0x60;
constexpr uint8_t kModeConfig = 0x80;
constexpr uint8_t kCanCtrlAbat = 0x10;
constexpr uint8_t kCanCtrlOsm = 0x08;
constexpr uint8_t kCanCtrlClkEn = 0x04;

// CANINTE / CANINTF.
constexpr uint8_t kIntRx0 = 0x01;
constexpr uint8_t kIntRx1 = 0x02;
constexpr uint8_t kIntTx0 = 0x04;
constexpr uint8_t kIntTx1 = 0x08;
constexpr uint8_t kIntTx2 = 0x10;
constexpr uint8_t kIntErr = 0x20;
constexpr uint8_t kIntWak = 0x40;
constexpr uint8_t kIntMerr = 0x80;

// EFLG.
constexpr uint8_t kEflgEwarn = 0x01;
constexpr uint8_t kEflgRxWar = 0x02;
constexpr uint8_t kEflgTxWar = 0x04;
constexpr uint8_t kEflgRxEp = 0x08;
constexpr uint8_t kEflgTxEp = 0x10;
constexpr uint8_t kEflgTxBo = 0x20;
constexpr uint8_t kEflgRx0Ovr = 0x40;
constexpr uint8_t kEflgRx1Ovr = 0x80;

// TXBnCTRL.
constexpr uint8_t kTxCtrlTxp = 0x03;  ///< transmit priority 0..3, 3 = sent first
constexpr uint8_t kTxCtrlTxReq = 0x08;
constexpr uint8_t kTxCtrlTxErr = 0x10;
constexpr uint8_t kTxCtrlMloa = 0x20;
constexpr uint8_t kTxCtrlAbtf = 0x40;

// RXBnCTRL.
constexpr uint8_t kRxCtrlRxmAny = 0x60;  ///< RXM = 11: filters off, take every frame
constexpr uint8_t kRxCtrlRxRtr = 0x08;
constexpr uint8_t kRxCtrlBukt = 0x04;   ///< RXB0 only: roll over into RXB1 when full
constexpr uint8_t kRxCtrlBukt1 = 0x02;  ///< RXB0 only: read-only copy of BUKT
constexpr uint8_t kRxB0FilHit = 0x01;
constexpr uint8_t kRxB1FilHit = 0x07;

// SIDL (buffers, filters) and DLC.
constexpr uint8_t kSidlExide = 0x08;  ///< extended id (IDE in RX buffers)
constexpr uint8_t kSidlSrr = 0x10;    ///< RX only: standard frame was a remote request
constexpr uint8_t kDlcRtr = 0x40;     ///< TX: send remote frame; RX: extended remote frame
constexpr uint8_t kDlcMask = 0x0F;

}  // namespace reg
}  // namespace mcp2515
}  // namespace mb2co
