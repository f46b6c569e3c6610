#include "eds_model.h"

#include <strings.h>

namespace mb2co {
namespace eds {

const std::vector<TypeInfo>& all_types() {
  static const std::vector<TypeInfo> types = {
      {DataType::kBoolean, "BOOLEAN", ValueKind::kBoolean, 1},
      {DataType::kInteger8, "INTEGER8", ValueKind::kSigned, 1},
      {DataType::kInteger16, "INTEGER16", ValueKind::kSigned, 2},
      {DataType::kInteger32, "INTEGER32", ValueKind::kSigned, 4},
      {DataType::kUnsigned8, "UNSIGNED8", ValueKind::kUnsigned, 1},
      {DataType::kUnsigned16, "UNSIGNED16", ValueKind::kUnsigned, 2},
      {DataType::kUnsigned32, "UNSIGNED32", ValueKind::kUnsigned, 4},
      {DataType::kReal32, "REAL32", ValueKind::kReal, 4},
      {DataType::kVisibleString, "VISIBLE_STRING", ValueKind::kVisibleString, 0},
      {DataType::kOctetString, "OCTET_STRING", ValueKind::kHexBytes, 0},
      {DataType::kUnicodeString, "UNICODE_STRING", ValueKind::kHexBytes, 0},
      {DataType::kTimeOfDay, "TIME_OF_DAY", ValueKind::kUnsigned, 6},
      {DataType::kTimeDifference, "TIME_DIFFERENCE", ValueKind::kUnsigned, 6},
      {DataType::kDomain, "DOMAIN", ValueKind::kHexBytes, 0},
      {DataType::kInteger24, "INTEGER24", ValueKind::kSigned, 3},
      {DataType::kReal64, "REAL64", ValueKind::kReal, 8},
      {DataType::kInteger40, "INTEGER40", ValueKind::kSigned, 5},
      {DataType::kInteger48, "INTEGER48", ValueKind::kSigned, 6},
      {DataType::kInteger56, "INTEGER56", ValueKind::kSigned, 7},
      {DataType::kInteger64, "INTEGER64", ValueKind::kSigned, 8},
      {DataType::kUnsigned24, "UNSIGNED24", ValueKind::kUnsigned, 3},
      {DataType::kUnsigned40, "UNSIGNED40", ValueKind::kUnsigned, 5},
      {DataType::kUnsigned48, "UNSIGNED48", ValueKind::kUnsigned, 6},
      {DataType::kUnsigned56, "UNSIGNED56", ValueKind::kUnsigned, 7},
      {DataType::kUnsigned64, "UNSIGNED64", ValueKind::kUnsigned, 8},
  };
  return types;
}

const TypeInfo* type_info(uint16_t data_type) {
  for (const TypeInfo& t : all_types()) {
    if (static_cast<uint16_t>(t.type) == data_type) return &t;
  }
  return nullptr;
}

const char* access_name(AccessType a) {
  switch (a) {
    case AccessType::kRo:
      return "ro";
    case AccessType::kWo:
      return "wo";
    case AccessType::kRw:
      return "rw";
    case AccessType::kRwr:
      return "rwr";
    case AccessType::kRww:
      return "rww";
    case AccessType::kConst:
      return "const";
  }
  return "?";
}

bool SubObject::operator==(const SubObject& o) const {
  return sub == o.sub && name == o.name && type == o.type && access == o.access &&
         pdo_mapping == o.pdo_mapping && default_value == o.default_value &&
         parameter_value == o.parameter_value && low_limit == o.low_limit && high_limit == o.high_limit &&
         denotation == o.denotation;
}

const SubObject* Object::find(uint8_t sub) const {
  for (const SubObject& s : subs) {
    if (s.sub == sub) return &s;
  }
  return nullptr;
}

bool Object::operator==(const Object& o) const {
  return index == o.index && name == o.name && type == o.type && obj_flags == o.obj_flags && subs == o.subs;
}

const Object* DeviceDescription::find(uint16_t index) const {
  const auto it = objects.find(index);
  return it == objects.end() ? nullptr : &it->second;
}

const SubObject* DeviceDescription::find(uint16_t index, uint8_t sub) const {
  const Object* o = find(index);
  return o == nullptr ? nullptr : o->find(sub);
}

bool DeviceDescription::operator==(const DeviceDescription& o) const {
  return file_info == o.file_info && device_info == o.device_info &&
         mandatory_objects == o.mandatory_objects && optional_objects == o.optional_objects &&
         manufacturer_objects == o.manufacturer_objects && objects == o.objects &&
         commissioning == o.commissioning && other_sections == o.other_sections;
}

const std::string* find_key(const KeyValues& kv, const std::string& key) {
  for (const auto& e : kv) {
    if (strcasecmp(e.first.c_str(), key.c_str()) == 0) return &e.second;
  }
  return nullptr;
}

}  // namespace eds
}  // namespace mb2co
