// mb2co-net-client: an FC 2Bh / MEI 0Dh client that is not ours. It is
// written from docs/gateway-network.md alone and links nothing of mb2co:
// libmodbus opens the serial line, adds address and CRC to each request
// (modbus_send_raw_request) and receives the answer
// (modbus_receive_confirmation); the PDUs are built and checked here, byte
// by byte as the document lays them out. The tests (tests/uno/
// test_uno_network.cpp) drive it through a gateway to remote nodes.
//
// Usage: mb2co-net-client DEVICE [SLAVE [TIMEOUT_MS]]   (115200 8N1, slave 1,
// kResponseTimeoutMs)
// Commands on stdin, one answer line on stdout each (numbers in hex but
// NODE, START, COUNT, MS; data as one hex string, CANopen byte order):
//   upload NODE INDEX SUB [START [COUNT]]  -> upload size=S more=M data=HEX ms=T
//   read NODE INDEX SUB [WINDOW]           -> read size=S data=HEX requests=N ms=T  (windows until done)
//   part NODE INDEX SUB SIZE START MORE HEX -> part size=S ms=T  (one download request)
//   write NODE INDEX SUB HEX [PART]        -> write size=S parts=N ms=T  (parts of PART bytes, default 63)
//   nmt NODE COMMAND                       -> nmt ms=T
//   view [FIRST]                           -> view more=M nodes=ID:STATE:AGE,... ms=T
//   raw HEX                                -> response HEX ms=T  (any PDU; the response's PDU, CRC checked)
//   send upload NODE INDEX SUB             -> sent  (the request only: its answer is not read)
//   inputs ADDR N                          -> inputs V V ... ms=T  (FC 04 by libmodbus)
//   silence MS                             -> silence | bytes N  (nothing may come from the gateway)
// Failures: "exception CC ms=T", "exception 04 abort=AAAAAAAA ms=T" (the
// SDO abort code of docs/gateway-network.md's 7-byte exception 04),
// "error TEXT" (no answer, a wrong CRC, a response that does not echo its
// request as the document says).
#include <errno.h>
#include <modbus.h>
#include <poll.h>
#include <stdint.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using Bytes = std::vector<uint8_t>;

// A master waits 500 ms plus the frame times for a missing node
// (docs/gateway-network.md, "How long a master waits"): 2 s leaves room for
// a slow host. A test that starves the gateway's host longer (a simulated
// Uno then runs slower than the wall clock) gives its own.
constexpr uint32_t kResponseTimeoutMs = 2000;
// Every part before the last carries whole SDO segments; 63 bytes (9
// segments) fit the Uno's frame buffer (docs/gateway-network.md, "Limits").
constexpr size_t kDefaultPart = 63;

modbus_t* g_ctx = nullptr;

using Clock = std::chrono::steady_clock;

// When the line is silent long enough for the next request: a request sent
// while the previous one is still being received (the gateway clocks it in
// at 87 us a character) or less than t3.5 after it would be one frame with
// it. After a request whose answer is not awaited (`send`) the next waits
// the frame's time and 20 ms (the simulated Uno reads its pty in passes of
// up to 2 ms, longer on a loaded host); after an answer, none.
Clock::time_point g_line_free_at;

std::string hex(const Bytes& b) {
  static const char kDigits[] = "0123456789abcdef";
  std::string s;
  for (uint8_t x : b) {
    s += kDigits[x >> 4];
    s += kDigits[x & 15];
  }
  return s;
}

bool parse_hex_bytes(const std::string& s, Bytes* out) {
  if (s.size() % 2 != 0) return false;
  out->clear();
  for (size_t i = 0; i < s.size(); i += 2) {
    char* end = nullptr;
    const std::string two = s.substr(i, 2);
    const unsigned long v = std::strtoul(two.c_str(), &end, 16);
    if (end != two.c_str() + 2) return false;
    out->push_back(static_cast<uint8_t>(v));
  }
  return true;
}

uint16_t be16(const Bytes& b, size_t at) {
  return static_cast<uint16_t>(b[at] << 8 | b[at + 1]);
}

uint32_t be32(const Bytes& b, size_t at) {
  return static_cast<uint32_t>(b[at]) << 24 | static_cast<uint32_t>(b[at + 1]) << 16 |
         static_cast<uint32_t>(b[at + 2]) << 8 | b[at + 3];
}

void put16(Bytes* b, uint32_t v) {
  b->push_back(static_cast<uint8_t>(v >> 8));
  b->push_back(static_cast<uint8_t>(v));
}

void put32(Bytes* b, uint32_t v) {
  put16(b, v >> 16);
  put16(b, v & 0xFFFF);
}

// The 12-byte header (docs/gateway-network.md, "Request and response").
Bytes header(uint8_t control, uint8_t node, uint16_t index, uint8_t sub, uint16_t start, uint16_t count) {
  Bytes b{0x2B, 0x0D, control, 0x00, node};
  put16(&b, index);
  b.push_back(sub);
  put16(&b, start);
  put16(&b, count);
  return b;
}

uint16_t crc16(const uint8_t* data, size_t n) {  // Modbus over serial line V1.02, 6.2.2
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

// The longest pause between two bytes of a response. The gateway sends
// them back to back; a longer pause is the host's: a simulated Uno
// (mb2co-uno) starved by a loaded host pauses with its whole clock
// (uno.network_load saw more than 100 ms).
constexpr int kByteGapMs = 1000;

// Reads exactly `n` more bytes of the frame from the port (at most
// kByteGapMs between two: the frame is on its way).
bool read_more(uint8_t* out, size_t n) {
  const int fd = modbus_get_socket(g_ctx);
  for (size_t got = 0; got < n;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, kByteGapMs) <= 0) return false;
    const ssize_t r = read(fd, out + got, n - got);
    if (r <= 0) return false;
    got += static_cast<size_t>(r);
  }
  return true;
}

// After a response that could not be read: what is left of it, so that the
// next request's answer is not mixed with it; how many bytes.
size_t discard_rest() {
  uint8_t junk[MODBUS_RTU_MAX_ADU_LENGTH];
  size_t n = 0;
  for (pollfd p{modbus_get_socket(g_ctx), POLLIN, 0}; poll(&p, 1, 50) > 0;) {
    const ssize_t r = read(p.fd, junk, sizeof junk);
    if (r <= 0) break;
    n += static_cast<size_t>(r);
  }
  return n;
}

struct Answer {
  std::string error;  ///< not empty: no usable response (the line to print)
  Bytes pdu;          ///< the response PDU (function code first), CRC checked
};

// The response to the request just sent. libmodbus frames a confirmation by
// its function code: a 3-byte exception (address, ABh, code; CRC) comes
// whole and CRC-checked. FC 2Bh responses and the 7-byte exception 04 are
// longer than libmodbus assumes (it takes the byte after the function code
// and then two bytes as the CRC, which fails with EMBBADCRC and leaves the
// five bytes read in `rsp`); the rest follows from the document's lengths
// and is read from libmodbus's port, and the CRC is checked here.
Answer receive_frame() {
  Answer a;
  uint8_t rsp[MODBUS_RTU_MAX_ADU_LENGTH] = {};
  const int n = modbus_receive_confirmation(g_ctx, rsp);
  if (n == 5 && rsp[1] == 0xAB) {
    a.pdu.assign(rsp + 1, rsp + 3);
    return a;
  }
  if (n >= 0 || errno != EMBBADCRC) {
    a.error = n < 0 ? std::string("error ") + modbus_strerror(errno) : "error unexpected response";
    return a;
  }
  Bytes adu(rsp, rsp + 5);
  size_t rest = 0;  // bytes after these five, CRC included
  if (adu[1] == 0xAB && adu[2] == 0x04) {
    rest = 1 + 7 + 2 - 5;  // address, AB 04 0D, the abort code, CRC: 10 bytes
  } else if (adu[1] == 0x2B && adu[2] == 0x0D) {
    Bytes head(adu.begin(), adu.end());
    head.resize(13);
    if (!read_more(head.data() + 5, 8)) {
      a.error = "error response cut short";
      return a;
    }
    adu = head;
    const bool sdo = (adu[3] >> 6) == 0;                // SDO responses carry the object size
    const bool download = sdo && (adu[3] & 0x20) != 0;  // echoes the header and size, no data
    rest = (sdo ? 4u : 0u) + (download ? 0u : size_t{be16(adu, 11)}) + 2u;
  } else {
    a.error = "error unexpected function " + hex({adu[1]});
    return a;
  }
  const size_t have = adu.size();
  adu.resize(have + rest);
  if (!read_more(adu.data() + have, rest)) {
    a.error = "error response cut short";
    return a;
  }
  const uint16_t crc = crc16(adu.data(), adu.size() - 2);
  if (adu[adu.size() - 2] != (crc & 0xFF) || adu[adu.size() - 1] != (crc >> 8)) {
    a.error = "error wrong CRC";
    return a;
  }
  a.pdu.assign(adu.begin() + 1, adu.end() - 2);
  return a;
}

Answer receive() {
  Answer a = receive_frame();
  g_line_free_at = Clock::now();
  if (!a.error.empty()) {
    const size_t left = discard_rest();
    if (left != 0) a.error += " (" + std::to_string(left) + " bytes after it discarded)";
  }
  return a;
}

bool send(const Bytes& pdu) {
  Bytes req{static_cast<uint8_t>(modbus_get_slave(g_ctx))};
  req.insert(req.end(), pdu.begin(), pdu.end());
  std::this_thread::sleep_until(g_line_free_at);
  const bool sent = modbus_send_raw_request(g_ctx, req.data(), static_cast<int>(req.size())) > 0;
  const auto frame_us = std::chrono::microseconds((req.size() + 2) * 11 * 1000000 / 115200);
  g_line_free_at = Clock::now() + frame_us + std::chrono::milliseconds(20);
  return sent;
}

std::string ms_since(Clock::time_point t0) {
  return " ms=" +
         std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count());
}

// Sends `pdu` and checks that the answer is a 2Bh/0Dh response echoing the
// request's bytes 2..9 (service, node, index, subindex, starting address;
// the `more follows` bit aside); `failure` gets the line to print otherwise.
bool exchange(const Bytes& pdu, Bytes* response, std::string* failure) {
  if (!send(pdu)) {
    *failure = std::string("error send: ") + modbus_strerror(errno);
    return false;
  }
  const Answer a = receive();
  if (!a.error.empty()) {
    *failure = a.error;
    return false;
  }
  const Bytes& r = a.pdu;
  if (r[0] == 0xAB) {
    if (r.size() == 7 && r[1] == 0x04 && r[2] == 0x0D) {
      char abort_code[9];
      std::snprintf(abort_code, sizeof abort_code, "%08x", be32(r, 3));
      *failure = std::string("exception 04 abort=") + abort_code;
    } else {
      *failure = "exception " + hex({r[1]});
    }
    return false;
  }
  if (r.size() < 12 || (r[2] & 0xFE) != (pdu[2] & 0xFE) || r[3] != 0 ||
      !std::equal(pdu.begin() + 4, pdu.begin() + 10, r.begin() + 4)) {
    *failure = "error response does not echo the request: " + hex(r);
    return false;
  }
  *response = r;
  return true;
}

struct Window {
  uint32_t size = 0;
  bool more = false;
  Bytes data;
};

bool upload(uint8_t node, uint16_t index, uint8_t sub, uint16_t start, uint16_t count, Window* w,
            std::string* failure) {
  Bytes r;
  if (!exchange(header(0x00, node, index, sub, start, count), &r, failure)) return false;
  if (r.size() < 16 || r.size() != 16u + be16(r, 10)) {
    *failure = "error upload response of a wrong length: " + hex(r);
    return false;
  }
  w->size = be32(r, 12);
  w->more = (r[2] & 1) != 0;
  w->data.assign(r.begin() + 16, r.end());
  return true;
}

// One download request: a part of `size` bytes at `start`.
bool part(uint8_t node, uint16_t index, uint8_t sub, uint32_t size, uint16_t start, bool more,
          const Bytes& data, std::string* failure) {
  Bytes req = header(more ? 0x21 : 0x20, node, index, sub, start, static_cast<uint16_t>(data.size()));
  put32(&req, size);
  req.insert(req.end(), data.begin(), data.end());
  Bytes r;
  if (!exchange(req, &r, failure)) return false;
  // The response: the request's 16 bytes echoed (header and size).
  if (r.size() != 16 || !std::equal(r.begin() + 10, r.end(), req.begin() + 10)) {
    *failure = "error download response: " + hex(r);
    return false;
  }
  return true;
}

std::string run(const std::string& line) {
  std::istringstream in(line);
  std::string word;
  in >> word;
  const Clock::time_point t0 = Clock::now();
  std::string failure;
  unsigned node = 0, index = 0, sub = 0;
  auto node_index_sub = [&] { return static_cast<bool>(in >> std::dec >> node >> std::hex >> index >> sub); };
  if (word == "upload") {
    unsigned start = 0, count = 0;
    if (!node_index_sub()) return "error usage: upload NODE INDEX SUB [START [COUNT]]";
    in >> std::dec >> start >> count;
    Window w;
    if (!upload(static_cast<uint8_t>(node), static_cast<uint16_t>(index), static_cast<uint8_t>(sub),
                static_cast<uint16_t>(start), static_cast<uint16_t>(count), &w, &failure))
      return failure + ms_since(t0);
    return "upload size=" + std::to_string(w.size) + " more=" + std::to_string(w.more) +
           " data=" + hex(w.data) + ms_since(t0);
  }
  if (word == "read") {
    unsigned window = 0;
    if (!node_index_sub()) return "error usage: read NODE INDEX SUB [WINDOW]";
    in >> std::dec >> window;
    Bytes all;
    Window w;
    int requests = 0;
    do {
      ++requests;
      if (!upload(static_cast<uint8_t>(node), static_cast<uint16_t>(index), static_cast<uint8_t>(sub),
                  static_cast<uint16_t>(all.size()), static_cast<uint16_t>(window), &w, &failure))
        return failure + ms_since(t0);
      all.insert(all.end(), w.data.begin(), w.data.end());
    } while (w.more && !w.data.empty());
    if (all.size() != w.size)
      return "error read " + std::to_string(all.size()) + " of " + std::to_string(w.size);
    return "read size=" + std::to_string(w.size) + " data=" + hex(all) +
           " requests=" + std::to_string(requests) + ms_since(t0);
  }
  if (word == "part") {
    unsigned size = 0, start = 0, more = 0;
    std::string text;
    Bytes data;
    if (!node_index_sub() || !(in >> std::dec >> size >> start >> more >> text) ||
        !parse_hex_bytes(text, &data))
      return "error usage: part NODE INDEX SUB SIZE START MORE HEX";
    if (!part(static_cast<uint8_t>(node), static_cast<uint16_t>(index), static_cast<uint8_t>(sub), size,
              static_cast<uint16_t>(start), more != 0, data, &failure))
      return failure + ms_since(t0);
    return "part size=" + std::to_string(size) + ms_since(t0);
  }
  if (word == "write") {
    std::string text;
    Bytes data;
    unsigned part_bytes = kDefaultPart;
    if (!node_index_sub() || !(in >> text) || !parse_hex_bytes(text, &data))
      return "error usage: write NODE INDEX SUB HEX [PART]";
    in >> std::dec >> part_bytes;
    if (part_bytes == 0 || part_bytes % 7 != 0) return "error PART must be a multiple of 7";
    int parts = 0;
    size_t at = 0;
    do {
      const size_t n = data.size() - at > part_bytes ? part_bytes : data.size() - at;
      const bool more = at + n < data.size();
      ++parts;
      if (!part(static_cast<uint8_t>(node), static_cast<uint16_t>(index), static_cast<uint8_t>(sub),
                static_cast<uint32_t>(data.size()), static_cast<uint16_t>(at), more,
                Bytes(data.begin() + static_cast<long>(at), data.begin() + static_cast<long>(at + n)),
                &failure))
        return failure + " parts=" + std::to_string(parts) + ms_since(t0);
      at += n;
    } while (at < data.size());
    return "write size=" + std::to_string(data.size()) + " parts=" + std::to_string(parts) + ms_since(t0);
  }
  if (word == "nmt") {
    unsigned command = 0;
    if (!(in >> std::dec >> node >> std::hex >> command)) return "error usage: nmt NODE COMMAND";
    Bytes req = header(0x60, static_cast<uint8_t>(node), 0, 0, 0, 1);
    req.push_back(static_cast<uint8_t>(command));
    Bytes r;
    if (!exchange(req, &r, &failure)) return failure + ms_since(t0);
    if (r != req) return "error nmt response is not the request: " + hex(r);
    return "nmt" + ms_since(t0);
  }
  if (word == "view") {
    unsigned first = 0;
    in >> std::dec >> first;
    Bytes r;
    if (!exchange(header(0x80, static_cast<uint8_t>(first), 0, 0, 0, 0), &r, &failure))
      return failure + ms_since(t0);
    const size_t count = be16(r, 10);
    if (r.size() != 12 + count || count % 4 != 0) return "error view response of a wrong length: " + hex(r);
    std::string nodes;
    for (size_t i = 12; i < r.size(); i += 4) {
      nodes += (nodes.empty() ? "" : ",") + std::to_string(r[i]) + ":" + hex({r[i + 1]}) + ":" +
               std::to_string(be16(r, i + 2));
    }
    return "view more=" + std::to_string(r[2] & 1) + " nodes=" + nodes + ms_since(t0);
  }
  if (word == "raw") {
    std::string text;
    Bytes pdu;
    if (!(in >> text) || !parse_hex_bytes(text, &pdu) || pdu.empty()) return "error usage: raw HEX";
    if (!send(pdu)) return std::string("error send: ") + modbus_strerror(errno);
    const Answer a = receive();
    return (a.error.empty() ? "response " + hex(a.pdu) : a.error) + ms_since(t0);
  }
  if (word == "send") {
    std::string what;
    if (!(in >> what) || what != "upload" || !node_index_sub())
      return "error usage: send upload NODE INDEX SUB";
    return send(header(0x00, static_cast<uint8_t>(node), static_cast<uint16_t>(index),
                       static_cast<uint8_t>(sub), 0, 0))
               ? "sent"
               : std::string("error send: ") + modbus_strerror(errno);
  }
  if (word == "inputs") {
    int address = 0, count = 0;
    if (!(in >> std::dec >> address >> count) || count < 1 || count > 125)
      return "error usage: inputs ADDR N";
    uint16_t regs[125] = {};
    std::this_thread::sleep_until(g_line_free_at);
    const int got = modbus_read_input_registers(g_ctx, address, count, regs);
    g_line_free_at = Clock::now();
    if (got != count) return std::string("error ") + modbus_strerror(errno) + ms_since(t0);
    std::string out = "inputs";
    for (int i = 0; i < count; ++i) out += " " + std::to_string(regs[i]);
    return out + ms_since(t0);
  }
  if (word == "silence") {
    int ms = 0;
    if (!(in >> std::dec >> ms) || ms < 0) return "error usage: silence MS";
    pollfd p{modbus_get_socket(g_ctx), POLLIN, 0};
    if (poll(&p, 1, ms) <= 0) return "silence";
    uint8_t junk[MODBUS_RTU_MAX_ADU_LENGTH];
    const ssize_t r = read(p.fd, junk, sizeof junk);
    return "bytes " + std::to_string(r);
  }
  return "error unknown command '" + word + "'";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::fprintf(stderr, "usage: mb2co-net-client DEVICE [SLAVE [TIMEOUT_MS]]\n");
    return 2;
  }
  g_ctx = modbus_new_rtu(argv[1], 115200, 'N', 8, 1);
  if (g_ctx == nullptr || modbus_set_slave(g_ctx, argc >= 3 ? std::atoi(argv[2]) : 1) != 0 ||
      modbus_connect(g_ctx) != 0) {
    std::fprintf(stderr, "mb2co-net-client: %s: %s\n", argv[1], modbus_strerror(errno));
    return 1;
  }
  const uint32_t timeout_ms = argc == 4 ? static_cast<uint32_t>(std::atol(argv[3])) : kResponseTimeoutMs;
  modbus_set_response_timeout(g_ctx, timeout_ms / 1000, (timeout_ms % 1000) * 1000);
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    std::cout << run(line) << std::endl;
  }
  modbus_close(g_ctx);
  modbus_free(g_ctx);
  return 0;
}
