// The serial side of --via-modbus: one FC 2Bh/MEI 0Dh request to the
// gateway and its answer, one at a time (a Modbus/RTU line has one master
// and the gateway serves one remote transfer at a time). libmodbus (3.1)
// opens and configures the line and sends the request
// (modbus_send_raw_request); it cannot receive a 2Bh response (its receive
// derives the length from the function code), so the answer is read from
// its file descriptor here and checked with the shared codec
// (modbus/network_pdu.h: CRC, echoed fields).
#pragma once
#include <stdint.h>

#include <string>
#include <utility>

#include "host/status.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "modbus/parity.h"

typedef struct _modbus modbus_t;

namespace mb2co {
namespace master {

/// One request/response exchange with the gateway. An interface so the
/// transfer logic can be tested against a scripted gateway.
class GatewayChannel {
 public:
  enum class Outcome : uint8_t {
    kAnswered,     ///< a normal response or an exception: see the NetResponse
    kNoAnswer,     ///< silence until the response timeout
    kBadAnswer,    ///< bytes that are no valid answer to the request (CRC, echo, length)
    kInterrupted,  ///< SIGINT/SIGTERM during the wait
    kIoError,      ///< the device went away (end of file, write refused)
  };
  /// What one exchange came to. `status` fails, with the line that says
  /// why, for kNoAnswer, kBadAnswer and kIoError; it is ok for kAnswered
  /// and kInterrupted (an interrupt is the user's, not the link's).
  struct Exchange {
    Outcome outcome = Outcome::kAnswered;
    Status status;

    static Exchange answered() { return Exchange{}; }
    static Exchange interrupted() { return Exchange{Outcome::kInterrupted, Status::ok()}; }
    static Exchange failed(Outcome o, std::string why) {
      return Exchange{o, Status::failure(std::move(why))};
    }
  };
  /// Sends the request ADU (CRC included, as build_net_request makes it)
  /// and waits up to `timeout_ms` for its answer, decoded into `out` (its
  /// data points into the channel's buffer: valid until the next exchange).
  /// kAnswered with ParseStatus kOk or kException only.
  virtual Exchange exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                            modbus::NetResponse* out) = 0;
  /// "slave 1 on /dev/ttyACM0", for error lines.
  virtual std::string where() const = 0;

 protected:
  ~GatewayChannel() = default;
};

/// The channel on a serial device (or a pty) through libmodbus. Not copyable.
class GatewayLink : public GatewayChannel {
 public:
  GatewayLink() = default;
  ~GatewayLink() { close(); }
  GatewayLink(const GatewayLink&) = delete;
  GatewayLink& operator=(const GatewayLink&) = delete;

  /// Opens `path` at `baud`, 8 data bits, `parity` and one stop bit, for
  /// slave `slave` (1..247).
  Status open(const std::string& path, uint32_t baud, uint8_t slave,
              modbus::Parity parity = modbus::Parity::kNone);
  void close();
  uint8_t slave() const { return slave_; }

  Exchange exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                    modbus::NetResponse* out) override;
  std::string where() const override;

 private:
  /// After a frame that already parses, how long to wait for more bytes
  /// that would make it longer (a plain exception 04 and the first five
  /// bytes of an abort response both end in a valid CRC): t3.5 of the line
  /// plus scheduling slack.
  uint32_t settle_ms() const;

  modbus_t* ctx_ = nullptr;
  std::string path_;
  uint32_t baud_ = 115200;
  uint8_t slave_ = 1;
  uint8_t response_[modbus::kMaxAduBytes + 8];
};

}  // namespace master
}  // namespace mb2co
