// The model of a CiA 306 EDS/DCF file: what a device description says about
// a node's Object Dictionary, independent of the text it was read from.
// Host-only (C++17, std::), for the master side and the PC tools.
//
// Invariants a model from parse() keeps (and write_eds()/write_dcf() expect):
// objects are keyed by index; an object's subs are sorted by sub-index with
// no duplicates; a VAR, DOMAIN or DEFTYPE object has exactly one sub, sub 0,
// which holds its data type, access and values; CompactSubObj arrays are
// expanded into their sub-objects (the model never says "compact").
#pragma once
#include <stdint.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mb2co {
namespace eds {

/// CiA 301 object codes (EDS "ObjectType").
enum class ObjectType : uint8_t {
  kDomain = 0x2,
  kDefType = 0x5,
  kDefStruct = 0x6,
  kVar = 0x7,
  kArray = 0x8,
  kRecord = 0x9,
};

/// CiA 301 basic data types (EDS "DataType", the index of the type's entry).
enum class DataType : uint16_t {
  kBoolean = 0x01,
  kInteger8 = 0x02,
  kInteger16 = 0x03,
  kInteger32 = 0x04,
  kUnsigned8 = 0x05,
  kUnsigned16 = 0x06,
  kUnsigned32 = 0x07,
  kReal32 = 0x08,
  kVisibleString = 0x09,
  kOctetString = 0x0A,
  kUnicodeString = 0x0B,
  kTimeOfDay = 0x0C,       ///< 48 bits (ms after midnight, days since 1984), as an integer here
  kTimeDifference = 0x0D,  ///< 48 bits, as TIME_OF_DAY
  kDomain = 0x0F,
  kInteger24 = 0x10,
  kReal64 = 0x11,
  kInteger40 = 0x12,
  kInteger48 = 0x13,
  kInteger56 = 0x14,
  kInteger64 = 0x15,
  kUnsigned24 = 0x16,
  kUnsigned40 = 0x18,
  kUnsigned48 = 0x19,
  kUnsigned56 = 0x1A,
  kUnsigned64 = 0x1B,
};

/// How a value of a data type is written in a file and held in bytes.
enum class ValueKind : uint8_t { kBoolean, kSigned, kUnsigned, kReal, kVisibleString, kHexBytes };

struct TypeInfo {
  DataType type;
  const char* name;  ///< CiA 301 name, e.g. "UNSIGNED32"
  ValueKind kind;
  uint8_t bytes;  ///< value size in bytes; 0: variable (strings, DOMAIN)
};

/// The basic type with this DataType number, or nullptr when it is none.
const TypeInfo* type_info(uint16_t data_type);
inline const TypeInfo& type_info(DataType t) {
  return *type_info(static_cast<uint16_t>(t));
}
/// Every basic type, in DataType order (for tests and tools).
const std::vector<TypeInfo>& all_types();

/// EDS "AccessType": rwr/rww are rw entries meant for TPDO/RPDO mapping.
enum class AccessType : uint8_t { kRo, kWo, kRw, kRwr, kRww, kConst };
/// The file spelling ("ro", ..., "const").
const char* access_name(AccessType a);

/// A value as the bus carries it: little-endian, `bytes` of the type's size
/// (strings and DOMAIN: their bytes, no terminator).
/// node_id_relative: the file said `$NODEID+base`; `bytes` hold the base and
/// the value on a node is base + node id (resolve it with eds::resolve()).
struct Value {
  std::vector<uint8_t> bytes;
  bool node_id_relative = false;
  bool operator==(const Value& o) const { return bytes == o.bytes && node_id_relative == o.node_id_relative; }
  bool operator!=(const Value& o) const { return !(*this == o); }
};

/// One sub-index of an object (for a VAR: the object itself, sub 0).
struct SubObject {
  uint8_t sub = 0;
  std::string name;  ///< ParameterName
  DataType type = DataType::kUnsigned8;
  AccessType access = AccessType::kRo;
  bool pdo_mapping = false;
  std::optional<Value> default_value;    ///< DefaultValue (absent: the file gave none)
  std::optional<Value> parameter_value;  ///< ParameterValue: the configured value of a DCF
  std::optional<Value> low_limit;
  std::optional<Value> high_limit;
  std::string denotation;  ///< DCF Denotation (empty: none)
  bool operator==(const SubObject& o) const;
  bool operator!=(const SubObject& o) const { return !(*this == o); }
};

struct Object {
  uint16_t index = 0;
  std::string name;  ///< ParameterName
  ObjectType type = ObjectType::kVar;
  std::optional<uint32_t> obj_flags;  ///< ObjFlags (bit 0: no read on scan, bit 1: no write on download)
  std::vector<SubObject> subs;        ///< sorted by sub; VAR/DOMAIN/DEFTYPE: just sub 0
  const SubObject* find(uint8_t sub) const;
  bool operator==(const Object& o) const;
  bool operator!=(const Object& o) const { return !(*this == o); }
};

/// Key/value lines of a section in file order (keys as spelled in the file).
using KeyValues = std::vector<std::pair<std::string, std::string>>;

/// A section the model does not interpret ([Comments], [DummyUsage], ...),
/// kept so that a file written back says the same.
struct OtherSection {
  std::string name;
  KeyValues entries;
  bool operator==(const OtherSection& o) const { return name == o.name && entries == o.entries; }
};

/// [DeviceComissioning] (CiA 306 spelling) of a DCF.
struct Commissioning {
  std::optional<uint8_t> node_id;         ///< NodeID, 1..127
  std::optional<uint16_t> baudrate_kbit;  ///< Baudrate in kbit/s
  KeyValues others;                       ///< NodeName, NetNumber, ... as written
  bool operator==(const Commissioning& o) const {
    return node_id == o.node_id && baudrate_kbit == o.baudrate_kbit && others == o.others;
  }
};

struct DeviceDescription {
  KeyValues file_info;    ///< [FileInfo]
  KeyValues device_info;  ///< [DeviceInfo]
  std::vector<uint16_t> mandatory_objects;
  std::vector<uint16_t> optional_objects;
  std::vector<uint16_t> manufacturer_objects;
  std::map<uint16_t, Object> objects;
  std::optional<Commissioning> commissioning;  ///< present in a DCF
  std::vector<OtherSection> other_sections;

  const Object* find(uint16_t index) const;
  const SubObject* find(uint16_t index, uint8_t sub) const;
  bool operator==(const DeviceDescription& o) const;
  bool operator!=(const DeviceDescription& o) const { return !(*this == o); }
};

/// Case-insensitive lookup of a key in key/values (nullptr: absent).
const std::string* find_key(const KeyValues& kv, const std::string& key);

}  // namespace eds
}  // namespace mb2co
