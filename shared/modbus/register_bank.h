// The Modbus data model as the slave sees it. The data lives elsewhere (the
// gateway implements this on the CANopen Object Dictionary; tests on arrays).
#pragma once
#include <stdint.h>

#include "modbus/data_spans.h"
#include "modbus/protocol.h"

namespace mb2co {
namespace modbus {

/// The four Modbus tables; addresses are PDU addresses 0..65535 in each.
enum class Table : uint8_t { kCoils, kDiscreteInputs, kInputRegisters, kHoldingRegisters };

enum class Access : uint8_t { kRead, kWrite };

/// Contract between the slave and the data. The slave calls it only from
/// process()/on_byte(), one call at a time, and only after the request passed
/// the function-code and quantity checks (exceptions 01 and 03 are the
/// slave's). Per request the calls are:
///   1. covers() for every address range of the request: false gives
///      exception 02 and nothing else is called;
///   2. exactly one read_* or write_* (FC 17: write_registers, then
///      read_registers if the write succeeded).
///
/// Which exception for what (the gateway's OD mapping follows this):
///   02 IllegalDataAddress: an address in the range is unmapped, or mapped to
///      an entry without the requested access (write to a read-only/const OD
///      entry, read of a write-only one). Decided by covers(), before anything
///      is executed, so the state diagrams' order (02 before 04) holds.
///   04 ServerDeviceFailure: the access itself failed: a value rejected by the
///      entry (outside its limits, refused by a write hook), an OD read/write
///      error. Returned by read_*/write_*.
///   03 IllegalDataValue is never the bank's: it means a malformed request.
/// read_*/write_* may return any of 01..04; kNone means success.
class RegisterBank {
 public:
  /// True when `access` is allowed at every address start..start+count-1 of
  /// `table` (1 ≤ count, start + count ≤ 65536 guaranteed). No side effects.
  virtual bool covers(Table table, Access access, uint16_t start, uint16_t count) = 0;

  /// Reads coils or discrete inputs start..start+out.count-1 into `out`
  /// (cleared to zero beforehand).
  virtual Exception read_bits(Table table, uint16_t start, BitSpan out) = 0;

  /// Reads input or holding registers start..start+out.count-1 into `out`.
  virtual Exception read_registers(Table table, uint16_t start, RegisterSpan out) = 0;

  /// Writes coils start..start+values.count-1. All-or-nothing: on any
  /// exception no coil has changed (validate every value, then commit).
  virtual Exception write_coils(uint16_t start, ConstBitSpan values) = 0;

  /// Writes holding registers start..start+values.count-1. All-or-nothing
  /// like write_coils.
  virtual Exception write_registers(uint16_t start, ConstRegisterSpan values) = 0;

 protected:
  ~RegisterBank() = default;  // not deleted through this interface (no heap)
};

/// Device identification objects of the basic category (FC 2B / MEI 0E):
/// 0x00 vendor name, 0x01 product code, 0x02 major-minor revision (ASCII).
/// The gateway fills them from 1008h–100Ah / 1018h.
class DeviceIdentity {
 public:
  enum : uint8_t { kVendorName = 0x00, kProductCode = 0x01, kRevision = 0x02 };
  enum : uint8_t { kLastBasicObject = kRevision };

  /// Copies the first min(length, capacity) bytes of object `id` (0..2) to
  /// `out` and returns the object's full length (like snprintf), so the
  /// caller can tell whether it fitted. Strings may live in flash on the AVR.
  virtual uint8_t copy_object(uint8_t id, uint8_t* out, uint8_t capacity) = 0;

 protected:
  ~DeviceIdentity() = default;
};

}  // namespace modbus
}  // namespace mb2co
