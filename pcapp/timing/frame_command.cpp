// `mb2co-timing frame`: frame lengths by DLC (both worst-case conventions)
// or the exact length of one concrete frame.
#include <cstdio>

#include "command_parts.h"
#include "timing/can_bits.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

Status parse_hex_bytes(const std::string& hex, CanFrame& frame) {
  if (hex.size() % 2 != 0 || hex.size() > 16) {
    return Status::failure("--data must be 0..8 bytes as an even number of hex digits, got \"" + hex + "\"");
  }
  for (size_t i = 0; i < hex.size(); i += 2) {
    unsigned value = 0;
    for (size_t k = i; k < i + 2; ++k) {
      const char c = hex[k];
      const int digit = c >= '0' && c <= '9'   ? c - '0'
                        : c >= 'a' && c <= 'f' ? c - 'a' + 10
                        : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                               : -1;
      if (digit < 0) {
        return Status::failure("--data must be hex digits, got \"" + hex + "\"");
      }
      value = value * 16u + static_cast<unsigned>(digit);
    }
    frame.data[i / 2] = static_cast<uint8_t>(value);
  }
  frame.dlc = static_cast<uint8_t>(hex.size() / 2);
  return Status::ok();
}

Status parse_id(const std::string& text, bool extended, uint32_t* id) {
  const uint64_t max = extended ? 0x1FFFFFFFu : 0x7FFu;
  uint64_t v = 0;
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  bool ok = text.size() > (hex ? 2u : 0u) && text.size() <= 12;
  for (size_t i = hex ? 2 : 0; ok && i < text.size(); ++i) {
    const char c = text[i];
    int digit = c >= '0' && c <= '9' ? c - '0' : -1;
    if (hex && c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (hex && c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    ok = digit >= 0;
    v = v * (hex ? 16u : 10u) + static_cast<uint64_t>(digit < 0 ? 0 : digit);
  }
  if (!ok || v > max) {
    return Status::failure(std::string("--id must be ") + (extended ? "0..0x1FFFFFFF" : "0..0x7FF") +
                           " (decimal or 0x-hex), got \"" + text + "\"");
  }
  *id = static_cast<uint32_t>(v);
  return Status::ok();
}

Status exact_frame(const Options& o, uint32_t bitrate, timing::WorstCase convention, std::ostream& out,
                   Format format) {
  if (!o.has("--id")) {
    return Status::failure("--data/--rtr needs --id");
  }
  CanFrame frame{};
  frame.flags = static_cast<uint8_t>((o.has("--ext") ? CanFrame::kExtended : 0) |
                                     (o.has("--rtr") ? CanFrame::kRtr : 0));
  Status s = parse_id(o.get("--id"), frame.extended(), &frame.id);
  if (!s) return s;
  if (o.has("--data") && !(s = parse_hex_bytes(o.get("--data"), frame))) return s;
  if (o.has("--dlc")) {
    uint64_t dlc = 0;
    if (!(s = uint_option(o, "--dlc", 0, 8, 0, &dlc))) return s;
    if (!frame.rtr() && o.has("--data") && dlc != frame.dlc) {
      return Status::failure("--dlc disagrees with the " + std::to_string(frame.dlc) + " bytes of --data");
    }
    frame.dlc = static_cast<uint8_t>(dlc);
  }
  const timing::ExactFrameBits exact = timing::frame_bits_exact(frame);
  char crc[8];
  std::snprintf(crc, sizeof crc, "0x%04X", exact.crc15);
  std::string data;
  const uint8_t data_bytes = frame.rtr() ? uint8_t{0} : frame.dlc;
  for (uint8_t i = 0; i < data_bytes; ++i) {
    char byte[4];
    std::snprintf(byte, sizeof byte, "%02X", frame.data[i]);
    data += byte;
  }
  Report r;
  r.rows_key = "frames";
  r.columns = {"id",         "ext",  "rtr",   "dlc",  "data",      "bits_unstuffed",
               "stuff_bits", "bits", "crc15", "c_us", "bits_worst"};
  r.rows.push_back(
      {Cell::id(frame.id, frame.extended()), Cell::boolean(frame.extended()), Cell::boolean(frame.rtr()),
       Cell::integer(frame.dlc), Cell::str(data),
       Cell::integer(static_cast<uint64_t>(exact.total_bits - exact.stuff_bits)),
       Cell::integer(exact.stuff_bits), Cell::integer(exact.total_bits), Cell::str(crc),
       Cell::us(timing::bits_to_ns_ceil(exact.total_bits, bitrate)),
       Cell::integer(timing::frame_bits_worst(frame.extended(), frame.rtr() ? 0 : frame.dlc, convention))});
  r.totals = {{"bitrate", Cell::integer(bitrate)}, {"frame_bits", Cell::str(frame_bits_name(convention))}};
  print_report(r, format, out);
  return Status::ok();
}

}  // namespace

Status frame_command(const Options& o, std::ostream& out) {
  const uint32_t rate = o.args.bitrate_bps("--bitrate", 1000000);
  timing::WorstCase convention = timing::WorstCase::kDavis;
  Format format = Format::kTable;
  Status s = frame_bits_option(o, &convention);
  if (s) s = format_option(o, &format);
  if (!s) return s;
  if (o.has("--id") || o.has("--data") || o.has("--rtr")) {
    return exact_frame(o, rate, convention, out, format);
  }
  uint64_t dlc_first = 0;
  uint64_t dlc_last = 8;
  if (o.has("--dlc")) {
    if (!(s = uint_option(o, "--dlc", 0, 8, 0, &dlc_first))) return s;
    dlc_last = dlc_first;
  }
  const bool ext = o.has("--ext");
  Report r;
  r.columns = {"dlc",         "bits_unstuffed", "stuffable_bits", "stuff_course", "bits_course",
               "stuff_davis", "bits_davis",     "bits",           "c_us"};
  for (uint64_t d = dlc_first; d <= dlc_last; ++d) {
    const uint8_t dlc = static_cast<uint8_t>(d);
    const uint16_t bits = timing::frame_bits_worst(ext, dlc, convention);
    r.rows.push_back({Cell::integer(dlc), Cell::integer(timing::frame_bits_unstuffed(ext, dlc)),
                      Cell::integer(timing::stuffable_bits(ext, dlc)),
                      Cell::integer(timing::worst_stuff_bits(ext, dlc, timing::WorstCase::kCourse)),
                      Cell::integer(timing::frame_bits_worst(ext, dlc, timing::WorstCase::kCourse)),
                      Cell::integer(timing::worst_stuff_bits(ext, dlc, timing::WorstCase::kDavis)),
                      Cell::integer(timing::frame_bits_worst(ext, dlc, timing::WorstCase::kDavis)),
                      Cell::integer(bits), Cell::us(timing::bits_to_ns_ceil(bits, rate))});
  }
  r.totals = {{"bitrate", Cell::integer(rate)},
              {"frame_bits", Cell::str(frame_bits_name(convention))},
              {"extended", Cell::boolean(ext)}};
  print_report(r, format, out);
  return Status::ok();
}

}  // namespace timing_cli
}  // namespace mb2co
