// What `serve` asks of the network, whatever carries it: SDO transfers and
// NMT commands, each answered later through its callback, each cancellable
// (a client that went away). The SocketCAN backend runs every node's queue
// at once on the bus loop (serve_can_backend.h); through a gateway one
// request at a time on a thread of its own (serve_thread_backend.h).
#pragma once
#include <stdint.h>

#include <functional>
#include <string>
#include <vector>

namespace mb2co {
namespace master {

struct SdoJob {
  uint8_t node = 0;
  uint16_t index = 0;
  uint8_t sub = 0;
  bool upload = true;
  std::vector<uint8_t> data;  ///< download: the bytes
  uint32_t timeout_ms = 0;    ///< SDO client timeout of this transfer
  bool block = false;         ///< CiA 301 block transfer
};

struct SdoOutcome {
  bool ok = false;
  uint32_t abort_code = 0;    ///< when not ok and no gateway_error
  std::string gateway_error;  ///< the gateway refused or is unreachable (not an SDO abort)
  std::vector<uint8_t> data;  ///< upload: the bytes
};

class ServeBackend {
 public:
  using Ticket = uint64_t;
  using SdoDone = std::function<void(const SdoOutcome&)>;
  /// "" when the frame went out (or the gateway confirmed), else why not.
  using NmtDone = std::function<void(const std::string& failure)>;

  virtual ~ServeBackend() = default;
  /// Queues a transfer behind the node's others. `done` is called exactly
  /// once, later, from the loop (never inside this call), unless the
  /// ticket is cancelled first.
  virtual Ticket sdo(SdoJob job, SdoDone done) = 0;
  /// An NMT command to `node` (0: all); `done` as for sdo().
  virtual Ticket nmt(uint8_t command, uint8_t node, NmtDone done) = 0;
  /// The ticket's callback is never called. A transfer still queued is
  /// dropped; one running is aborted on the bus where the backend can
  /// (08000020h: the data cannot go to the application), else it runs to
  /// its end unseen.
  virtual void cancel(Ticket ticket) = 0;
  /// Whether `set sdo_block` and `set sdo_timeout` can be honoured.
  virtual bool block_transfer() const = 0;
  virtual bool sdo_timeout() const = 0;
  /// "SocketCAN vcan0", "gateway /dev/ttyACM0:1", for `info`.
  virtual std::string describe() const = 0;
};

}  // namespace master
}  // namespace mb2co
