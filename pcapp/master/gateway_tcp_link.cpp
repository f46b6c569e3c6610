#include "gateway_tcp_link.h"

#include <errno.h>
#include <modbus.h>

#include <cstring>

#include "modbus/master_codec.h"
#include "platform/mbap_client.h"
#include "platform/stop_signal.h"

namespace mb2co {
namespace master {

Status GatewayTcpLink::open(const TcpAddress& where, uint8_t unit) {
  close();
  address_ = where;
  unit_ = unit;
  port::catch_stop_signals();
  const std::string port = std::to_string(where.port);
  ctx_ = modbus_new_tcp_pi(where.host.c_str(), port.c_str());
  if (ctx_ == nullptr)
    return Status::failure("cannot use tcp:" + where.text() + ": " + modbus_strerror(errno));
  if (modbus_connect(ctx_) != 0) {
    Status refused = Status::failure("cannot connect to tcp:" + where.text() + ": " + modbus_strerror(errno));
    close();
    return refused;
  }
  return Status::ok();
}

void GatewayTcpLink::close() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

std::string GatewayTcpLink::where() const {
  return "unit " + std::to_string(unit_) + " on tcp:" + address_.text();
}

GatewayChannel::Outcome GatewayTcpLink::exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                                                 modbus::NetResponse* out) {
  error_.clear();
  if (ctx_ == nullptr) {
    error_ = "the gateway's connection is not open";
    return Outcome::kIoError;
  }
  uint16_t n = 0;
  switch (mbap_exchange(modbus_get_socket(ctx_), request, length, ++transaction_, mbap_now_ms() + timeout_ms,
                        adu_, &n, &port::stop_requested)) {
    case MbapOutcome::kAnswer:
      break;
    case MbapOutcome::kInterrupted:
      return Outcome::kInterrupted;
    case MbapOutcome::kSilence:
      error_ = "no answer from " + where() + " within " + std::to_string(timeout_ms) + " ms";
      return Outcome::kNoAnswer;
    case MbapOutcome::kPartial:
      error_ = "no whole answer from " + where() + " within " + std::to_string(timeout_ms) + " ms";
      return Outcome::kBadAnswer;
    case MbapOutcome::kBadFrame:  // the stream cannot be cut into frames any more
      error_ = "an answer with a bad MBAP header from " + where();
      close();
      return Outcome::kIoError;
    case MbapOutcome::kClosed:
      error_ = where() + ": closed by the gateway";
      return Outcome::kIoError;
    case MbapOutcome::kSendFailed:
      error_ = "cannot send to " + where() + ": " + std::strerror(errno);
      return Outcome::kIoError;
  }
  const modbus::ParseStatus st = modbus::parse_net_response(request, length, adu_, n, *out);
  if (st == modbus::ParseStatus::kOk || st == modbus::ParseStatus::kException) return Outcome::kAnswered;
  error_ = "no valid answer from " + where() + " (" + std::to_string(n) + " bytes)";
  return Outcome::kBadAnswer;
}

}  // namespace master
}  // namespace mb2co
