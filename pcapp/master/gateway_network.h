// SDO transfers through a Modbus gateway (FC 2Bh / MEI 0Dh, the "CANopen
// General Reference"; layout in docs/gateway-network.md): the gateway's own
// SDO client talks to the node, we only see its answers. One request at a
// time, one transfer at a time, the nodes' queues served in turn. An object
// longer than one Modbus frame goes in successive requests: uploads as
// windows at a growing starting address, downloads as parts with "more
// follows" set on all but the last.
//
// What the answers mean:
//   normal response            → data (upload) or done (download)
//   exception 04 + abort code  → the SDO abort, printed as over SocketCAN;
//                                05040000h is the gateway's SDO timeout
//                                (the node is silent), as our own client's
//   exception 06 (busy)        → asked again until the response timeout
//   exception 01 / silence / garbage → the gateway is unusable: every
//                                transfer ends (link_status() says why)
//   other exceptions (02, 03)  → this transfer is refused by the gateway
#pragma once
#include <stdint.h>

#include <deque>
#include <string>

#include "gateway_link.h"
#include "transfer_network.h"

namespace mb2co {
namespace master {

/// NMT `command` to `node` (0: all) through the gateway at `slave`: the
/// gateway sends the frame on its line and confirms. Fails with one line
/// when it does not answer or refuses.
Status gateway_nmt(GatewayChannel& channel, uint8_t slave, uint32_t timeout_ms, uint8_t command,
                   uint8_t node);

class GatewayNetwork : public TransferNetwork {
 public:
  /// `channel` outlives the network; `slave`: the gateway's Modbus address;
  /// `response_timeout_ms`: how long one request may wait for its answer
  /// (above the gateway's own bound for a remote transfer).
  GatewayNetwork(GatewayChannel& channel, uint8_t slave, uint32_t response_timeout_ms);

  void queue(Transfer* t) override;
  size_t pending() const override { return pending_; }
  void progress(uint8_t node, uint32_t* moved, uint32_t* size) const override;
  void drop_queued(uint8_t node, canopen::SdoAbort code) override;
  void abort_all(canopen::SdoAbort code) override;
  bool run(ProgressHook* progress) override;
  Status link_status() const override { return link_; }

 private:
  enum class Step : uint8_t { kDone, kFailed, kInterrupted };
  /// One request and its answer, exception 06 asked again; kDone with a
  /// normal response in `r`, kFailed with `t` ended.
  Step ask(Transfer* t, const uint8_t* request, uint16_t length, modbus::NetResponse* r);
  /// The whole of `t`, every window or part.
  Step upload(Transfer* t);
  Step download(Transfer* t);
  /// Ends `t` (not on its queue any more) and calls its on_done.
  void finish(Transfer* t, canopen::SdoAbort result, bool by_server);
  /// Ends `t` refused by the gateway itself (`why`).
  void refuse(Transfer* t, const std::string& why);
  /// The gateway is unusable: `t` and every queued transfer end with `why`.
  void link_down(Transfer* t, const std::string& why);
  void tick(ProgressHook* progress);
  uint32_t now_us() const;

  GatewayChannel& channel_;
  uint8_t slave_;
  uint32_t response_timeout_ms_;
  std::deque<Transfer*> queues_[128];
  size_t pending_ = 0;
  uint8_t last_node_ = 0;          ///< served last: the turn goes on from here
  Transfer* running_ = nullptr;    ///< off its queue while it runs
  uint32_t moved_ = 0, size_ = 0;  ///< of the running transfer
  ProgressHook* progress_ = nullptr;
  Status link_;
};

}  // namespace master
}  // namespace mb2co
