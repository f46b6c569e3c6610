#include "eds_writer.h"

#include <cstdio>

#include "eds_value.h"

namespace mb2co {
namespace eds {

namespace {

std::string hex(uint32_t v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%0*X", digits, v);
  return buf;
}

void key_values(std::string& s, const std::string& section, const KeyValues& kv) {
  s += "[" + section + "]\n";
  for (const auto& e : kv) s += e.first + "=" + e.second + "\n";
  s += "\n";
}

void object_list(std::string& s, const char* section, const std::vector<uint16_t>& list) {
  s += std::string("[") + section + "]\nSupportedObjects=" + std::to_string(list.size()) + "\n";
  for (size_t i = 0; i < list.size(); ++i) s += std::to_string(i + 1) + "=0x" + hex(list[i], 4) + "\n";
  s += "\n";
}

void value_key(std::string& s, const char* key, DataType type, const std::optional<Value>& v) {
  if (v) s += std::string(key) + "=" + format_value(type, *v) + "\n";
}

/// The keys of a VAR-like description (a VAR object or one sub-object).
void var_fields(std::string& s, const SubObject& sub) {
  s += "DataType=0x" + hex(static_cast<uint16_t>(sub.type), 4) + "\n";
  s += std::string("AccessType=") + access_name(sub.access) + "\n";
  value_key(s, "DefaultValue", sub.type, sub.default_value);
  value_key(s, "ParameterValue", sub.type, sub.parameter_value);
  value_key(s, "LowLimit", sub.type, sub.low_limit);
  value_key(s, "HighLimit", sub.type, sub.high_limit);
  s += std::string("PDOMapping=") + (sub.pdo_mapping ? "1" : "0") + "\n";
  if (!sub.denotation.empty()) s += "Denotation=" + sub.denotation + "\n";
}

bool is_var_like(ObjectType t) {
  return t == ObjectType::kVar || t == ObjectType::kDomain || t == ObjectType::kDefType;
}

void object(std::string& s, const Object& o) {
  const std::string idx = hex(o.index, 4);
  s += "[" + idx + "]\nParameterName=" + o.name + "\n";
  s += "ObjectType=0x" + hex(static_cast<uint8_t>(o.type), 1) + "\n";
  if (o.obj_flags) s += "ObjFlags=0x" + hex(*o.obj_flags, 1) + "\n";
  if (is_var_like(o.type)) {
    if (!o.subs.empty()) var_fields(s, o.subs.front());
    s += "\n";
    return;
  }
  s += "SubNumber=" + std::to_string(o.subs.size()) + "\n\n";
  for (const SubObject& sub : o.subs) {
    s += "[" + idx + "sub" + hex(sub.sub, 1) + "]\nParameterName=" + sub.name + "\nObjectType=0x7\n";
    var_fields(s, sub);
    s += "\n";
  }
}

}  // namespace

std::string write_eds(const DeviceDescription& m) {
  std::string s;
  key_values(s, "FileInfo", m.file_info);
  key_values(s, "DeviceInfo", m.device_info);
  for (const OtherSection& o : m.other_sections) key_values(s, o.name, o.entries);
  object_list(s, "MandatoryObjects", m.mandatory_objects);
  if (!m.optional_objects.empty()) object_list(s, "OptionalObjects", m.optional_objects);
  if (!m.manufacturer_objects.empty()) object_list(s, "ManufacturerObjects", m.manufacturer_objects);
  for (const auto& o : m.objects) object(s, o.second);
  if (m.commissioning) {
    const Commissioning& c = *m.commissioning;
    s += "[DeviceComissioning]\n";
    if (c.node_id) s += "NodeID=" + std::to_string(*c.node_id) + "\n";
    if (c.baudrate_kbit) s += "Baudrate=" + std::to_string(*c.baudrate_kbit) + "\n";
    for (const auto& e : c.others) s += e.first + "=" + e.second + "\n";
  }
  return s;
}

DeviceDescription with_commissioning(DeviceDescription model, uint8_t node_id,
                                     std::optional<uint16_t> baudrate_kbit) {
  if (!model.commissioning) model.commissioning = Commissioning{};
  model.commissioning->node_id = node_id;
  if (baudrate_kbit) model.commissioning->baudrate_kbit = baudrate_kbit;
  return model;
}

std::string write_dcf(const DeviceDescription& model, uint8_t node_id,
                      std::optional<uint16_t> baudrate_kbit) {
  return write_eds(with_commissioning(model, node_id, baudrate_kbit));
}

}  // namespace eds
}  // namespace mb2co
