#include "od_export.h"

#include <cstdio>

#include "eds_value.h"
#include "gateway/gateway.h"

namespace mb2co {
namespace odtool {

using canopen::ObjectDictionary;
using canopen::OdEntry;

namespace {

std::string hex(uint64_t v, int digits) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%0*llX", digits, static_cast<unsigned long long>(v));
  return buf;
}

// The CiA 301 name of a basic type (the EDS library's table: one list of
// the types for the tools).
const char* type_name(uint8_t t) {
  const eds::TypeInfo* info = eds::type_info(t);
  return info != nullptr ? info->name : "?";
}

// Types beyond the first seven are printed in their own notation (CiA 306,
// eds::format_value: reals as decimals, signed integers in decimal, byte
// strings as hex dumps); the first seven keep the hex the docs always had.
bool own_notation(uint8_t t) {
  return t > canopen::kUnsigned32;
}

// `v`'s low bytes as a value of numeric type `t`, in the type's notation.
std::string numeric_text(uint8_t t, uint64_t v) {
  eds::Value value;
  const eds::TypeInfo* info = eds::type_info(t);
  for (uint8_t i = 0; info != nullptr && i < info->bytes; ++i)
    value.bytes.push_back(static_cast<uint8_t>(v >> (8 * i)));
  return eds::format_value(static_cast<eds::DataType>(t), value);
}

const char* access(const OdEntry& e) {
  if (e.attr & canopen::kAttrConst) return "const";
  const bool r = e.attr & canopen::kAttrRead;
  const bool w = e.attr & canopen::kAttrWrite;
  return r && w ? "rw" : w ? "wo" : "ro";
}

std::string default_text(const ObjectDictionary& od, uint16_t row, bool eds) {
  const OdEntry e = od.entry(row);
  const uint8_t type = e.data_type();
  if (e.attr & canopen::kAttrString) {
    const char* p = od.definition().strings + (e.def & 0xFFFF);
    if (type == canopen::kVisibleString) return eds ? std::string(p) : "\"" + std::string(p) + "\"";
    // The other byte runs: their whole capacity, a hex dump (the default
    // text padded with zeros, as the node holds it).
    eds::Value v;
    const uint16_t capacity = static_cast<uint16_t>(e.def >> 16);
    const size_t len = std::string(p).size();
    for (uint16_t i = 0; i < capacity; ++i) v.bytes.push_back(i < len ? static_cast<uint8_t>(p[i]) : 0);
    if (type == canopen::kUnicodeString) {  // its length: up to the first character 0
      while (v.bytes.size() >= 2 && v.bytes[v.bytes.size() - 1] == 0 && v.bytes[v.bytes.size() - 2] == 0) {
        v.bytes.resize(v.bytes.size() - 2);
      }
    }
    return eds::format_value(static_cast<eds::DataType>(type), v);
  }
  if (e.attr & canopen::kAttrNodeId) return "$NODEID+0x" + hex(e.def, 1);
  if (own_notation(type)) return numeric_text(type, e.def);
  return "0x" + hex(e.def, 1);
}

const char* name_of(const ObjectDictionary& od, uint16_t row) {
  return od.definition().names != nullptr ? od.definition().names[row] : "";
}

// Sub-index 0 names a record as "<record>: highest sub-index"; the part
// before the colon names the object.
std::string object_name(const ObjectDictionary& od, uint16_t row) {
  std::string n = name_of(od, row);
  const size_t colon = n.find(':');
  return colon == std::string::npos ? n : n.substr(0, colon);
}

// CiA 306 tools list a record's sub-indices under the record: each sub is
// named by itself, without the "<record>: " the OD's flat names carry, and
// sub-index 0 by CiA 301's name for it.
std::string sub_name(const ObjectDictionary& od, uint16_t row) {
  if (od.entry(row).sub == 0) return "Highest sub-index supported";
  const std::string n = name_of(od, row);
  const std::string prefix = object_name(od, row) + ": ";
  return n.compare(0, prefix.size(), prefix) == 0 ? n.substr(prefix.size()) : n;
}

std::string limit_text(uint8_t type, canopen::OdLimitValue v) {
  if (canopen::od_type_kind(type) == canopen::kKindReal) {  // stored as its ordered key
    return numeric_text(type, canopen::od_real_limit_bits(v, type == canopen::kReal32 ? 4 : 8));
  }
  return v < 0 ? std::to_string(v) : "0x" + hex(static_cast<uint64_t>(v), 1);
}

// LowLimit/HighLimit lines of a row that has limits beyond its data type.
std::string limit_lines(const ObjectDictionary& od, uint16_t row) {
  const OdEntry e = od.entry(row);
  const canopen::OdDefinition& d = od.definition();
  for (uint8_t i = 0; i < d.limit_count; ++i) {
    const canopen::OdLimit& l = d.limits[i];
    if (l.index == e.index && l.sub == e.sub)
      return "LowLimit=" + limit_text(e.data_type(), l.min) +
             "\nHighLimit=" + limit_text(e.data_type(), l.max) + "\n";
  }
  return "";
}

// The default of a constant entry, e.g. 1018h's numbers for [DeviceInfo].
std::string constant_of(const ObjectDictionary& od, uint16_t index, uint8_t sub) {
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const OdEntry e = od.entry(r);
    if (e.index == index && e.sub == sub) return "0x" + hex(e.def, 8);
  }
  return "0x00000000";
}

}  // namespace

std::string od_markdown(const ObjectDictionary& od, const std::string& title) {
  std::string s = "# " + title + "\n\n";
  s += "Generated by `build/pcapp/odtool/mb2co-od` from the node's own OD definition: do not edit.\n";
  s += "`$NODEID+x`: the default is x plus the node id. Access as seen over SDO.\n";
  s += "Saved: kept by 1010h \"save all parameters\" and loaded at every start; other\n"
       "entries start with their default (commands such as a RUN command, outputs and\n"
       "received values are never stored parameters).\n\n";
  s += "1010h/01 \"save\" is answered at once and runs over the node's loop passes (an\n"
       "EEPROM byte takes 3.3 ms on the Uno, a whole first save ~1.5 s; heartbeats, PDOs,\n"
       "SDO and Modbus go on meanwhile). 1010h/01 reads 0 while it runs and 1 when it is\n"
       "done: poll it. A \"save\" or \"load\" (1011h/01) meanwhile is refused with abort\n"
       "08000022h (the gateway's Modbus: exception 06, busy); a reset (NMT; on the gateway\n"
       "also 2001h) waits until the save is done. A save that fails keeps the previous\n"
       "set and raises EMCY 5530h with bit 0 of 1001h until a save succeeds.\n\n";
  s += "| index | sub | name | type | access | PDO | saved | default |\n";
  s += "|---|---|---|---|---|---|---|---|\n";
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const OdEntry e = od.entry(r);
    s += "| " + hex(e.index, 4) + "h | " + hex(e.sub, 2) + " | " + name_of(od, r) + " | " +
         type_name(e.data_type()) + " | " + access(e) + " | " + ((e.attr & canopen::kAttrPdo) ? "yes" : "") +
         " | " + (canopen::param_is_saved(od, r) ? "yes" : "") + " | " + default_text(od, r, false) + " |\n";
  }
  return s;
}

std::string od_eds(const ObjectDictionary& od, const std::string& product) {
  std::string s;
  s += "[FileInfo]\nFileName=" + product + ".eds\nFileVersion=1\nFileRevision=0\nEDSVersion=4.0\n";
  s += "Description=Generated by mb2co-od from the node's OD definition\nCreatedBy=mb2co\n\n";
  s += "[DeviceInfo]\nVendorName=mb2co\nVendorNumber=" + constant_of(od, 0x1018, 1) +
       "\nProductName=" + product + "\nProductNumber=" + constant_of(od, 0x1018, 2) +
       "\nRevisionNumber=" + constant_of(od, 0x1018, 3) + "\n";
  s += "BaudRate_10=0\nBaudRate_20=0\nBaudRate_50=0\nBaudRate_125=1\nBaudRate_250=1\n";
  s += "BaudRate_500=1\nBaudRate_800=0\nBaudRate_1000=1\nSimpleBootUpMaster=0\nSimpleBootUpSlave=1\n";
  s += "Granularity=1\nDynamicChannelsSupported=0\nCompactPDO=0\nGroupMessaging=0\n";
  s += "NrOfRXPDO=4\nNrOfTXPDO=4\nLSS_Supported=0\n\n";
  // CiA 306 has no key for the SDO services a device offers: said here.
  const bool gateway = product == "mb2co-gateway";
  s += "[Comments]\nLines=";
  s += gateway ? "3\n" : "1\n";
  s += "Line1=SDO: expedited and segmented; block transfer requests are answered with abort 05040001h.\n";
  if (gateway) {
    s += "Line2=mb2co-node (this firmware on Linux) also does block transfer (CRC) and serves\n";
    s += "Line3=1F50h/1 program data, a DOMAIN of up to 1 MiB in RAM, outside this file.\n";
  }
  s += "\n";
  std::string mandatory, optional, manufacturer;
  int n_mand = 0, n_opt = 0, n_man = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const OdEntry e = od.entry(r);
    // Every object is in a list; the data-type definitions (below 1000h)
    // are optional objects like the communication ones.
    if (e.sub != 0) continue;
    const std::string line = "=0x" + hex(e.index, 4) + "\n";
    if (e.index == 0x1000 || e.index == 0x1001 || e.index == 0x1018) {
      mandatory += std::to_string(++n_mand) + line;
    } else if (e.index >= 0x2000 && e.index < 0x6000) {
      manufacturer += std::to_string(++n_man) + line;
    } else {
      optional += std::to_string(++n_opt) + line;
    }
  }
  s += "[MandatoryObjects]\nSupportedObjects=" + std::to_string(n_mand) + "\n" + mandatory + "\n";
  s += "[OptionalObjects]\nSupportedObjects=" + std::to_string(n_opt) + "\n" + optional + "\n";
  s += "[ManufacturerObjects]\nSupportedObjects=" + std::to_string(n_man) + "\n" + manufacturer + "\n";
  for (uint16_t r = 0; r < od.row_count();) {
    const OdEntry first = od.entry(r);
    uint16_t end = r;
    while (end < od.row_count() && od.entry(end).index == first.index) ++end;
    const bool var = end - r == 1 && first.sub == 0;
    const std::string idx = hex(first.index, 4);
    auto entry = [&](uint16_t row, const std::string& section, const std::string& name) {
      const OdEntry e = od.entry(row);
      s += "[";
      s += section;
      s += "]\nParameterName=";
      s += name;
      s += "\nObjectType=0x7\n";
      s += "DataType=0x" + hex(e.data_type(), 4) + "\nAccessType=" + access(e) + "\n";
      s += "DefaultValue=" + default_text(od, row, true) + "\n" + limit_lines(od, row);
      s += std::string("PDOMapping=") + ((e.attr & canopen::kAttrPdo) ? "1" : "0") + "\n\n";
    };
    if (var) {
      entry(r, idx, name_of(od, r));
    } else {
      s += "[" + idx + "]\nParameterName=" + object_name(od, r) + "\nObjectType=0x9\n";
      s += "SubNumber=" + std::to_string(end - r) + "\n\n";
      for (uint16_t k = r; k < end; ++k) entry(k, idx + "sub" + hex(od.entry(k).sub, 1), sub_name(od, k));
    }
    r = end;
  }
  return s;
}

std::string register_map_markdown(const ObjectDictionary& od) {
  std::string s = "# Modbus register map of the gateway\n\n";
  s += "Generated by `build/pcapp/odtool/mb2co-od --node gateway --format registers` from the\n"
       "default maps in the gateway's OD (2400h–2403h): do not edit. The maps are OD entries\n"
       "themselves (PDO mapping format: index, sub-index, length in bits), readable and\n"
       "writable by SDO; this table shows the defaults.\n\n"
       "Addresses are PDU addresses (0-based; mbpoll needs `-0`, most PLC tools add 1).\n"
       "An entry takes one register per 16 bits, high word first: up to 16 bits one register,\n"
       "24 and 32 bits two, 40 and 48 bits three, 56 and 64 bits four (a 24-, 40- or 56-bit\n"
       "value is right-aligned: the padding byte at the top reads 0 and must be written 0).\n"
       "REAL32 is two registers holding its IEEE 754 bits, REAL64 four, in the same order:\n"
       "-1234.5625 (C49A5200h) reads C49Ah 5200h. A VISIBLE_STRING or OCTET_STRING of n\n"
       "characters is a run of (n + 1) / 2 registers, two characters each, the first in the\n"
       "high byte (a VISIBLE_STRING ends at its first 0). An entry of several registers is\n"
       "written only whole (all its registers in one FC 10h/17h request), and a request\n"
       "is checked whole before any of it is stored. On the Arduino Uno only entries of up\n"
       "to 32 bits can be mapped; the Linux build (mb2co-node) maps them all, and its default\n"
       "map holds the process values of 2500h (REAL32 and UNSIGNED64), which the Uno's OD\n"
       "does not have.\n"
       "Coils and discrete inputs are bit 0 of an 8-bit entry.\n\n"
       "Exceptions: 01 unknown function; 03 bad quantity or malformed request; 02 an address\n"
       "that is unmapped, beyond the map, or not writable (read-only OD entry, part of a\n"
       "value of several registers); 04 a value the OD refuses (out of the entry's limits, refused by the\n"
       "owning service). A write of several registers or coils is checked whole before any\n"
       "of it is carried out: a refused one changes nothing (no value, no save, no reset, no\n"
       "acknowledged stop). 06 busy: not in the present state, try again (SDO abort\n"
       "08000022h), e.g. HR 11-12 (1010h/01 \"save\") written while a save runs.\n\n"
       "A save (HR 11-12 = 6576h 6173h) is answered at once, not when it is done: on the Uno\n"
       "it programs up to a whole slot of EEPROM at 3.3 ms a byte (~1.5 s), longer than\n"
       "masters wait for an answer (libmodbus 0.5 s, mbpoll 1 s), and it runs over the\n"
       "loop's passes, so heartbeats, PDOs and Modbus go on meanwhile. Poll HR 11-12: they\n"
       "read 0 0 while the save runs, 0 1 when it is done; a further save meanwhile gets\n"
       "exception 06 and a restart (HR 13) waits until it is done. A failed save keeps\n"
       "the previous set and sets bit 0 of the error register (IR 19, EMCY 5530h) until\n"
       "a save succeeds.\n\n"
       "The RUN command (2100h/01) is a command, not a parameter: 1010h \"save\" does not keep\n"
       "it, and a station always starts stopped. The Modbus watchdog (2000h/09, ms; 0 off)\n"
       "runs from power-on: with no request for that long the station latches a stop (stop\n"
       "cause 4). A latched stop holds until the PC writes RUN command 0; RUN 1 then runs.\n"
       "docs/od-gateway.md shows which entries are saved.\n\n"
       "Neighbours (2110h previous, 2120h next station): the status register (2110h/03,\n"
       "2120h/03) is 0 unknown (no heartbeat, or lost), 1 alive, 2 none (end of a chain), plus\n"
       "80h while no TPDO1 of that station has arrived since this gateway's reset. With 80h set\n"
       "its RUN state and STOP2 counter read 0 as placeholders, not values it sent: take the\n"
       "neighbour as unknown and count no STOP2 events from that counter (compare the next\n"
       "value without 80h with the last one without it). The flag goes with the first TPDO1\n"
       "and does not come back when the heartbeat is lost later (the values are then the last\n"
       "it sent; status 0 says they may be stale).\n\n"
       "Saved parameters found damaged (2003h): the resets since power-on that found a saved\n"
       "set damaged (CRC, or a value beyond its limits) and fell back to the older set or to\n"
       "the defaults. Each such reset also sends EMCY 5530h after the boot-up and sets bit 0\n"
       "of the error register (1001h) until a save succeeds. A blank EEPROM (never saved, all\n"
       "FFh, or invalidated by 1011h) is no damage. The count never goes down; it starts at 0\n"
       "at power-on.\n\n";
  s += "On the Arduino Uno the Modbus frame buffer holds " + std::to_string(mb2co::gateway::kMapFrameBytes) +
       " bytes, not the protocol's 256: enough for\n"
       "every request the maps can cover and its answer, even with every map entry 32 bits\n"
       "wide. The Uno counts a longer request as a character overrun (FC 08 sub-function 12h)\n"
       "and does not answer it, where the Linux build answers: exception 02 or 03 (no map\n"
       "covers that many addresses), or the echo of an FC 08/00 with more than " +
       std::to_string(mb2co::gateway::kMapFrameBytes - 6) +
       " data bytes\n"
       "(docs/performance.md).\n\n"
       "## The rest of the CAN network (FC 2Bh / MEI 0Dh)\n\n"
       "Beyond these registers, FC 2Bh with MEI type 0Dh (CANopen General Reference) reads\n"
       "and writes any object of any node on the CAN bus by SDO, sends NMT commands to one\n"
       "node or all, and lists the NMT state and heartbeat age of every node the gateway\n"
       "hears. It answers when the CAN transfer is done (a master waits up to 1 s); 2000h/10 = 0\n"
       "turns it off (exception 01). Layout, rules and examples: docs/gateway-network.md.\n";
  static const struct {
    uint16_t index;
    const char* title;
    bool registers;
  } tables[] = {{0x2400, "Holding registers (FC 03, 06, 10h, 17h)", true},
                {0x2401, "Input registers (FC 04)", true},
                {0x2402, "Coils (FC 01, 05, 0Fh)", false},
                {0x2403, "Discrete inputs (FC 02)", false}};
  for (const auto& t : tables) {
    s += std::string("\n## ") + t.title +
         "\n\n| address | OD entry | bits | type | access | meaning |\n|---|---|---|---|---|---|\n";
    const uint16_t row0 = od.find(t.index, 0);
    const uint32_t count = od.get(row0);
    uint32_t at = 0;
    for (uint32_t k = 1; k <= count; ++k) {
      const uint32_t entry = od.get(static_cast<uint16_t>(row0 + k));
      const uint16_t index = static_cast<uint16_t>(entry >> 16);
      const uint8_t sub = static_cast<uint8_t>(entry >> 8);
      const uint8_t bits = static_cast<uint8_t>(entry);
      // One register per 16 bits (OdRegisterBank).
      const uint32_t width = (t.registers && entry != 0 && bits > 16) ? (bits + 15u) / 16u : 1;
      const std::string addr =
          width >= 2 ? std::to_string(at) + "-" + std::to_string(at + width - 1) : std::to_string(at);
      if (entry == 0) {
        s += "| " + addr + " | - | - | - | - | unmapped |\n";
      } else {
        const uint16_t row = od.find(index, sub);
        const OdEntry e = od.entry(row);
        const bool writable = (e.attr & canopen::kAttrWrite) != 0;
        s += "| " + addr + " | " + hex(index, 4) + "h/" + hex(sub, 2) + " | " + std::to_string(bits) + " | " +
             type_name(e.data_type()) + " | " + (writable ? "rw" : "ro") + " | " + name_of(od, row) + " |\n";
      }
      at += width;
    }
  }
  return s;
}

}  // namespace odtool
}  // namespace mb2co
