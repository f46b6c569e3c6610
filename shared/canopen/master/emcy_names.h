// What an emergency error code (CiA 301 §7.2.7.1, table 21) and the error
// register 1001h bits mean, as classes and constant names. The names are
// MB2CO_FLASH strings (flash on the AVR, read them with flash_byte(); plain
// C strings elsewhere), never copied into RAM.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace canopen {

/// The class of an error code, from its high byte (and the 81xxh/82xxh
/// subclasses of monitoring).
enum EmcyClass : uint8_t {
  kEmcyClassErrorReset = 0,       ///< 0000h: error reset or no error
  kEmcyClassGeneric,              ///< 10xxh
  kEmcyClassCurrent,              ///< 2xxxh
  kEmcyClassVoltage,              ///< 3xxxh
  kEmcyClassTemperature,          ///< 4xxxh
  kEmcyClassDeviceHardware,       ///< 50xxh
  kEmcyClassDeviceSoftware,       ///< 6xxxh
  kEmcyClassAdditionalModules,    ///< 70xxh
  kEmcyClassMonitoring,           ///< 80xxh, 83xxh-8Fxxh
  kEmcyClassCommunication,        ///< 81xxh (monitoring: communication)
  kEmcyClassProtocol,             ///< 82xxh (monitoring: protocol error)
  kEmcyClassExternal,             ///< 90xxh
  kEmcyClassAdditionalFunctions,  ///< F0xxh
  kEmcyClassDeviceSpecific,       ///< FFxxh
  kEmcyClassUnknown,              ///< a code table 21 does not define (e.g. 0001h, A000h)
};

EmcyClass emcy_class(uint16_t code);
/// "generic", "communication", ... (MB2CO_FLASH).
const char* emcy_class_name(EmcyClass c);
/// The name of a code table 21 defines to the digit (the 81xxh and 82xxh
/// ones: "CAN overrun", "PDO length error", ...), else its class's name
/// (MB2CO_FLASH).
const char* emcy_code_name(uint16_t code);
/// The name of one error register bit, given as its mask (01h generic ...
/// 80h manufacturer); nullptr for bit 6 (reserved) or not exactly one bit
/// (MB2CO_FLASH).
const char* error_register_bit_name(uint8_t bit);

}  // namespace canopen
}  // namespace mb2co
