// CAN frames as a pcap file of link type LINKTYPE_CAN_SOCKETCAN (227), the
// form Wireshark and tcpdump open as CAN: a 24-byte file header, then per
// frame a 16-byte record header and the 16-byte SocketCAN frame (can_id
// big-endian with the flags of linux/can.h, len, three zero bytes, eight data
// bytes, zero beyond len). Every multi-byte field but can_id is little-endian
// (the magic tells readers which). Host-only (std::string).
#pragma once
#include <stdint.h>

#include <string>

#include "canopen/can_frame.h"
#include "host/candump_text.h"
#include "host/status.h"

namespace mb2co {

constexpr uint32_t kLinktypeCanSocketcan = 227;
constexpr uint32_t kPcapMagicMicroseconds = 0xA1B2C3D4u;
constexpr size_t kPcapFileHeaderBytes = 24;
/// Record header plus the SocketCAN frame.
constexpr size_t kPcapCanRecordBytes = 16 + 16;
/// Flags of can_id in a SocketCAN frame (linux/can.h).
constexpr uint32_t kSocketCanEffFlag = 0x80000000u;
constexpr uint32_t kSocketCanRtrFlag = 0x40000000u;

namespace pcap_detail {
inline void put_le32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFFu);
}
inline void put_le16(std::string& out, uint16_t v) {
  out += static_cast<char>(v & 0xFFu);
  out += static_cast<char>(v >> 8);
}
}  // namespace pcap_detail

/// True when `path` names a pcap file (ends in ".pcap"): the trace options
/// choose the format by it.
inline bool is_pcap_path(const std::string& path) {
  static const std::string kExt = ".pcap";
  return path.size() > kExt.size() && path.compare(path.size() - kExt.size(), kExt.size(), kExt) == 0;
}

/// The file header: version 2.4, time stamps in µs, link type 227.
inline std::string pcap_can_file_header() {
  std::string h;
  pcap_detail::put_le32(h, kPcapMagicMicroseconds);
  pcap_detail::put_le16(h, 2);
  pcap_detail::put_le16(h, 4);
  pcap_detail::put_le32(h, 0);      // thiszone
  pcap_detail::put_le32(h, 0);      // sigfigs
  pcap_detail::put_le32(h, 65535);  // snaplen
  pcap_detail::put_le32(h, kLinktypeCanSocketcan);
  return h;
}

/// One record for `frame` seen at t_us (µs since the epoch).
inline std::string pcap_can_record(uint64_t t_us, const CanFrame& frame) {
  std::string r;
  pcap_detail::put_le32(r, static_cast<uint32_t>(t_us / 1000000u));
  pcap_detail::put_le32(r, static_cast<uint32_t>(t_us % 1000000u));
  pcap_detail::put_le32(r, 16);  // bytes stored
  pcap_detail::put_le32(r, 16);  // bytes on the wire
  uint32_t id = frame.id;
  if (frame.extended()) id |= kSocketCanEffFlag;
  if (frame.rtr()) id |= kSocketCanRtrFlag;
  for (int i = 3; i >= 0; --i) r += static_cast<char>((id >> (8 * i)) & 0xFFu);
  const uint8_t len = frame.dlc > 8 ? 8 : frame.dlc;
  r += static_cast<char>(len);
  r.append(3, '\0');
  for (uint8_t i = 0; i < 8; ++i) r += static_cast<char>(i < len && !frame.rtr() ? frame.data[i] : 0);
  return r;
}

/// A whole `candump -L` log as pcap (blank lines skipped); fails naming the
/// first line it cannot read.
inline Status pcap_from_candump_log(const std::string& log, std::string* pcap) {
  std::string out = pcap_can_file_header();
  size_t start = 0;
  for (size_t number = 1; start < log.size(); ++number) {
    size_t nl = log.find('\n', start);
    if (nl == std::string::npos) nl = log.size();
    const std::string line = log.substr(start, nl - start);
    start = nl + 1;
    if (line.empty()) continue;
    uint64_t t_us = 0;
    std::string iface;
    CanFrame frame = {};
    if (!parse_candump_log_line(line, &t_us, &iface, &frame))
      return Status::failure("candump log line " + std::to_string(number) + " is not a frame: " + line);
    out += pcap_can_record(t_us, frame);
  }
  *pcap = std::move(out);
  return Status::ok();
}

}  // namespace mb2co
