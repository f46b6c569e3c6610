#include "eds_reader.h"

#include <strings.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <set>
#include <sstream>

#include "eds_sections.h"
#include "eds_value.h"

namespace mb2co {
namespace eds {

namespace {

using detail::Entry;
using detail::Section;

bool ieq(const std::string& a, const char* b) {
  return strcasecmp(a.c_str(), b) == 0;
}

std::string hex4(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04X", v);
  return buf;
}

/// What an object-related section name says: [xxxx], [xxxxsubN], [xxxxName], ...
struct ObjectSectionName {
  enum Kind { kNone, kObject, kSub, kNames, kValues, kDenotations, kUnknown } kind = kNone;
  uint16_t index = 0;
  uint8_t sub = 0;
};

ObjectSectionName classify(const std::string& name) {
  ObjectSectionName r;
  if (name.size() < 4) return r;
  for (size_t i = 0; i < 4; ++i) {
    if (!isxdigit(static_cast<unsigned char>(name[i]))) return r;
  }
  r.index = static_cast<uint16_t>(std::stoul(name.substr(0, 4), nullptr, 16));
  const std::string rest = name.substr(4);
  if (rest.empty()) {
    r.kind = ObjectSectionName::kObject;
  } else if (rest.size() >= 4 && rest.size() <= 5 && strncasecmp(rest.c_str(), "sub", 3) == 0 &&
             isxdigit(static_cast<unsigned char>(rest[3])) &&
             (rest.size() == 4 || isxdigit(static_cast<unsigned char>(rest[4])))) {
    r.kind = ObjectSectionName::kSub;
    r.sub = static_cast<uint8_t>(std::stoul(rest.substr(3), nullptr, 16));
  } else if (ieq(rest, "Name")) {
    r.kind = ObjectSectionName::kNames;
  } else if (ieq(rest, "Value")) {
    r.kind = ObjectSectionName::kValues;
  } else if (ieq(rest, "Denotation")) {
    r.kind = ObjectSectionName::kDenotations;
  } else {
    r.kind = ObjectSectionName::kUnknown;
  }
  return r;
}

class Reader {
 public:
  Reader(const std::string& file, std::optional<uint8_t> node_id) : file_(file), node_id_(node_id) {}

  ParseResult run(std::string_view text) {
    ParseResult result;
    DeviceDescription m;
    if (node_id_ && (*node_id_ < 1 || *node_id_ > 127)) {
      fail(0, "node id " + std::to_string(*node_id_) + " is not 1..127");
    } else if (detail::split_sections(text, &sections_, &error_, &last_line_)) {
      read(&m);
    }
    if (error_.line < 0) {
      result.model = std::move(m);
    } else {
      result.error = ParseError{file_, error_.line, error_.what};
    }
    return result;
  }

 private:
  bool fail(int line, std::string what) {
    if (error_.line < 0) {
      error_.line = line;
      error_.what = std::move(what);
    }
    return false;
  }
  bool failed() const { return error_.line >= 0; }

  const Section* section(const char* name) const {
    for (const Section& s : sections_) {
      if (ieq(s.name, name)) return &s;
    }
    return nullptr;
  }

  bool read(DeviceDescription* m) {
    const Section* file_info = section("FileInfo");
    const Section* device_info = section("DeviceInfo");
    const Section* mandatory = section("MandatoryObjects");
    if (file_info == nullptr) return fail(last_line_, "missing section [FileInfo]");
    if (device_info == nullptr) return fail(last_line_, "missing section [DeviceInfo]");
    if (mandatory == nullptr) return fail(last_line_, "missing section [MandatoryObjects]");
    m->file_info = file_info->key_values();
    m->device_info = device_info->key_values();
    // Object sections first: the lists are checked against them.
    std::map<uint16_t, std::vector<const Section*>> subs;
    std::map<uint16_t, const Section*> mains, names, values, denotations;
    for (const Section& s : sections_) {
      const ObjectSectionName n = classify(s.name);
      switch (n.kind) {
        case ObjectSectionName::kNone:
          if (!is_known_section(s.name)) m->other_sections.push_back(OtherSection{s.name, s.key_values()});
          break;
        case ObjectSectionName::kObject:
          mains[n.index] = &s;
          break;
        case ObjectSectionName::kSub:
          subs[n.index].push_back(&s);
          break;
        case ObjectSectionName::kNames:
          names[n.index] = &s;
          break;
        case ObjectSectionName::kValues:
          values[n.index] = &s;
          break;
        case ObjectSectionName::kDenotations:
          denotations[n.index] = &s;
          break;
        case ObjectSectionName::kUnknown:
          return fail(s.line, "unknown section [" + s.name +
                                  "] (expected [xxxx], [xxxxsubN], [xxxxName], "
                                  "[xxxxValue] or [xxxxDenotation])");
      }
    }
    for (const auto& e : subs) {
      if (mains.count(e.first) == 0) {
        return fail(e.second.front()->line, "sub-object section [" + e.second.front()->name +
                                                "] without its object [" + hex4(e.first) + "]");
      }
    }
    for (const auto* table : {&names, &values, &denotations}) {
      for (const auto& e : *table) {
        if (mains.count(e.first) == 0) {
          return fail(e.second->line,
                      "section [" + e.second->name + "] without its object [" + hex4(e.first) + "]");
        }
      }
    }
    for (const auto& e : mains) {
      Object o;
      if (!read_object(e.first, *e.second, subs[e.first], names[e.first], values[e.first],
                       denotations[e.first], &o)) {
        return false;
      }
      m->objects[e.first] = std::move(o);
    }
    std::set<uint16_t> listed;
    if (!read_list(*mandatory, *m, &listed, &m->mandatory_objects)) return false;
    if (const Section* s = section("OptionalObjects")) {
      if (!read_list(*s, *m, &listed, &m->optional_objects)) return false;
    }
    if (const Section* s = section("ManufacturerObjects")) {
      if (!read_list(*s, *m, &listed, &m->manufacturer_objects)) return false;
    }
    for (const auto& e : mains) {
      if (e.first >= 0x1000 && listed.count(e.first) == 0) {
        return fail(e.second->line, "object [" + e.second->name +
                                        "] is in none of [MandatoryObjects], [OptionalObjects], "
                                        "[ManufacturerObjects]");
      }
    }
    const Section* comm = section("DeviceComissioning");  // CiA 306 spelling
    if (const Section* also = section("DeviceCommissioning")) {
      if (comm != nullptr) return fail(also->line, "[" + also->name + "] beside [" + comm->name + "]");
      comm = also;
    }
    if (comm != nullptr && !read_commissioning(*comm, m)) return false;
    return !failed();
  }

  static bool is_known_section(const std::string& name) {
    for (const char* k : {"FileInfo", "DeviceInfo", "MandatoryObjects", "OptionalObjects",
                          "ManufacturerObjects", "DeviceComissioning", "DeviceCommissioning"}) {
      if (ieq(name, k)) return true;
    }
    return false;
  }

  bool read_list(const Section& s, const DeviceDescription& m, std::set<uint16_t>* listed,
                 std::vector<uint16_t>* out) {
    const Entry* count_entry = s.find("SupportedObjects");
    if (count_entry == nullptr) return fail(s.line, "[" + s.name + "] without SupportedObjects");
    const std::optional<uint64_t> count = parse_unsigned(count_entry->value, 0xFFFF);
    if (!count) return fail(count_entry->line, "SupportedObjects is not a number of 0..65535");
    if (s.entries.size() != *count + 1) {
      return fail(count_entry->line, "SupportedObjects=" + std::to_string(*count) + " but [" + s.name +
                                         "] lists " + std::to_string(s.entries.size() - 1) + " objects");
    }
    // Entries by their number 1..count, found in one pass (a list may be long).
    std::vector<const Entry*> by_number(*count + 1, nullptr);
    for (const Entry& e : s.entries) {
      if (&e == count_entry) continue;
      const std::optional<uint64_t> k = parse_unsigned(e.key, *count);
      if (!k || *k == 0) {
        return fail(e.line, "'" + e.key + "' in [" + s.name + "] is not an entry number 1.." +
                                std::to_string(*count));
      }
      if (by_number[*k] != nullptr) return fail(e.line, "entry " + std::to_string(*k) + " appears twice");
      by_number[*k] = &e;
    }
    for (uint64_t k = 1; k <= *count; ++k) {
      const Entry* e = by_number[k];
      if (e == nullptr) return fail(s.line, "[" + s.name + "] has no entry " + std::to_string(k));
      const std::optional<uint64_t> index = parse_unsigned(e->value, 0xFFFF);
      if (!index) return fail(e->line, "'" + e->value + "' is not an object index (0..0xFFFF)");
      const auto idx = static_cast<uint16_t>(*index);
      if (m.objects.count(idx) == 0) {
        return fail(e->line, "object " + hex4(idx) + "h is listed but has no section [" + hex4(idx) + "]");
      }
      if (!listed->insert(idx).second) return fail(e->line, "object " + hex4(idx) + "h is listed twice");
      out->push_back(idx);
    }
    return true;
  }

  bool read_commissioning(const Section& s, DeviceDescription* m) {
    Commissioning c;
    for (const Entry& e : s.entries) {
      if (ieq(e.key, "NodeID")) {
        const std::optional<uint64_t> id = parse_unsigned(e.value, 127);
        if (!id || *id == 0) return fail(e.line, "NodeID '" + e.value + "' is not a node id 1..127");
        c.node_id = static_cast<uint8_t>(*id);
      } else if (ieq(e.key, "Baudrate")) {
        const std::optional<uint64_t> kbit = parse_unsigned(e.value, 1000);
        if (!kbit || (*kbit != 10 && *kbit != 20 && *kbit != 50 && *kbit != 125 && *kbit != 250 &&
                      *kbit != 500 && *kbit != 800 && *kbit != 1000)) {
          return fail(e.line, "Baudrate '" + e.value + "' is not a CiA 301 bit rate in kbit/s");
        }
        c.baudrate_kbit = static_cast<uint16_t>(*kbit);
      } else {
        c.others.emplace_back(e.key, e.value);
      }
    }
    m->commissioning = std::move(c);
    return true;
  }

  bool read_object(uint16_t index, const Section& s, std::vector<const Section*>& sub_sections,
                   const Section* names, const Section* values, const Section* denotations, Object* o) {
    o->index = index;
    const Entry* name = s.find("ParameterName");
    if (name == nullptr || name->value.empty()) return fail(s.line, "[" + s.name + "] without ParameterName");
    o->name = name->value;
    o->type = ObjectType::kVar;
    if (const Entry* t = s.find("ObjectType")) {
      const std::optional<uint64_t> v = parse_unsigned(t->value, 0xFF);
      if (!v || (*v != 2 && *v != 5 && *v != 6 && *v != 7 && *v != 8 && *v != 9)) {
        return fail(t->line, "unknown ObjectType '" + t->value + "' (0x2, 0x5-0x9)");
      }
      o->type = static_cast<ObjectType>(*v);
    }
    if (const Entry* f = s.find("ObjFlags")) {
      const std::optional<uint64_t> v = parse_unsigned(f->value, 0xFFFFFFFF);
      if (!v) return fail(f->line, "ObjFlags '" + f->value + "' is not an UNSIGNED32");
      o->obj_flags = static_cast<uint32_t>(*v);
    }
    const Entry* compact = s.find("CompactSubObj");
    uint64_t compact_count = 0;  // 0: not compact (CiA 306)
    if (compact != nullptr) {
      const std::optional<uint64_t> v = parse_unsigned(compact->value, 0xFE);
      if (!v) return fail(compact->line, "CompactSubObj '" + compact->value + "' is not 0..254");
      compact_count = *v;
      if (compact_count != 0 && o->type != ObjectType::kArray) {
        return fail(compact->line, std::string("CompactSubObj on a ") + object_type_name(o->type) +
                                       " object (only an ARRAY may be compact)");
      }
    }
    const Entry* sub_number = s.find("SubNumber");
    const bool var_like =
        o->type == ObjectType::kVar || o->type == ObjectType::kDomain || o->type == ObjectType::kDefType;
    if (compact_count == 0) {
      for (const Section* table : {names, values, denotations}) {
        if (table != nullptr) {
          return fail(table->line, "[" + table->name + "] belongs to a CompactSubObj array, but [" + s.name +
                                       "] is not one");
        }
      }
    }
    if (var_like) {
      if (sub_number != nullptr) {
        return fail(sub_number->line, std::string("SubNumber in a ") + object_type_name(o->type) + " object");
      }
      if (!sub_section_list_empty(sub_sections, *o)) return false;
      SubObject sub;
      sub.sub = 0;
      sub.name = o->name;
      if (!read_var_fields(s, o->type == ObjectType::kDomain, &sub)) return false;
      o->subs.push_back(std::move(sub));
      return true;
    }
    if (compact_count != 0) {
      if (sub_number != nullptr) {
        const std::optional<uint64_t> n = parse_unsigned(sub_number->value, 0xFF);
        if (!n || *n != 0)
          return fail(sub_number->line, "SubNumber beside CompactSubObj (the subs are implied)");
      }
      if (!sub_section_list_empty(sub_sections, *o)) return false;
      return expand_compact(s, static_cast<uint8_t>(compact_count), names, values, denotations, o);
    }
    if (sub_number == nullptr) return fail(s.line, "[" + s.name + "] without SubNumber or CompactSubObj");
    const std::optional<uint64_t> n = parse_unsigned(sub_number->value, 0xFF);
    if (!n) return fail(sub_number->line, "SubNumber '" + sub_number->value + "' is not 0..255");
    if (*n != sub_sections.size()) {
      return fail(sub_number->line, "SubNumber=" + std::to_string(*n) + " but there are " +
                                        std::to_string(sub_sections.size()) + " sections [" + s.name +
                                        "subN]");
    }
    for (const Section* ss : sub_sections) {
      SubObject sub;
      sub.sub = classify(ss->name).sub;
      if (o->find(sub.sub) != nullptr) {
        return fail(ss->line,
                    "sub-object " + hex4(index) + "h/" + std::to_string(sub.sub) + " is described twice");
      }
      const Entry* sub_name = ss->find("ParameterName");
      if (sub_name == nullptr || sub_name->value.empty()) {
        return fail(ss->line, "[" + ss->name + "] without ParameterName");
      }
      sub.name = sub_name->value;
      if (const Entry* t = ss->find("ObjectType")) {
        const std::optional<uint64_t> v = parse_unsigned(t->value, 0xFF);
        if (!v || *v != 7)
          return fail(t->line, "ObjectType '" + t->value + "' in a sub-object (only 0x7, VAR)");
      }
      if (!read_var_fields(*ss, false, &sub)) return false;
      o->subs.push_back(std::move(sub));
    }
    std::sort(o->subs.begin(), o->subs.end(),
              [](const SubObject& a, const SubObject& b) { return a.sub < b.sub; });
    return true;
  }

  bool sub_section_list_empty(const std::vector<const Section*>& sub_sections, const Object& o) {
    if (sub_sections.empty()) return true;
    return fail(sub_sections.front()->line,
                "sub-object section [" + sub_sections.front()->name + "] for " +
                    (o.type == ObjectType::kArray ? std::string("a CompactSubObj")
                                                  : std::string("a ") + object_type_name(o.type)) +
                    " object");
  }

  static const char* object_type_name(ObjectType t) {
    switch (t) {
      case ObjectType::kDomain:
        return "DOMAIN";
      case ObjectType::kDefType:
        return "DEFTYPE";
      case ObjectType::kDefStruct:
        return "DEFSTRUCT";
      case ObjectType::kVar:
        return "VAR";
      case ObjectType::kArray:
        return "ARRAY";
      case ObjectType::kRecord:
        return "RECORD";
    }
    return "?";
  }

  /// Sub-objects 0..count of a CompactSubObj array (CiA 306 compact storage).
  bool expand_compact(const Section& s, uint8_t count, const Section* names, const Section* values,
                      const Section* denotations, Object* o) {
    SubObject sub0;
    sub0.sub = 0;
    sub0.name = "NrOfObjects";
    sub0.type = DataType::kUnsigned8;
    sub0.access = AccessType::kRo;
    sub0.default_value = Value{{count}, false};
    o->subs.push_back(sub0);
    SubObject tmpl;
    if (!read_var_fields(s, false, &tmpl)) return false;
    for (unsigned k = 1; k <= count; ++k) {
      SubObject sub = tmpl;
      sub.sub = static_cast<uint8_t>(k);
      sub.name = o->name + std::to_string(k);
      o->subs.push_back(std::move(sub));
    }
    if (names != nullptr && !read_compact_table(*names, o, [&](SubObject* sub, const Entry& e) {
          if (e.value.empty()) return fail(e.line, "an empty name");
          sub->name = e.value;
          return true;
        })) {
      return false;
    }
    if (values != nullptr && !read_compact_table(*values, o, [&](SubObject* sub, const Entry& e) {
          return read_value(e, sub->type, &sub->parameter_value) &&
                 check_limits(e, *sub, sub->parameter_value);
        })) {
      return false;
    }
    if (denotations != nullptr && !read_compact_table(*denotations, o, [&](SubObject* sub, const Entry& e) {
          sub->denotation = e.value;
          return true;
        })) {
      return false;
    }
    return true;
  }

  /// [xxxxName]/[xxxxValue]/[xxxxDenotation]: NrOfEntries=n, then n lines sub=text.
  template <class Apply>
  bool read_compact_table(const Section& t, Object* o, Apply apply) {
    const Entry* n = t.find("NrOfEntries");
    if (n == nullptr) return fail(t.line, "[" + t.name + "] without NrOfEntries");
    const std::optional<uint64_t> count = parse_unsigned(n->value, 0xFE);
    if (!count || *count != t.entries.size() - 1) {
      return fail(n->line, "NrOfEntries='" + n->value + "' but [" + t.name + "] has " +
                               std::to_string(t.entries.size() - 1) + " entries");
    }
    for (const Entry& e : t.entries) {
      if (&e == n) continue;
      const std::optional<uint64_t> sub = parse_unsigned(e.key, 0xFF);
      if (!sub || *sub == 0 || *sub >= o->subs.size()) {
        return fail(e.line, "'" + e.key + "' is not a sub-index 1.." + std::to_string(o->subs.size() - 1) +
                                " of the compact array");
      }
      if (!apply(&o->subs[*sub], e)) return false;
    }
    return true;
  }

  bool read_value(const Entry& e, DataType type, std::optional<Value>* out) {
    const TypeInfo& t = type_info(type);
    const bool numeric = t.kind != ValueKind::kVisibleString && t.kind != ValueKind::kHexBytes;
    if (e.value.empty() && numeric) return true;  // no value given
    const ValueResult v = parse_value(type, e.value, node_id_);
    if (!v.value) return fail(e.line, e.key + ": " + v.error);
    *out = v.value;
    return true;
  }

  /// A value within LowLimit/HighLimit (when both are known numbers).
  bool check_limits(const Entry& e, const SubObject& sub, const std::optional<Value>& v) {
    if (!v) return true;
    if (sub.low_limit && compare_values(sub.type, *v, *sub.low_limit).value_or(0) < 0) {
      return fail(e.line, e.key + " below LowLimit");
    }
    if (sub.high_limit && compare_values(sub.type, *v, *sub.high_limit).value_or(0) > 0) {
      return fail(e.line, e.key + " above HighLimit");
    }
    return true;
  }

  /// DataType, AccessType, PDOMapping, values and limits of a VAR or a sub.
  bool read_var_fields(const Section& s, bool domain, SubObject* sub) {
    const Entry* type = s.find("DataType");
    if (type == nullptr) {
      if (!domain) return fail(s.line, "[" + s.name + "] without DataType");
      sub->type = DataType::kDomain;
    } else {
      const std::optional<uint64_t> v = parse_unsigned(type->value, 0xFFFF);
      if (!v) return fail(type->line, "DataType '" + type->value + "' is not a number");
      if (type_info(static_cast<uint16_t>(*v)) == nullptr) {
        return fail(type->line, "unknown DataType " + type->value + " (not a CiA 301 basic type)");
      }
      sub->type = static_cast<DataType>(*v);
    }
    const Entry* access = s.find("AccessType");
    if (access == nullptr) {
      if (!domain) return fail(s.line, "[" + s.name + "] without AccessType");
      sub->access = AccessType::kRw;
    } else {
      bool known = false;
      for (const AccessType a : {AccessType::kRo, AccessType::kWo, AccessType::kRw, AccessType::kRwr,
                                 AccessType::kRww, AccessType::kConst}) {
        if (ieq(access->value, access_name(a))) {
          sub->access = a;
          known = true;
        }
      }
      if (!known) return fail(access->line, "unknown AccessType '" + access->value + "'");
    }
    if (const Entry* pdo = s.find("PDOMapping")) {
      const std::optional<uint64_t> v = parse_unsigned(pdo->value, 1);
      if (!v) return fail(pdo->line, "PDOMapping '" + pdo->value + "' is not 0 or 1");
      sub->pdo_mapping = *v == 1;
    }
    const TypeInfo& t = type_info(sub->type);
    const bool numeric = t.kind != ValueKind::kVisibleString && t.kind != ValueKind::kHexBytes;
    for (const char* key : {"LowLimit", "HighLimit"}) {
      if (const Entry* e = s.find(key)) {
        if (!numeric && !e->value.empty())
          return fail(e->line, std::string(key) + " on a " + t.name + " entry");
        if (!read_value(*e, sub->type, key[0] == 'L' ? &sub->low_limit : &sub->high_limit)) return false;
      }
    }
    if (sub->low_limit && sub->high_limit &&
        compare_values(sub->type, *sub->low_limit, *sub->high_limit).value_or(0) > 0) {
      return fail(s.find("HighLimit")->line, "HighLimit below LowLimit");
    }
    if (const Entry* e = s.find("DefaultValue")) {
      if (!read_value(*e, sub->type, &sub->default_value) || !check_limits(*e, *sub, sub->default_value)) {
        return false;
      }
    }
    if (const Entry* e = s.find("ParameterValue")) {
      if (!read_value(*e, sub->type, &sub->parameter_value) ||
          !check_limits(*e, *sub, sub->parameter_value)) {
        return false;
      }
    }
    if (const Entry* e = s.find("Denotation")) sub->denotation = e->value;
    return true;
  }

  const std::string& file_;
  std::optional<uint8_t> node_id_;
  std::vector<Section> sections_;
  detail::LineError error_;
  int last_line_ = 0;
};

}  // namespace

ParseResult parse(std::string_view text, const std::string& filename, std::optional<uint8_t> node_id) {
  try {
    Reader r(filename, node_id);
    return r.run(text);
  } catch (const std::bad_alloc&) {
    ParseResult r;
    r.error = ParseError{filename, 0, "out of memory"};
    return r;
  }
}

ParseResult parse_file(const std::string& path, std::optional<uint8_t> node_id) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    ParseResult r;
    r.error = ParseError{path, 0, std::string("cannot open: ") + std::strerror(errno)};
    return r;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path, node_id);
}

}  // namespace eds
}  // namespace mb2co
