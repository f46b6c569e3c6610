#include "canopen/master/emcy_names.h"

#include "platform/flash.h"

namespace mb2co {
namespace canopen {

EmcyClass emcy_class(uint16_t code) {
  if (code == 0x0000) return kEmcyClassErrorReset;
  const uint8_t high = static_cast<uint8_t>(code >> 8);
  switch (high >> 4) {
    case 0x1:
      return high == 0x10 ? kEmcyClassGeneric : kEmcyClassUnknown;
    case 0x2:
      return kEmcyClassCurrent;
    case 0x3:
      return kEmcyClassVoltage;
    case 0x4:
      return kEmcyClassTemperature;
    case 0x5:
      return high == 0x50 ? kEmcyClassDeviceHardware : kEmcyClassUnknown;
    case 0x6:
      return kEmcyClassDeviceSoftware;
    case 0x7:
      return high == 0x70 ? kEmcyClassAdditionalModules : kEmcyClassUnknown;
    case 0x8:
      if (high == 0x81) return kEmcyClassCommunication;
      if (high == 0x82) return kEmcyClassProtocol;
      return kEmcyClassMonitoring;
    case 0x9:
      return high == 0x90 ? kEmcyClassExternal : kEmcyClassUnknown;
    case 0xF:
      if (high == 0xF0) return kEmcyClassAdditionalFunctions;
      if (high == 0xFF) return kEmcyClassDeviceSpecific;
      return kEmcyClassUnknown;
    default:
      return kEmcyClassUnknown;
  }
}

static const char kReset[] MB2CO_FLASH = "error reset";
static const char kGeneric[] MB2CO_FLASH = "generic";
static const char kCurrent[] MB2CO_FLASH = "current";
static const char kVoltage[] MB2CO_FLASH = "voltage";
static const char kTemperature[] MB2CO_FLASH = "temperature";
static const char kHardware[] MB2CO_FLASH = "device hardware";
static const char kSoftware[] MB2CO_FLASH = "device software";
static const char kModules[] MB2CO_FLASH = "additional modules";
static const char kMonitoring[] MB2CO_FLASH = "monitoring";
static const char kCommunication[] MB2CO_FLASH = "communication";
static const char kProtocol[] MB2CO_FLASH = "protocol error";
static const char kExternal[] MB2CO_FLASH = "external";
static const char kFunctions[] MB2CO_FLASH = "additional functions";
static const char kDeviceSpecific[] MB2CO_FLASH = "device specific";
static const char kUnknown[] MB2CO_FLASH = "unknown";

// In EmcyClass order (a table of pointers: in flash too on the AVR).
static const char* const kClassNames[] MB2CO_FLASH = {
    kReset,      kGeneric,       kCurrent,  kVoltage,  kTemperature, kHardware,       kSoftware, kModules,
    kMonitoring, kCommunication, kProtocol, kExternal, kFunctions,   kDeviceSpecific, kUnknown,
};

const char* emcy_class_name(EmcyClass c) {
  if (c > kEmcyClassUnknown) c = kEmcyClassUnknown;
  return flash_read(&kClassNames[c]);
}

static const char k8110[] MB2CO_FLASH = "CAN overrun";
static const char k8120[] MB2CO_FLASH = "CAN in error passive mode";
static const char k8130[] MB2CO_FLASH = "life guard or heartbeat error";
static const char k8140[] MB2CO_FLASH = "recovered from bus-off";
static const char k8150[] MB2CO_FLASH = "CAN-ID collision";
static const char k8210[] MB2CO_FLASH = "PDO length error";
static const char k8220[] MB2CO_FLASH = "PDO length exceeded";
static const char k8230[] MB2CO_FLASH = "DAM MPDO not processed";
static const char k8240[] MB2CO_FLASH = "unexpected SYNC data length";
static const char k8250[] MB2CO_FLASH = "RPDO timeout";

struct NamedCode {
  uint16_t code;
  const char* name;
};
static const NamedCode kCodeNames[] MB2CO_FLASH = {
    {0x8110, k8110}, {0x8120, k8120}, {0x8130, k8130}, {0x8140, k8140}, {0x8150, k8150},
    {0x8210, k8210}, {0x8220, k8220}, {0x8230, k8230}, {0x8240, k8240}, {0x8250, k8250},
};

const char* emcy_code_name(uint16_t code) {
  for (const NamedCode& n : kCodeNames) {
    const NamedCode entry = flash_read(&n);
    if (entry.code == code) return entry.name;
  }
  return emcy_class_name(emcy_class(code));
}

static const char kBitDeviceProfile[] MB2CO_FLASH = "device profile specific";
static const char kBitManufacturer[] MB2CO_FLASH = "manufacturer specific";

// Bits 0..7 of 1001h; bit 6 is reserved.
static const char* const kBitNames[] MB2CO_FLASH = {
    kGeneric, kCurrent, kVoltage, kTemperature, kCommunication, kBitDeviceProfile, nullptr, kBitManufacturer,
};

const char* error_register_bit_name(uint8_t bit) {
  for (uint8_t i = 0; i < 8; ++i) {
    if (bit == (1u << i)) return flash_read(&kBitNames[i]);
  }
  return nullptr;
}

}  // namespace canopen
}  // namespace mb2co
