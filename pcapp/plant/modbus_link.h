// The Modbus master: owns a libmodbus context on one serial device (RTU) or
// one Modbus/TCP connection (--tcp, to mb2co-node --tcp) and runs the
// cycle's transactions (transaction_plan.h) with a response
// timeout and retries. Calls block for at most (retries + 1) x timeout
// (identify(): one timeout more, listening for a late answer after silence).
// Before every attempt it drops what waits on the port: a late answer to an
// abandoned attempt must not be taken for the next one's.
//
// Where it runs: in the cycle timer's slot, on the GUI-less main thread,
// not in a worker QThread. The controller cannot step before the read
// returns and the write carries the step's result, so the transaction is
// the cycle's critical path either way; a worker thread would only add a
// hand-over per cycle and a second owner of the plant state. The event loop
// has nothing time-critical to do meanwhile (signals wait in the self-pipe,
// the status line is drawn after the cycle), and the block is bounded: a
// healthy exchange takes the frame times (~6-10 ms at 115200 baud), a dead
// link at most (retries + 1) x timeout, after which the link is declared lost
// and the port closed (no blocking call at all while it is down).
// On a pty: no RS-485 mode, no RTS control (DESIGN §10).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"
#include "host/tcp_address.h"
#include "modbus/parity.h"
#include "station_io.h"
#include "status_view.h"
#include "transaction_plan.h"

typedef struct _modbus modbus_t;

namespace mb2co {
namespace pcapp {

struct LinkSettings {
  std::string path;
  /// Modbus/TCP instead of `path` (then baud and parity are unused and
  /// `slave` is the unit id).
  bool on_tcp = false;
  TcpAddress tcp;
  int baud = 115200;
  modbus::Parity parity = modbus::Parity::kNone;
  int slave = 1;        ///< Modbus address 1..247
  int timeout_ms = 25;  ///< response timeout (and inter-byte timeout)
  int retries = 2;      ///< extra attempts after a timeout / CRC error

  /// "/dev/ttyACM0" or "tcp:127.0.0.1:1502", for messages.
  std::string where() const { return on_tcp ? "tcp:" + tcp.text() : path; }
};

enum class LinkStatus : uint8_t {
  kOk,
  kException,  ///< the slave answered with an exception (the link is fine)
  kFailed,     ///< no valid answer after every retry: the link is lost
};

/// What a transaction came to: the outcome, and unless it is ok why, in
/// `status` (one line).
struct LinkResult {
  LinkStatus outcome = LinkStatus::kOk;
  Status status;
  /// failed, but bytes came back (a late, corrupt or foreign answer): a slave
  /// is there, the exchange with it was disturbed. false: silence.
  bool heard = false;

  bool ok() const { return outcome == LinkStatus::kOk; }
  static LinkResult done() { return LinkResult(); }
  static LinkResult failure(LinkStatus outcome, std::string why, bool heard = false) {
    return LinkResult{outcome, Status::failure(std::move(why)), heard};
  }
};

/// Not copyable; one context, one open device at a time.
class ModbusLink {
 public:
  ModbusLink() = default;
  ~ModbusLink() { close(); }
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  /// Opens and configures the device.
  Status open(const LinkSettings& settings);
  void close();
  bool is_open() const { return ctx_ != nullptr; }
  const LinkSettings& settings() const { return settings_; }

  /// Checks that an mb2co gateway answers: FC 2B/0E basic device
  /// identification (vendor "mb2co"); a slave without FC 2B (exception 01) is
  /// accepted when it echoes FC 08/00. `identity`: "vendor product revision".
  /// exception: the answer is definitely not from an mb2co gateway (another
  /// vendor, or neither FC 2B nor FC 08); failed: no valid answer in time.
  LinkResult identify(std::string& identity);

  /// The plan's reads into `in` (FC 03/04), or with plan.read_write one
  /// FC 17h that writes `out`'s write block first.
  LinkResult read(const TransactionPlan& plan, const RegisterImage& out, RegisterImage& in);
  /// The plan's write blocks from `out` (FC 06 / FC 10h), also for a
  /// read_write plan (used at shutdown).
  LinkResult write(const TransactionPlan& plan, const RegisterImage& out);

  /// The gateway's view of the CANopen network (FC 2Bh/MEI 0Dh): every node
  /// it hears, with NMT state and heartbeat age, in node id order. An
  /// exception comes back as LinkStatus::kException; `unsupported` tells
  /// exception 01 (a gateway without the service, or with it switched off).
  LinkResult network_view(std::vector<modbus::NetViewEntry>& view, bool& unsupported);

  /// An entry of up to 32 bits of node `node_id` (the gateway's own id: its
  /// own OD) by FC 2Bh/MEI 0Dh SDO upload (CiA 309-2), little-endian as SDO
  /// carries it. An SDO abort comes back as LinkStatus::kException with
  /// `abort_code` set (0: a plain exception).
  LinkResult upload(uint8_t node_id, uint16_t index, uint8_t sub, uint32_t& value, uint32_t& abort_code);
  /// One holding register (FC 03).
  LinkResult holding_register(uint16_t address, uint16_t& value);

  /// Attempts that timed out or were corrupt and were repeated (only grows).
  uint64_t retries_used() const { return retries_used_; }
  /// Bytes that were waiting before a request was sent and were dropped:
  /// late answers to abandoned attempts (only grows).
  uint64_t stale_bytes_dropped() const { return stale_bytes_dropped_; }

 private:
  template <class F>
  LinkResult attempt(const char* what, F request);
  /// One raw request/response on the device (for FC 2B and 08, which
  /// libmodbus 3.1 cannot receive); response parsed by the shared codec.
  /// The answer is the first frame in what arrives that answers `request`:
  /// a late answer to an earlier attempt read before or together with it is
  /// skipped. On success it is response[0, got).
  LinkResult raw(const uint8_t* request, uint16_t length, uint8_t* response, uint16_t capacity,
                 uint16_t& got);
  /// raw() on Modbus/TCP (platform/mbap_client.h): the answer with this
  /// request's transaction id, as an RTU ADU for the same codec.
  LinkResult raw_tcp(const uint8_t* request, uint16_t length, uint8_t* response, uint16_t& got);
  /// Reads and drops whatever waits on the device (no waiting): before every
  /// request, so that a late answer to an abandoned attempt is not taken for
  /// the next one's. The number of bytes dropped.
  size_t drop_pending();
  /// Waits up to `wait_ms` for bytes and drops them: whether any came.
  bool late_answer_within(int wait_ms);

  modbus_t* ctx_ = nullptr;
  LinkSettings settings_;
  uint64_t retries_used_ = 0;
  uint64_t stale_bytes_dropped_ = 0;
  uint16_t transaction_ = 0;  ///< raw_tcp's last transaction id
};

}  // namespace pcapp
}  // namespace mb2co
