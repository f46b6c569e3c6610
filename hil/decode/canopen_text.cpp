#include "canopen_text.h"

#include <cstdio>

namespace mb2co {
namespace hil {

namespace {
std::string fmt(const char* format, unsigned a = 0, unsigned b = 0, unsigned c = 0, unsigned d = 0) {
  char buf[128];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

unsigned le16(const CanFrame& f, int at) {
  return f.data[at] | (f.data[at + 1] << 8);
}
unsigned le32(const CanFrame& f, int at) {
  return le16(f, at) | (static_cast<unsigned>(le16(f, at + 2)) << 16);
}

const char* nmt_state(unsigned s) {
  switch (s & 0x7F) {
    case 0x00:
      return "boot-up";
    case 0x04:
      return "stopped";
    case 0x05:
      return "operational";
    case 0x7F:
      return "pre-operational";
    default:
      return "invalid state";
  }
}

std::string object(const CanFrame& f) {
  return fmt("%04Xh/%02X", le16(f, 1), f.data[3]);
}

std::string expedited_value(const CanFrame& f) {
  const unsigned n = (f.data[0] & 0x01) ? 4 - ((f.data[0] >> 2) & 3) : 4;
  unsigned v = 0;
  for (unsigned i = 0; i < n; ++i) v |= static_cast<unsigned>(f.data[4 + i]) << (8 * i);
  return n == 1 ? fmt("%02Xh", v) : n == 2 ? fmt("%04Xh", v) : fmt("%08Xh", v);
}

std::string sdo(const CanFrame& f, bool request, unsigned node) {
  const char* who = request ? "SDO request node %u: " : "SDO response node %u: ";
  std::string s = fmt(who, node);
  if (f.dlc != 8) return s + "invalid length";
  const unsigned cs = f.data[0] >> 5;
  if (cs == 4) return s + "abort " + object(f) + fmt(" code %08Xh", le32(f, 4));
  if (request) {
    switch (cs) {
      case 1:
        if (f.data[0] & 0x02) return s + "download " + object(f) + " = " + expedited_value(f);
        return s + "initiate segmented download " + object(f) +
               ((f.data[0] & 1) ? fmt(" (%u bytes)", le32(f, 4)) : "");
      case 0:
        return s + fmt("download segment toggle %u", (f.data[0] >> 4) & 1) +
               ((f.data[0] & 1) ? ", last" : "");
      case 2:
        return s + "upload " + object(f);
      case 3:
        return s + fmt("upload segment request toggle %u", (f.data[0] >> 4) & 1);
      default:
        return s + fmt("command specifier %u", cs);
    }
  }
  switch (cs) {
    case 3:
      return s + "download done " + object(f);
    case 1:
      return s + fmt("segment acknowledged toggle %u", (f.data[0] >> 4) & 1);
    case 2:
      if (f.data[0] & 0x02) return s + "upload " + object(f) + " = " + expedited_value(f);
      return s + "segmented upload " + object(f) + fmt(" (%u bytes)", le32(f, 4));
    case 0: {
      std::string text;
      const unsigned n = 7 - ((f.data[0] >> 1) & 7);
      for (unsigned i = 0; i < n; ++i) {
        const char c = static_cast<char>(f.data[1 + i]);
        text += (c >= 32 && c < 127) ? c : '.';
      }
      return s + fmt("segment toggle %u", (f.data[0] >> 4) & 1) + " \"" + text + "\"" +
             ((f.data[0] & 1) ? ", last" : "");
    }
    default:
      return s + fmt("command specifier %u", cs);
  }
}
}  // namespace

std::string frame_bytes(const CanFrame& f) {
  std::string s = fmt("<%03X>", f.id);
  if (f.rtr()) return s + fmt(" RTR dlc %u", f.dlc);
  for (unsigned i = 0; i < f.dlc; ++i) s += fmt(" %02X", f.data[i]);
  return s;
}

std::string describe(const CanFrame& f) {
  const unsigned id = f.id;
  const unsigned node = id & 0x7F;
  const unsigned fn = id & 0x780;
  if (f.extended()) return "extended frame (not CANopen)";
  if (id == 0) {
    if (f.dlc != 2) return "NMT (invalid length)";
    const char* cmd = f.data[0] == 0x01   ? "start"
                      : f.data[0] == 0x02 ? "stop"
                      : f.data[0] == 0x80 ? "enter pre-operational"
                      : f.data[0] == 0x81 ? "reset node"
                      : f.data[0] == 0x82 ? "reset communication"
                                          : "unknown command";
    return f.data[1] == 0 ? std::string("NMT ") + cmd + " all nodes"
                          : std::string("NMT ") + cmd + fmt(" node %u", f.data[1]);
  }
  if (id == 0x80) return f.dlc ? fmt("SYNC counter %u", f.data[0]) : "SYNC";
  if (fn == 0x80) {
    if (f.dlc != 8) return fmt("EMCY node %u (invalid length)", node);
    const unsigned code = le16(f, 0);
    return code == 0 ? fmt("EMCY node %u: error reset, register %02Xh", node, f.data[2])
                     : fmt("EMCY node %u: code %04Xh, register %02Xh", node, code, f.data[2]);
  }
  if (fn == 0x580) return sdo(f, false, node);
  if (fn == 0x600) return sdo(f, true, node);
  if (fn == 0x700) {
    if (f.rtr()) return fmt("node guarding request node %u", node);
    if (f.dlc != 1) return fmt("error control node %u (invalid length)", node);
    if (f.data[0] == 0) return fmt("boot-up node %u", node);
    return fmt("heartbeat node %u: ", node) + nmt_state(f.data[0]) + ((f.data[0] & 0x80) ? " (toggle)" : "");
  }
  static const char* const pdo[] = {nullptr, nullptr, nullptr, "TPDO1", "RPDO1", "TPDO2",
                                    "RPDO2", "TPDO3", "RPDO3", "TPDO4", "RPDO4"};
  const unsigned slot = id >> 7;
  if (slot >= 3 && slot <= 10)
    return std::string(pdo[slot]) + fmt(" node %u", node) + (f.rtr() ? " (remote request)" : "");
  return "unknown";
}

}  // namespace hil
}  // namespace mb2co
