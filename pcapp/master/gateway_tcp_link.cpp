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

GatewayChannel::Exchange GatewayTcpLink::exchange(const uint8_t* request, uint16_t length,
                                                  uint32_t timeout_ms, modbus::NetResponse* out) {
  if (ctx_ == nullptr) return Exchange::failed(Outcome::kIoError, "the gateway's connection is not open");
  uint16_t n = 0;
  switch (mbap_exchange(modbus_get_socket(ctx_), request, length, ++transaction_, mbap_now_ms() + timeout_ms,
                        adu_, &n, &port::stop_requested)) {
    case MbapOutcome::kAnswer:
      break;
    case MbapOutcome::kInterrupted:
      return Exchange::interrupted();
    case MbapOutcome::kSilence:
      return Exchange::failed(Outcome::kNoAnswer,
                              "no answer from " + where() + " within " + std::to_string(timeout_ms) + " ms");
    case MbapOutcome::kPartial:
      return Exchange::failed(Outcome::kBadAnswer, "no whole answer from " + where() + " within " +
                                                       std::to_string(timeout_ms) + " ms");
    case MbapOutcome::kBadFrame: {  // the stream cannot be cut into frames any more
      Exchange failed =
          Exchange::failed(Outcome::kIoError, "an answer with a bad MBAP header from " + where());
      close();
      return failed;
    }
    case MbapOutcome::kClosed:
      return Exchange::failed(Outcome::kIoError, where() + ": closed by the gateway");
    case MbapOutcome::kSendFailed:
      return Exchange::failed(Outcome::kIoError, "cannot send to " + where() + ": " + std::strerror(errno));
  }
  const modbus::ParseStatus st = modbus::parse_net_response(request, length, adu_, n, *out);
  if (st == modbus::ParseStatus::kOk || st == modbus::ParseStatus::kException) return Exchange::answered();
  return Exchange::failed(Outcome::kBadAnswer,
                          "no valid answer from " + where() + " (" + std::to_string(n) + " bytes)");
}

}  // namespace master
}  // namespace mb2co
