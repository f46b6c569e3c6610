// Data that an SDO transfer moves without holding it: a byte stream by offset
// (SdoData, the SDO client's source or destination), and objects an
// application serves outside the OD table (SdoDomain: a DOMAIN such as CiA
// 302's 1F50h "program data", far larger than any OD value). Plain function
// pointers with a context, as the port contract (platform/device_port.h).
#pragma once
#include <stdint.h>

#include "canopen/sdo_abort.h"

namespace mb2co {
namespace canopen {

/// Where an SDO client's upload goes to, or its download comes from. A
/// buffer in RAM on the AVR, a file on Linux. Called from the context that
/// calls the client (never re-entered); `data`/`buf` are borrowed for the call.
struct SdoData {
  /// Upload: `n` bytes that belong at `offset`. Offsets arrive in order and
  /// contiguous from 0. kSdoOk, or the abort code the client sends (e.g.
  /// 05040005h when the destination is full).
  SdoAbort (*write)(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n);
  /// Download: copy the `n` bytes at `offset` into `buf` (offset + n <= the
  /// size given to start_download). Random access: a block transfer reads a
  /// sub-block again when the server asks to have it resent.
  SdoAbort (*read)(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n);
  void* ctx;
};

/// Objects the SDO server serves from the application instead of the OD
/// table (host builds only: MB2CO_CONFIG_SDO_BLOCK, sdo_server.h). The server asks
/// owns() before it looks into the OD. A download goes to a staging area of
/// the application: begin(), write() in order, commit() once the transfer
/// completed; a download that ends any other way (abort, timeout, a new
/// request) never reaches commit(), so the object keeps its old content whole.
struct SdoDomain {
  /// True when (index, sub) is one of the application's objects.
  bool (*owns)(void* ctx, uint16_t index, uint8_t sub);
  /// Current size of the object in bytes (what an upload sends).
  uint32_t (*size)(void* ctx, uint16_t index, uint8_t sub);
  /// Copies the `n` bytes at `offset` (offset + n <= size) into `buf`.
  /// Random access (block retransmission reads a sub-block again).
  SdoAbort (*read)(void* ctx, uint16_t index, uint8_t sub, uint32_t offset, uint8_t* buf, uint16_t n);
  /// A download starts: `size` bytes when `indicated`, else unknown. Empties
  /// the staging area. An abort code refuses it (read-only object 06010002h,
  /// too large 06070012h).
  SdoAbort (*begin)(void* ctx, uint16_t index, uint8_t sub, uint32_t size, bool indicated);
  /// `n` bytes at `offset` into the staging area; offsets in order, from 0.
  /// 06070012h when the object cannot hold them.
  SdoAbort (*write)(void* ctx, uint16_t index, uint8_t sub, uint32_t offset, const uint8_t* data, uint16_t n);
  /// The download completed with `size` bytes: they become the content.
  SdoAbort (*commit)(void* ctx, uint16_t index, uint8_t sub, uint32_t size);
  void* ctx;
};

}  // namespace canopen
}  // namespace mb2co
