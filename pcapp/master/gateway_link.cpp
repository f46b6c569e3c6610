#include "gateway_link.h"

#include <errno.h>
#include <modbus.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

#include "platform/stop_signal.h"

namespace mb2co {
namespace master {

namespace {

int64_t now_ms() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}

}  // namespace

Status GatewayLink::open(const std::string& path, uint32_t baud, uint8_t slave, modbus::Parity parity) {
  close();
  path_ = path;
  baud_ = baud;
  slave_ = slave;
  port::catch_stop_signals();
  ctx_ = modbus_new_rtu(path.c_str(), static_cast<int>(baud), modbus::parity_letter(parity), 8, 1);
  if (ctx_ == nullptr) return Status::failure("cannot use " + path + ": " + modbus_strerror(errno));
  if (modbus_set_slave(ctx_, slave) != 0) {
    Status refused = Status::failure(std::string("libmodbus refused slave ") + std::to_string(slave) + ": " +
                                     modbus_strerror(errno));
    close();
    return refused;
  }
  if (modbus_connect(ctx_) != 0) {
    Status refused = Status::failure("cannot open " + path + ": " + modbus_strerror(errno));
    close();
    return refused;
  }
  return Status::ok();
}

void GatewayLink::close() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

std::string GatewayLink::where() const {
  return "slave " + std::to_string(slave_) + " on " + path_;
}

uint32_t GatewayLink::settle_ms() const {
  // t3.5: 3.5 characters of 11 bits, at least 1.75 ms (serial line spec
  // §2.5.1.1); 10 ms more for the scheduling of a pty under load.
  const uint32_t t35_us = baud_ > 19200u ? 1750u : 38500000u / baud_;
  return t35_us / 1000u + 1u + 10u;
}

GatewayChannel::Exchange GatewayLink::exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                                               modbus::NetResponse* out) {
  if (ctx_ == nullptr || length < 4)
    return Exchange::failed(Outcome::kIoError, "the gateway's port is not open");
  const int fd = modbus_get_socket(ctx_);
  modbus_flush(ctx_);  // a late answer to an earlier request must not be taken for this one
  // libmodbus appends the CRC itself: hand it the request without ours.
  if (modbus_send_raw_request(ctx_, request, length - modbus::kCrcBytes) != length)
    return Exchange::failed(Outcome::kIoError,
                            std::string("cannot send to ") + where() + ": " + modbus_strerror(errno));
  const int64_t deadline = now_ms() + timeout_ms;
  uint16_t got = 0;
  bool parsed = false;  // response_[0, got) is a whole answer already
  int64_t settle_until = 0;
  for (;;) {
    if (port::stop_requested()) return Exchange::interrupted();
    const int64_t until = parsed ? settle_until : deadline;
    const int64_t left = until - now_ms();
    pollfd p{fd, POLLIN, 0};
    const int ready = left > 0 ? poll(&p, 1, static_cast<int>(left)) : 0;
    if (ready < 0 && errno == EINTR) continue;  // port::stop_requested() tells
    if (ready <= 0) {
      if (parsed) return Exchange::answered();
      if (got == 0)
        return Exchange::failed(Outcome::kNoAnswer, "no answer from " + where() + " within " +
                                                        std::to_string(timeout_ms) + " ms");
      return Exchange::failed(Outcome::kBadAnswer,
                              "no valid answer from " + where() + " (" + std::to_string(got) + " bytes)");
    }
    const ssize_t n = ::read(fd, response_ + got, sizeof response_ - got);
    if (n <= 0) {
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      // A hung-up device does not come back by waiting.
      return Exchange::failed(
          Outcome::kIoError,
          where() + ": " + (n == 0 ? std::string("end of file") : std::string(std::strerror(errno))));
    }
    got = static_cast<uint16_t>(got + n);
    const modbus::ParseStatus st = modbus::parse_net_response(request, length, response_, got, *out);
    parsed = st == modbus::ParseStatus::kOk || st == modbus::ParseStatus::kException;
    // A normal response's length comes from its own header and an exception
    // other than 04 is five bytes: both are whole once they parse. A
    // five-byte exception 04 may be the start of an abort response (ten
    // bytes): more bytes within t3.5 make it that.
    if (parsed && !(st == modbus::ParseStatus::kException && out->abort_code == 0 &&
                    out->exception == modbus::Exception::kServerDeviceFailure))
      return Exchange::answered();
    if (parsed) settle_until = now_ms() + settle_ms();
    if (got == sizeof response_)
      return Exchange::failed(Outcome::kBadAnswer, "an answer longer than any Modbus frame from " + where());
  }
}

}  // namespace master
}  // namespace mb2co
