// CiA 301 SDO abort codes (§7.2.4.3.17): the one result type of the CANopen
// core. Every function of shared/canopen, shared/gateway and shared/ionode
// that decides about an access answers with an SdoAbort (kSdoOk = done), up to
// the SDO server, which puts the value on the bus as it is: the enumerators
// are the exact CiA 301 codes. A write hook's extra outcome "done, not stored"
// is HookResult (od.h), not a value of this type.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace canopen {

enum SdoAbort : uint32_t {
  kSdoOk = 0,
  kAbortToggle = 0x05030000u,        ///< toggle bit not alternated
  kAbortTimeout = 0x05040000u,       ///< SDO protocol timed out
  kAbortCommand = 0x05040001u,       ///< client/server command specifier not valid or unknown
  kAbortBlockSize = 0x05040002u,     ///< invalid block size (block transfer only)
  kAbortSequence = 0x05040003u,      ///< invalid sequence number (block transfer only)
  kAbortCrc = 0x05040004u,           ///< CRC error (block transfer only)
  kAbortOutOfMemory = 0x05040005u,   ///< out of memory (an SDO client's buffer is too small)
  kAbortUnsupported = 0x06010000u,   ///< unsupported access to an object
  kAbortWriteOnly = 0x06010001u,     ///< attempt to read a write-only object
  kAbortReadOnly = 0x06010002u,      ///< attempt to write a read-only object
  kAbortNoObject = 0x06020000u,      ///< object does not exist in the object dictionary
  kAbortNotMappable = 0x06040041u,   ///< object cannot be mapped to the PDO
  kAbortMapLength = 0x06040042u,     ///< mapped objects would exceed the PDO length
  kAbortIncompatible = 0x06040043u,  ///< general parameter incompatibility reason
  kAbortTypeMismatch = 0x06070010u,  ///< data type / length of service parameter does not match
  kAbortTooLong = 0x06070012u,       ///< length of service parameter too high
  kAbortTooShort = 0x06070013u,      ///< length of service parameter too low
  kAbortNoSubindex = 0x06090011u,    ///< sub-index does not exist
  kAbortInvalidValue = 0x06090030u,  ///< invalid value for parameter (download only)
  kAbortValueTooHigh = 0x06090031u,  ///< value of parameter written too high
  kAbortValueTooLow = 0x06090032u,   ///< value of parameter written too low
  kAbortGeneral = 0x08000000u,       ///< general error
  kAbortStore = 0x08000020u,         ///< data cannot be transferred or stored to the application
  kAbortLocalControl = 0x08000021u,  ///< ... because of local control
  kAbortDeviceState = 0x08000022u,   ///< ... because of the present device state
};

}  // namespace canopen
}  // namespace mb2co
