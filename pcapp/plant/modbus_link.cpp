#include "modbus_link.h"

#include <errno.h>
#include <modbus.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

#include "gateway/network_service.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "platform/mbap_client.h"

namespace mb2co {
namespace pcapp {

namespace {
bool is_exception(int err) {
  return err >= EMBXILFUN && err <= EMBXGTAR;
}

int64_t now_ms() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}

/// The first frame in buf[0, got) that answers `request` (its exception
/// included), moved to buf[0], `got` cut to its length. Before it may lie a
/// late answer to an abandoned attempt that arrived in the same read (a slave
/// catching up sends both back to back, so no silence separates them here),
/// after it anything. kTooShort while there is none: more bytes may complete
/// it. Every start at this slave's address and function is tried with every
/// length: a wrong frame needs a matching CRC and consistent fields to pass.
modbus::ParseStatus find_answer(const uint8_t* request, uint16_t length, bool net, uint8_t* buf,
                                uint16_t& got) {
  constexpr uint16_t kShortestFrame = 5;  // address, function, exception code, CRC
  for (uint16_t start = 0; start + kShortestFrame <= got; ++start) {
    if (buf[start] != request[0] || (buf[start + 1] & 0x7F) != request[1]) continue;
    for (uint16_t end = static_cast<uint16_t>(start + kShortestFrame); end <= got; ++end) {
      const uint16_t n = static_cast<uint16_t>(end - start);
      modbus::Response parsed;
      modbus::NetResponse net_parsed{};  // FC 2Bh/0Dh has its own codec
      const modbus::ParseStatus st =
          net ? modbus::parse_net_response(request, length, buf + start, n, net_parsed)
              : modbus::parse_response(request, length, buf + start, n, parsed);
      if (st == modbus::ParseStatus::kOk || st == modbus::ParseStatus::kException) {
        std::memmove(buf, buf + start, n);
        got = n;
        return st;
      }
    }
  }
  return modbus::ParseStatus::kTooShort;
}
}  // namespace

Status ModbusLink::open(const LinkSettings& settings) {
  close();
  settings_ = settings;
  ctx_ = settings.on_tcp
             ? modbus_new_tcp_pi(settings.tcp.host.c_str(), std::to_string(settings.tcp.port).c_str())
             : modbus_new_rtu(settings.path.c_str(), settings.baud, modbus::parity_letter(settings.parity), 8,
                              1);
  if (ctx_ == nullptr)
    return Status::failure("cannot use " + settings.where() + ": " + modbus_strerror(errno));
  const uint32_t us = static_cast<uint32_t>(settings.timeout_ms) * 1000u;
  if (modbus_set_slave(ctx_, settings.slave) != 0 ||
      modbus_set_response_timeout(ctx_, us / 1000000u, us % 1000000u) != 0 ||
      modbus_set_byte_timeout(ctx_, us / 1000000u, us % 1000000u) != 0) {
    Status refused =
        Status::failure(std::string("libmodbus refused the settings: ") + modbus_strerror(errno));
    close();
    return refused;
  }
  if (modbus_connect(ctx_) != 0) {
    Status refused = Status::failure("cannot open " + settings.where() + ": " + modbus_strerror(errno));
    close();
    return refused;
  }
  return Status::ok();
}

void ModbusLink::close() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

template <class F>
LinkResult ModbusLink::attempt(const char* what, F request) {
  if (ctx_ == nullptr) return LinkResult::failure(LinkStatus::kFailed, std::string(what) + ": port closed");
  std::string why;
  bool heard = false;
  for (int i = 0; i <= settings_.retries; ++i) {
    if (i > 0) ++retries_used_;
    // libmodbus takes the first frame it reads for the answer: a late one to
    // an abandoned attempt (this request's or the one before) must go first.
    // One that arrives later still is read by libmodbus by its own length and
    // refused (another function, CRC or count): a failed attempt, repeated.
    if (drop_pending() > 0) heard = true;
    if (request() >= 0) return LinkResult::done();
    const int err = errno;
    why = std::string(what) + ": " + modbus_strerror(err);
    if (is_exception(err)) return LinkResult::failure(LinkStatus::kException, why);
    if (err != ETIMEDOUT) heard = true;
  }
  return LinkResult::failure(LinkStatus::kFailed, why, heard);
}

bool ModbusLink::late_answer_within(int wait_ms) {
  pollfd p{modbus_get_socket(ctx_), POLLIN, 0};
  if (poll(&p, 1, wait_ms) <= 0 || (p.revents & POLLIN) == 0) return false;
  return drop_pending() > 0;
}

size_t ModbusLink::drop_pending() {
  const int fd = modbus_get_socket(ctx_);
  size_t dropped = 0;
  uint8_t junk[256];
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 0) <= 0 || (p.revents & POLLIN) == 0) break;
    const ssize_t n = ::read(fd, junk, sizeof junk);
    if (n <= 0) break;  // a hung-up device: the request's write or read says so
    dropped += static_cast<size_t>(n);
  }
  stale_bytes_dropped_ += dropped;
  return dropped;
}

LinkResult ModbusLink::read(const TransactionPlan& plan, const RegisterImage& out, RegisterImage& in) {
  if (plan.read_write) {
    const Block& w = plan.writes[0];
    const Block& r = plan.reads[0];
    const uint16_t* values = out.regs[0].data() + w.start;
    uint16_t* dest = in.block(r);
    return attempt("FC 17", [&] {
      return modbus_write_and_read_registers(ctx_, w.start, w.count, values, r.start, r.count, dest);
    });
  }
  for (const Block& b : plan.reads) {
    uint16_t* dest = in.block(b);
    const bool input = b.table == RegTable::kInput;
    LinkResult s = attempt(input ? "FC 04" : "FC 03", [&] {
      return input ? modbus_read_input_registers(ctx_, b.start, b.count, dest)
                   : modbus_read_registers(ctx_, b.start, b.count, dest);
    });
    if (!s.ok()) return s;
  }
  return LinkResult::done();
}

LinkResult ModbusLink::write(const TransactionPlan& plan, const RegisterImage& out) {
  for (const Block& b : plan.writes) {
    const uint16_t* values = out.regs[0].data() + b.start;
    LinkResult s =
        b.count == 1
            ? attempt("FC 06", [&] { return modbus_write_register(ctx_, b.start, values[0]); })
            : attempt("FC 10", [&] { return modbus_write_registers(ctx_, b.start, b.count, values); });
    if (!s.ok()) return s;
  }
  return LinkResult::done();
}

LinkResult ModbusLink::raw_tcp(const uint8_t* request, uint16_t length, uint8_t* response, uint16_t& got) {
  const bool net = modbus::is_net_pdu(request + 1, static_cast<uint16_t>(length - 1));
  std::string why;
  bool heard = false;
  for (int i = 0; i <= settings_.retries; ++i) {
    if (i > 0) ++retries_used_;
    const int64_t deadline = mbap_now_ms() + settings_.timeout_ms;
    const MbapOutcome o =
        mbap_exchange(modbus_get_socket(ctx_), request, length, ++transaction_, deadline, response, &got);
    if (o == MbapOutcome::kAnswer) {
      modbus::Response parsed;
      modbus::NetResponse net_parsed{};
      const modbus::ParseStatus st =
          net ? modbus::parse_net_response(request, length, response, got, net_parsed)
              : modbus::parse_response(request, length, response, got, parsed);
      if (st == modbus::ParseStatus::kOk) return LinkResult::done();
      if (st == modbus::ParseStatus::kException) {
        const modbus::Exception e = net ? net_parsed.exception : parsed.exception;
        return LinkResult::failure(LinkStatus::kException,
                                   "exception " + std::to_string(static_cast<int>(e)));
      }
      why = "bad answer (" + std::to_string(got) + " bytes)";
      heard = true;
      continue;
    }
    // A broken stream or connection does not come back by retrying.
    if (o == MbapOutcome::kClosed || o == MbapOutcome::kSendFailed || o == MbapOutcome::kBadFrame)
      return LinkResult::failure(LinkStatus::kFailed,
                                 o == MbapOutcome::kBadFrame ? "bad MBAP header" : "connection closed", true);
    heard = heard || o == MbapOutcome::kPartial;
    why = o == MbapOutcome::kPartial ? "part of an answer" : "no answer";
  }
  return LinkResult::failure(LinkStatus::kFailed, why, heard);
}

LinkResult ModbusLink::raw(const uint8_t* request, uint16_t length, uint8_t* response, uint16_t capacity,
                           uint16_t& got) {
  if (settings_.on_tcp) return raw_tcp(request, length, response, got);
  const int fd = modbus_get_socket(ctx_);
  const bool net = modbus::is_net_pdu(request + 1, static_cast<uint16_t>(length - 1));
  std::string why;
  bool heard = false;
  for (int i = 0; i <= settings_.retries; ++i) {
    if (i > 0) ++retries_used_;
    // What waits now answers nothing still asked (find_answer skips one that
    // arrives during this attempt).
    if (drop_pending() > 0) heard = true;
    if (::write(fd, request, length) != static_cast<ssize_t>(length)) {
      return LinkResult::failure(LinkStatus::kFailed, std::string("write: ") + std::strerror(errno));
    }
    got = 0;
    const int64_t deadline = now_ms() + settings_.timeout_ms;
    modbus::ParseStatus st = modbus::ParseStatus::kTooShort;
    while (st != modbus::ParseStatus::kOk && st != modbus::ParseStatus::kException) {
      const int64_t left = deadline - now_ms();
      pollfd p{fd, POLLIN, 0};
      if (left <= 0 || poll(&p, 1, static_cast<int>(left)) <= 0) break;
      const ssize_t n = ::read(fd, response + got, capacity - got);
      if (n <= 0) {
        // A hung-up device does not come back by retrying.
        return LinkResult::failure(LinkStatus::kFailed,
                                   std::string("read: ") + (n == 0 ? "end of file" : std::strerror(errno)));
      }
      got = static_cast<uint16_t>(got + n);
      st = find_answer(request, length, net, response, got);
      if (got == capacity) break;
    }
    if (st == modbus::ParseStatus::kOk) return LinkResult::done();
    if (st == modbus::ParseStatus::kException) {
      modbus::Response parsed;
      modbus::NetResponse net_parsed{};
      if (net)
        modbus::parse_net_response(request, length, response, got, net_parsed);
      else
        modbus::parse_response(request, length, response, got, parsed);
      const modbus::Exception e = net ? net_parsed.exception : parsed.exception;
      return LinkResult::failure(LinkStatus::kException, "exception " + std::to_string(static_cast<int>(e)));
    }
    if (got > 0) heard = true;
    why = got == 0 ? "no answer" : "bad answer (" + std::to_string(got) + " bytes)";
  }
  return LinkResult::failure(LinkStatus::kFailed, why, heard);
}

LinkResult ModbusLink::network_view(std::vector<modbus::NetViewEntry>& view, bool& unsupported) {
  unsupported = false;
  if (ctx_ == nullptr) return LinkResult::failure(LinkStatus::kFailed, "FC 2B/0D: port closed");
  view.clear();
  const uint8_t slave = static_cast<uint8_t>(settings_.slave);
  uint8_t request[32];
  uint8_t response[modbus::kMaxAduBytes];
  uint8_t first = 1;
  // A response lists at most kMaxViewEntries nodes; "more follows" asks
  // for the rest from the node after the last one listed.
  for (;;) {
    const uint16_t n = modbus::build_net_view(request, sizeof request, slave, first);
    uint16_t got = 0;
    const LinkResult s = raw(request, n, response, sizeof response, got);
    modbus::NetResponse r{};
    if (s.outcome == LinkStatus::kException) {
      modbus::parse_net_response(request, n, response, got, r);
      unsupported = r.exception == modbus::Exception::kIllegalFunction;
    }
    if (!s.ok()) return LinkResult::failure(s.outcome, "FC 2B/0D network view: " + s.status.message());
    modbus::parse_net_response(request, n, response, got, r);
    const size_t before = view.size();
    if (!append_view_entries(r.message, &view))
      return LinkResult::failure(LinkStatus::kFailed, "FC 2B/0D network view: not whole entries");
    if (!r.message.more_follows || view.size() == before || view.back().node_id >= 127) break;
    first = static_cast<uint8_t>(view.back().node_id + 1);
  }
  return LinkResult::done();
}

LinkResult ModbusLink::upload(uint8_t node_id, uint16_t index, uint8_t sub, uint32_t& value,
                              uint32_t& abort_code) {
  value = 0;
  abort_code = 0;
  if (ctx_ == nullptr) return LinkResult::failure(LinkStatus::kFailed, "FC 2B/0D: port closed");
  uint8_t request[32];
  uint8_t response[modbus::kMaxAduBytes];
  const uint16_t n = modbus::build_net_upload(request, sizeof request, static_cast<uint8_t>(settings_.slave),
                                              node_id, index, sub, 0, 4);
  uint16_t got = 0;
  // The gateway answers when its SDO client is done: a node that does not
  // answer ends it with abort 05040000h after kNetSdoTimeoutUs, later than
  // the cycle's timeout. Waited for once (a repeat would only be refused
  // with exception 06 while the first runs), not taken for a lost link.
  const LinkSettings cycle = settings_;
  settings_.timeout_ms += static_cast<int>(gateway::kNetSdoTimeoutUs / 1000u);
  settings_.retries = 0;
  LinkResult s = raw(request, n, response, sizeof response, got);
  settings_ = cycle;
  modbus::NetResponse r{};
  modbus::parse_net_response(request, n, response, got, r);
  if (s.outcome == LinkStatus::kException) abort_code = r.abort_code;
  if (!s.ok()) return s;
  if (r.message.data_length > 4)
    return LinkResult::failure(LinkStatus::kFailed, "FC 2B/0D upload: more than 4 bytes");
  for (uint16_t i = 0; i < r.message.data_length; ++i)
    value |= static_cast<uint32_t>(r.message.data[i]) << (8 * i);
  return LinkResult::done();
}

LinkResult ModbusLink::holding_register(uint16_t address, uint16_t& value) {
  if (ctx_ == nullptr) return LinkResult::failure(LinkStatus::kFailed, "FC 03: port closed");
  return attempt("FC 03", [&] { return modbus_read_registers(ctx_, address, 1, &value); });
}

LinkResult ModbusLink::identify(std::string& identity) {
  if (ctx_ == nullptr) return LinkResult::failure(LinkStatus::kFailed, "");
  const uint8_t slave = static_cast<uint8_t>(settings_.slave);
  uint8_t request[16];
  uint8_t response[256];
  uint16_t got = 0;
  uint16_t n = modbus::build_read_device_id(request, sizeof request, slave, 1, 0);
  LinkResult s = raw(request, n, response, sizeof response, got);
  if (s.ok()) {
    modbus::Response r;
    modbus::parse_response(request, n, response, got, r);
    std::string parts[3];
    for (uint8_t i = 0; i < r.object_count; ++i) {
      uint8_t id = 0, len = 0;
      const uint8_t* value = nullptr;
      if (modbus::device_id_object(r, i, id, value, len) && id < 3) {
        parts[id].assign(reinterpret_cast<const char*>(value), len);
      }
    }
    identity = parts[0] + " " + parts[1] + " " + parts[2];
    if (parts[0] != "mb2co") {
      return LinkResult::failure(LinkStatus::kException, "slave " + std::to_string(settings_.slave) +
                                                             " is not an mb2co gateway (vendor '" + parts[0] +
                                                             "')");
    }
    return LinkResult::done();
  }
  if (s.outcome == LinkStatus::kFailed && !s.heard && late_answer_within(settings_.timeout_ms)) {
    // Silence in every attempt, then bytes: a slave that answers, only later
    // than the timeout. Not the same as no slave at all (LinkSupervisor).
    return LinkResult::failure(LinkStatus::kFailed,
                               "FC 2B/0E: answer later than " + std::to_string(settings_.timeout_ms) + " ms",
                               true);
  }
  if (s.outcome != LinkStatus::kException)
    return LinkResult::failure(s.outcome, "FC 2B/0E: " + s.status.message(), s.heard);
  // No FC 2B: an echo (FC 08/00) at least shows a live slave at this address.
  n = modbus::build_diagnostics(request, sizeof request, slave, 0x0000, 0xA55A);
  s = raw(request, n, response, sizeof response, got);
  // An exception to FC 08 too: a slave is there, and it is not one of ours.
  if (!s.ok()) return LinkResult::failure(s.outcome, "FC 08/00: " + s.status.message(), true);
  identity = "unidentified slave (FC 08/00 echo)";
  return s;
}

}  // namespace pcapp
}  // namespace mb2co
