// What an SDO command queues its transfers on, whatever carries them: the
// SocketCAN network of SDO clients (can_transport.h) or a Modbus gateway
// that runs them on its own CAN line (gateway_network.h). The commands see
// only this, so their output is the same either way.
#pragma once
#include <stdint.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "canopen/sdo_abort.h"
#include "canopen/sdo_client.h"
#include "host/status.h"

namespace mb2co {
namespace master {

/// The most bytes an upload takes unless told otherwise (Transfer::
/// max_bytes): a value for a terminal, a DCF or a poll, 64 KiB. `upload`
/// raises it with --max-bytes; its data go to a file as they come.
static const uint32_t kValueMaxBytes = 65536;

/// One SDO transfer and, once done(), how it ended. Owned by the caller;
/// must stay put (not move) while queued or running.
struct Transfer {
  uint8_t node = 0;
  uint16_t index = 0;
  uint8_t sub = 0;
  bool upload = true;
  canopen::SdoMode mode = canopen::kSdoAuto;
  std::vector<uint8_t> data;  ///< download: the bytes to write; upload: what came (unless `write`)
  /// Upload: the most bytes taken. A larger size indicated by the node is
  /// refused at once, a transfer without one is stopped at the first byte
  /// beyond: 05040005h (out of memory) sent, either way.
  uint32_t max_bytes = kValueMaxBytes;
  /// Upload: where the bytes go as they come (a file), in order, instead of
  /// into `data`. A code other than kSdoOk ends the transfer with it (sent).
  std::function<canopen::SdoAbort(const uint8_t* bytes, size_t n)> write;
  /// Called when it ended (may queue more transfers for the same node).
  std::function<void(Transfer&)> on_done;
  /// 0: starts when its turn comes. Else not before this time of the
  /// network's clock (the started_us/ended_us clock): a poll's pause, e.g.
  /// `ended_us + 100000` from the on_done of the previous transfer. The
  /// node's later transfers wait behind it.
  uint32_t not_before_us = 0;
  /// SDO client timeout of this transfer in µs; 0: the network's (-t).
  /// A gateway applies its own.
  uint32_t timeout_us = 0;
  /// A probe of a node id that may have no node (scan): a timeout ends it
  /// without the abort frame (SdoClient::set_timeout_abort_sent). A
  /// gateway's SDO client decides that itself.
  bool probe = false;

  bool finished = false;
  canopen::SdoAbort result = canopen::kSdoOk;
  bool by_server = false;  ///< result is the server's abort code
  bool node_lost = false;  ///< ended by the watchdog (heartbeat lost)
  bool crc = false;        ///< a block transfer with CRC
  /// It timed out once while the node's heartbeat said it serves SDO, and
  /// was started over 7 ms later (SdoNetwork, which then sets
  /// not_before_us; a gateway's client decides for itself).
  bool asked_again = false;
  /// Through a gateway: why the gateway itself refused the request (an
  /// exception other than an SDO abort), "" otherwise; `link_down`: the
  /// gateway did not answer at all (or not usably).
  std::string gateway_error;
  bool link_down = false;
  bool started = false;
  /// When it started and ended, on one clock that never goes back (a bus
  /// loop's ServiceClock, or the monotonic clock through a gateway).
  uint32_t started_us = 0;
  uint32_t ended_us = 0;
  /// Bytes moved once finished: uploaded, or downloaded and acknowledged.
  uint32_t bytes = 0;
  bool ok() const { return finished && result == canopen::kSdoOk; }
  /// From start to end (wrapping µs: right up to ~71 min).
  uint32_t elapsed_us() const { return ended_us - started_us; }
  /// "node 3 1018h/1: SDO abort 06020000h (object does not exist ...)" or "".
  std::string failure() const;
};

/// Redrawn while transfers run: called with the time at least every
/// next_us() (a progress bar); not owned by the network.
class ProgressHook {
 public:
  virtual void update(uint32_t now_us) = 0;
  virtual uint32_t next_us() const = 0;

 protected:
  ~ProgressHook() = default;
};

class TransferNetwork {
 public:
  virtual ~TransferNetwork() = default;
  /// Queues `t` behind the node's other transfers.
  virtual void queue(Transfer* t) = 0;
  /// Transfers not finished yet.
  virtual size_t pending() const = 0;
  /// Progress of the node's running transfer (bytes moved, size; size 0
  /// when unknown or idle).
  virtual void progress(uint8_t node, uint32_t* moved, uint32_t* size) const = 0;
  /// Ends the node's queued transfers that have not started with `code`,
  /// without calling their on_done (a running one runs on).
  virtual void drop_queued(uint8_t node, canopen::SdoAbort code) = 0;
  /// Ends every transfer with `code` without calling on_done; a running one
  /// is aborted where it runs (may be called from an on_done).
  virtual void abort_all(canopen::SdoAbort code) = 0;
  /// Ends `t` alone with `code` without calling its on_done: taken off its
  /// node's queue, or aborted where it runs (`code` sent) and the node's
  /// next transfer started. False when the network cannot (a gateway: the
  /// transfer then runs to its end) or `t` is not queued here.
  virtual bool cancel(Transfer* t, canopen::SdoAbort code) {
    (void)t;
    (void)code;
    return false;
  }
  /// Runs until nothing is pending; false when SIGINT/SIGTERM ended it
  /// first (the caller aborts what is left). `progress` may be null.
  virtual bool run(ProgressHook* progress) = 0;
  /// Fails when the way to the nodes broke (a gateway that stopped
  /// answering): then every transfer ended with Transfer::link_down.
  virtual Status link_status() const { return Status::ok(); }
};

}  // namespace master
}  // namespace mb2co
